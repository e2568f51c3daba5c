#pragma once
// A pool of worker threads that may solve LPs. Every pool of the library, the apps and the benches
// starts its threads here, so none can forget GLPK's per-thread environment (glpk_environment.hpp):
// five hand-written pools each had to remember it, and two did not (LeakSanitizer found them).

#include <algorithm>
#include <thread>
#include <vector>

#include "sets/numeric/glpk_environment.hpp"

namespace sets {

/// Runs worker() on max(1, threads) threads at once and returns when all have ended. Each thread
/// holds a GlpkThreadEnvironment around worker(), so the LPs worker() creates are gone before it
/// frees the thread's environment. worker() must not throw (catch inside it).
template <class Worker>
void run_worker_threads(int threads, const Worker& worker) {
  std::vector<std::thread> pool;
  for (int k = 0; k < std::max(1, threads); ++k)
    pool.emplace_back([&worker] {
      const GlpkThreadEnvironment glpk;  // freed when the worker ends
      worker();
    });
  for (auto& t : pool) t.join();
}

}  // namespace sets
