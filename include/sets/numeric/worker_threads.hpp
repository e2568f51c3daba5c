#pragma once
// A pool of worker threads that may solve LPs. Every pool of the library, the apps and the benches
// starts its threads here, so none can forget GLPK's per-thread environment (glpk_environment.hpp):
// five hand-written pools each had to remember it, and two did not (LeakSanitizer found them).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <optional>
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

/// A job of try_jobs that threw: its index and the exception.
struct JobFailure {
  std::size_t index;
  std::exception_ptr error;
};

/// Calls job(local, i) for i = 0 .. count-1 on run_worker_threads, indices handed out in order
/// from one counter. `local` is the worker's own state (e.g. a Simulator, never shared between
/// threads), made by make_local() before the worker's first job, inside the same try. After a job
/// throws no further index is handed out; the failure of the lowest index is returned (every lower
/// index was handed out before it, so it is the serial loop's first failure). Each job writes only
/// its own results, so they do not depend on the number of threads.
template <class MakeLocal, class Job>
std::optional<JobFailure> try_jobs_with(int threads, std::size_t count, const MakeLocal& make_local, const Job& job) {
  std::vector<std::exception_ptr> errors(count);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  run_worker_threads(threads, [&] {
    std::optional<decltype(make_local())> local;
    for (std::size_t i; !failed && (i = next++) < count;) {
      try {
        if (!local) local.emplace(make_local());
        job(*local, i);
      } catch (...) {
        errors[i] = std::current_exception();
        failed = true;
      }
    }
  });
  for (std::size_t i = 0; i < count; ++i)
    if (errors[i]) return JobFailure{i, errors[i]};
  return std::nullopt;
}

/// try_jobs_with without worker state: job(i).
template <class Job>
std::optional<JobFailure> try_jobs(int threads, std::size_t count, const Job& job) {
  return try_jobs_with(threads, count, [] { return 0; }, [&job](int, std::size_t i) { job(i); });
}

/// try_jobs_with, rethrowing the failure of the lowest index.
template <class MakeLocal, class Job>
void run_jobs_with(int threads, std::size_t count, const MakeLocal& make_local, const Job& job) {
  if (const auto failure = try_jobs_with(threads, count, make_local, job)) std::rethrow_exception(failure->error);
}

/// try_jobs, rethrowing the failure of the lowest index.
template <class Job>
void run_jobs(int threads, std::size_t count, const Job& job) {
  if (const auto failure = try_jobs(threads, count, job)) std::rethrow_exception(failure->error);
}

}  // namespace sets
