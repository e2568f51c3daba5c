// GlpkThreadEnvironment: a worker thread that solved LPs ends without a GLPK environment, and one
// that never touched GLPK gets none created. glp_free_env() returns 0 when it freed an environment
// of the calling thread and 1 when the thread had none: the probe below.

#include <gtest/gtest.h>

#include <glpk.h>

#include <thread>

#include "sets/numeric/glpk_environment.hpp"
#include "sets/numeric/linear_program.hpp"

namespace {

// min x0 + x1 s.t. x0 + 2 x1 >= 1, x in [0, 1]^2: optimum 0.5 at (0, 0.5).
double solve_small_lp() {
  sets::LinearProgram lp(2);
  lp.set_variable_bounds(0, 0, 1);
  lp.set_variable_bounds(1, 0, 1);
  lp.add_row(Eigen::Vector2d(1, 2), 1, sets::inf);
  lp.set_objective(Eigen::Vector2d(1, 1), sets::Sense::minimize);
  return lp.solve().objective;
}

// Runs `body` on a new thread, then asks GLPK on that same thread whether an environment is left.
template <class Body>
bool environment_left_after(Body body) {
  bool left = false;
  std::thread worker([&] {
    body();
    left = glp_free_env() == 0;  // frees it if it was left (no leak from the test itself)
  });
  worker.join();
  return left;
}

TEST(GlpkThreadEnvironment, WorkerThatSolvedLpsEndsWithoutEnvironment) {
  double objective = 0;
  EXPECT_FALSE(environment_left_after([&] {
    const sets::GlpkThreadEnvironment glpk;
    objective = solve_small_lp();
  }));
  EXPECT_DOUBLE_EQ(objective, 0.5);
}

TEST(GlpkThreadEnvironment, WithoutItTheEnvironmentStays) {
  // The probe can tell: the same work without the helper leaves GLPK's environment behind.
  EXPECT_TRUE(environment_left_after([] { solve_small_lp(); }));
}

TEST(GlpkThreadEnvironment, ThreadWithoutGlpkGetsNoEnvironment) {
  EXPECT_FALSE(environment_left_after([] { const sets::GlpkThreadEnvironment glpk; }));
}

TEST(GlpkThreadEnvironment, OtherThreadsKeepTheirEnvironment) {
  // GLPK's environment is thread-local: freeing a worker's leaves this thread's LPs usable.
  sets::LinearProgram kept(1);
  kept.set_variable_bounds(0, -1, 2);
  kept.set_objective_coordinate(0, sets::Sense::maximize);
  EXPECT_FALSE(environment_left_after([] {
    const sets::GlpkThreadEnvironment glpk;
    solve_small_lp();
  }));
  EXPECT_DOUBLE_EQ(kept.solve().objective, 2);
}

}  // namespace
