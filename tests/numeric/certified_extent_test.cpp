// The certified extent of an LP's set (src/numeric/certified_extent.cpp): what it answers when
// the floating-point solver is wrong.

#include <gtest/gtest.h>

#include <cmath>

#include "numeric/certified_extent.hpp"

namespace {

using sets::inf;
using sets::LinearProgram;
using sets::LpSolution;
using sets::LpStatus;

// The set 1 <= x0 <= 2, -1 <= x1 <= 3 as rows of an LP with free variables.
LinearProgram box_lp() {
  LinearProgram lp(2);
  lp.add_row(Eigen::Vector2d(1, 0), 1, 2);
  lp.add_row(Eigen::Vector2d(0, 1), -1, 3);
  return lp;
}

}  // namespace

TEST(CertifiedExtent, CertifiesTheExtentOfABox) {
  LinearProgram lp = box_lp();
  const auto e = sets::detail::certified_extent(lp, [&](int& lps) { ++lps; return lp.solve(); }, {}, true);
  ASSERT_EQ(e.status, sets::detail::ExtentStatus::feasible);
  ASSERT_TRUE(e.certified);
  EXPECT_LE(e.lo[0], 1.0);
  EXPECT_GE(e.hi[0], 2.0);
  EXPECT_LE(e.lo[1], -1.0);
  EXPECT_GE(e.hi[1], 3.0);
  EXPECT_NEAR(e.hi[1], 3.0, 1e-9);
}

TEST(CertifiedExtent, ASolverStoppedAtAWrongVertexGivesTheOwnBoundsNotItsPoint) {
  // A solver that reports the point (1.5, 1) as the optimum of every objective (as GLPK did on
  // badly scaled regressions: any vertex "optimal" once the duals fall under its tolerance),
  // with zero multipliers, and fails once the box is put on. Nothing can be certified; the
  // extent must then be the set's own (infinite) bounds, not the width-0 intervals at 1.5, 1
  // that miss almost all of the set. The floating-point answer stays apart, as an estimate.
  LinearProgram lp = box_lp();
  int calls = 0;
  const auto lying = [&](int& lps) {
    ++lps;
    LpSolution s;
    s.sense = lp.sense();
    if (calls++ >= 4) {
      s.status = LpStatus::unbounded;
      return s;
    }
    s.status = LpStatus::optimal;
    s.x = Eigen::Vector2d(1.5, 1);
    s.objective = lp.objective().dot(s.x);
    s.row_dual = Eigen::VectorXd::Zero(lp.num_rows());
    s.reduced_cost = lp.objective();
    return s;
  };
  const auto e = sets::detail::certified_extent(lp, lying, {Eigen::Vector2d(1, 1)}, true);
  ASSERT_EQ(e.status, sets::detail::ExtentStatus::feasible);
  EXPECT_FALSE(e.certified);
  for (int j = 0; j < 2; ++j) {
    EXPECT_EQ(e.lo[j], -inf) << j;
    EXPECT_EQ(e.hi[j], inf) << j;
  }
  EXPECT_EQ(e.float_lo[0], 1.5);
  EXPECT_EQ(e.float_hi[1], 1.0);
  ASSERT_EQ(e.maxima.size(), 1u);
  EXPECT_EQ(e.maxima[0], inf);
}
