// A GLPK internal error becomes a NumericalError on the calling thread (without the hook GLPK
// calls abort()), and the thread's LinearPrograms keep working afterwards.

#include <gtest/gtest.h>

#include <glpk.h>

#include <string>
#include <thread>

#include "sets/core/error.hpp"
#include "sets/numeric/glpk_environment.hpp"
#include "sets/numeric/glpk_error.hpp"
#include "sets/numeric/linear_program.hpp"

namespace {

// Provokes an internal error: a row index GLPK checks and rejects (xerror, then abort()).
void bad_glpk_call() {
  sets::call_glpk("test", [] {
    glp_prob* p = glp_create_prob();
    glp_set_row_bnds(p, 7, GLP_FX, 1.0, 1.0);  // the problem has no rows
  });
}

// max x s.t. x + y <= 3, x - y <= 1, y in [0, 5]: optimum 2 at (2, 1).
sets::LinearProgram small_lp() {
  sets::LinearProgram lp(2);
  lp.set_variable_bounds(1, 0, 5);
  lp.add_row(Eigen::Vector2d(1, 1), -sets::inf, 3);
  lp.add_row(Eigen::Vector2d(1, -1), -sets::inf, 1);
  lp.set_objective_coordinate(0, sets::Sense::maximize);
  return lp;
}

}  // namespace

TEST(GlpkError, InternalErrorBecomesNumericalErrorWithGlpksMessage) {
  const unsigned long before = sets::glpk_environment_generation();
  try {
    bad_glpk_call();
    FAIL() << "no exception";
  } catch (const sets::NumericalError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("GLPK internal error"), std::string::npos) << what;
    EXPECT_NE(what.find("glp_set_row_bnds"), std::string::npos) << what;
  }
  EXPECT_EQ(sets::glpk_environment_generation(), before + 1);
}

TEST(GlpkError, ProblemsOfTheThreadSurviveTheError) {
  sets::LinearProgram kept = small_lp();
  ASSERT_NEAR(kept.solve().objective, 2.0, 1e-12);
  const sets::LpBasis before = kept.basis();
  EXPECT_THROW(bad_glpk_call(), sets::NumericalError);
  // Its GLPK copy was freed with the environment: rebuilt from the stored data, same answer.
  const sets::LpSolution s = kept.solve();
  ASSERT_EQ(s.status, sets::LpStatus::optimal);
  EXPECT_NEAR(s.objective, 2.0, 1e-12);
  kept.set_basis(before);  // a basis of the lost copy still fits the rebuilt one
  EXPECT_NEAR(kept.solve().objective, 2.0, 1e-12);
  kept.add_row(Eigen::Vector2d(1, 0), -sets::inf, 1.5);
  EXPECT_NEAR(kept.solve().objective, 1.5, 1e-12);
  EXPECT_NEAR(small_lp().solve().objective, 2.0, 1e-12);  // and new problems work
}

TEST(GlpkError, OnAWorkerThreadTheExceptionReachesThatThread) {
  std::string caught;
  double after = 0;
  std::thread worker([&] {
    const sets::GlpkThreadEnvironment glpk;
    try {
      bad_glpk_call();
    } catch (const sets::NumericalError& e) {
      caught = e.what();
    }
    after = small_lp().solve().objective;
  });
  worker.join();
  EXPECT_NE(caught.find("GLPK internal error"), std::string::npos);
  EXPECT_NEAR(after, 2.0, 1e-12);
}

TEST(LinearProgram, RejectsParametersGlpkWouldMisread) {
  sets::LinearProgram lp(2);
  EXPECT_THROW(lp.add_row(Eigen::Vector2d(1, 1e200), 0, 1), sets::InputError);
  EXPECT_THROW(lp.add_row(Eigen::Vector2d(1, 1e-200), 0, 1), sets::InputError);
  EXPECT_THROW(lp.add_row(Eigen::Vector2d(1, 1), 0, 1e200), sets::InputError);
  EXPECT_THROW(lp.set_variable_bounds(0, NAN, 1), sets::InputError);
  EXPECT_THROW(lp.set_objective(Eigen::Vector2d(1, NAN), sets::Sense::minimize), sets::InputError);
  EXPECT_NO_THROW(lp.add_row(Eigen::Vector2d(1e10, 1e-10), -1, 1));  // badly scaled but fine
  lp.set_integer(0);
  sets::MilpOptions o;
  for (double t : {0.0, -1.0, double(NAN)}) {
    o.time_limit_s = t;
    EXPECT_THROW(lp.solve_milp(o), sets::InputError) << t;
  }
  o.time_limit_s = sets::inf;  // no limit
  o.relative_gap = NAN;
  EXPECT_THROW(lp.solve_milp(o), sets::InputError);
  o.relative_gap = 1e-6;
  o.node_limit = -1;
  EXPECT_THROW(lp.solve_milp(o), sets::InputError);
  o.node_limit = 0;
  EXPECT_NO_THROW(lp.solve_milp(o));
}
