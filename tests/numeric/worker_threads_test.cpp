// run_worker_threads: max(1, threads) threads, each running the worker once, none of them the
// caller's, and none left holding a GLPK environment after solving LPs. try_jobs / run_jobs:
// every index once, the serial loop's first failure, worker state made at most once per worker.

#include <gtest/gtest.h>

#include <glpk.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <vector>
#include <thread>

#include "sets/numeric/linear_program.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace {

// min x0 + x1 s.t. x0 + 2 x1 >= 1, x in [0, 1]^2: optimum 0.5.
double solve_small_lp() {
  sets::LinearProgram lp(2);
  lp.set_variable_bounds(0, 0, 1);
  lp.set_variable_bounds(1, 0, 1);
  lp.add_row(Eigen::Vector2d(1, 2), 1, sets::inf);
  lp.set_objective(Eigen::Vector2d(1, 1), sets::Sense::minimize);
  return lp.solve().objective;
}

std::atomic<int> environments_left{0};

// Destroyed when its thread exits, i.e. after the pool's GlpkThreadEnvironment: asks GLPK whether
// the thread still has an environment (glp_free_env returns 0 when it freed one).
struct ExitProbe {
  ~ExitProbe() {
    if (glp_free_env() == 0) ++environments_left;
  }
};
thread_local ExitProbe exit_probe;

}  // namespace

TEST(RunWorkerThreads, EachThreadRunsTheWorkerOnceSolvesLpsAndEndsWithoutEnvironment) {
  for (const int threads : {0, 1, 3}) {
    environments_left = 0;
    std::atomic<int> calls{0}, right_answers{0};
    std::mutex mu;
    std::set<std::thread::id> ids;
    sets::run_worker_threads(threads, [&] {
      (void)&exit_probe;  // odr-use: constructs this thread's probe
      ++calls;
      if (solve_small_lp() == 0.5) ++right_answers;
      const std::lock_guard<std::mutex> lock(mu);
      ids.insert(std::this_thread::get_id());
    });
    const int expected = std::max(1, threads);
    EXPECT_EQ(calls, expected) << threads;
    EXPECT_EQ(right_answers, expected) << threads;
    EXPECT_EQ(static_cast<int>(ids.size()), expected) << threads;
    EXPECT_EQ(ids.count(std::this_thread::get_id()), 0u) << threads;
    EXPECT_EQ(environments_left, 0) << threads;
  }
}

TEST(TryJobs, EveryIndexOnceWhateverTheThreadCount) {
  for (int threads : {1, 2, 5}) {
    std::vector<int> hits(37, 0);
    const auto failure = sets::try_jobs(threads, hits.size(), [&](std::size_t i) { hits[i] += 1; });
    EXPECT_FALSE(failure) << threads;
    for (int h : hits) EXPECT_EQ(h, 1) << threads;
  }
}

TEST(TryJobs, ReturnsTheLowestFailingIndexAndRunJobsRethrowsIt) {
  for (int threads : {1, 2, 4}) {
    const auto job = [](std::size_t i) {
      if (i == 7 || i == 3 || i == 20) throw std::runtime_error("job " + std::to_string(i));
    };
    const auto failure = sets::try_jobs(threads, 30, job);
    ASSERT_TRUE(failure) << threads;
    EXPECT_EQ(failure->index, 3u) << threads;
    try {
      sets::run_jobs(threads, 30, job);
      ADD_FAILURE() << "run_jobs did not rethrow";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "job 3");
    }
  }
}

TEST(TryJobs, WorkerStateIsMadeAtMostOncePerWorkerAndAFailureToMakeItIsTheJobs) {
  std::atomic<int> made{0};
  std::vector<int> owner(50, -1);
  const auto failure = sets::try_jobs_with(
      3, owner.size(), [&] { return made++; }, [&](int worker, std::size_t i) { owner[i] = worker; });
  EXPECT_FALSE(failure);
  EXPECT_GE(made.load(), 1);
  EXPECT_LE(made.load(), 3);
  for (int w : owner) EXPECT_TRUE(w >= 0 && w < made.load());
  const auto broken = sets::try_jobs_with(
      2, 5, []() -> int { throw std::runtime_error("no state"); }, [](int, std::size_t) {});
  ASSERT_TRUE(broken);
  EXPECT_EQ(broken->index, 0u);
}
