#pragma once
// Independent runs on worker threads. Each run must depend only on its index (its own random
// generator seeded from it), so the results do not depend on the number of threads. Every run
// builds its own LPs on its own thread (GLPK: one problem per thread).

#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <optional>
#include <vector>

#include "sets/numeric/worker_threads.hpp"

namespace sets::app {

struct RunFailure {
  std::size_t run;
  std::exception_ptr error;
};

/// Calls run(k) for k = 0 .. count-1 on `threads` threads (at least one). The runs still pending
/// after a failure are skipped; the failure of the lowest run index is returned, if any.
inline std::optional<RunFailure> run_parallel(std::size_t count, unsigned threads,
                                              const std::function<void(std::size_t)>& run) {
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(count);
  std::atomic<bool> failed{false};
  run_worker_threads(static_cast<int>(std::max(1u, threads)), [&] {
    for (std::size_t k; !failed && (k = next++) < count;) {
      try {
        run(k);
      } catch (...) {
        errors[k] = std::current_exception();
        failed = true;
      }
    }
  });
  for (std::size_t k = 0; k < count; ++k)
    if (errors[k]) return RunFailure{k, errors[k]};
  return std::nullopt;
}

}  // namespace sets::app
