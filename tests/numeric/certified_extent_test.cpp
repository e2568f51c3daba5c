// Certified extent of a convex set given as an LP (src/numeric/certified_extent.cpp): the certified
// coordinate bounds and direction maxima contain every point of the set (sampled points, checked
// in exact rationals), are tight to LP accuracy, and the set is called empty only with a
// certificate; and what it answers when the floating-point solver is wrong.

#include "numeric/certified_extent.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <gmpxx.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "sets/numeric/linear_program.hpp"
#include "support/random_matrices.hpp"

using sets::detail::certified_extent;
using sets::detail::Extent;
using sets::detail::ExtentStatus;

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

namespace {

LinearProgram polytope_lp(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  LinearProgram lp(static_cast<int>(A.cols()));
  lp.add_rows(A, Eigen::VectorXd::Constant(b.size(), -inf), b);
  return lp;
}

Extent extent_of(LinearProgram& lp, const std::vector<Eigen::VectorXd>& directions) {
  return certified_extent(
      lp,
      [&lp](int& lps) {
        ++lps;
        return lp.solve();
      },
      directions, true);
}

mpq_class exact_dot(const Eigen::VectorXd& a, const Eigen::VectorXd& x) {
  mpq_class s = 0;
  for (Eigen::Index j = 0; j < a.size(); ++j) s += mpq_class(a[j]) * mpq_class(x[j]);
  return s;
}

// x satisfies A x <= b exactly (in rationals).
bool exactly_inside(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    if (exact_dot(A.row(i).transpose(), x) > mpq_class(b[i])) return false;
  return true;
}

}  // namespace

TEST(CertifiedExtent, TriangleExtentAndDiagonalMaximumAreTheExactOnesWithinLpAccuracy) {
  // x >= 0, y >= 0, x + y <= 1: extent [0, 1] x [0, 1], max of x + y is 1, of x - y is 1.
  Eigen::MatrixXd A(3, 2);
  A << -1, 0, 0, -1, 1, 1;
  LinearProgram lp = polytope_lp(A, Eigen::Vector3d(0, 0, 1));
  const Extent e = extent_of(lp, {Eigen::Vector2d(1, 1), Eigen::Vector2d(1, -1)});
  ASSERT_EQ(e.status, ExtentStatus::feasible);
  ASSERT_TRUE(e.certified);
  for (int j = 0; j < 2; ++j) {
    EXPECT_LE(e.lo[j], 0.0);
    EXPECT_GE(e.lo[j], -1e-9);
    EXPECT_GE(e.hi[j], 1.0);
    EXPECT_LE(e.hi[j], 1.0 + 1e-9);
    // The attaining points lie in the triangle (to LP tolerance) and attain the ends.
    EXPECT_NEAR(e.lower_points(j, j), 0.0, 1e-9);
    EXPECT_NEAR(e.upper_points(j, j), 1.0, 1e-9);
  }
  ASSERT_EQ(e.maxima.size(), 2u);
  EXPECT_GE(e.maxima[0], 1.0);
  EXPECT_LE(e.maxima[0], 1.0 + 1e-9);
  EXPECT_GE(e.maxima[1], 1.0);
  EXPECT_LE(e.maxima[1], 1.0 + 1e-9);
  EXPECT_GT(e.lps, 0);
}

TEST(CertifiedExtent, ContradictoryRowsAreCertifiedEmpty) {
  // x <= 0 and -x <= -1.
  Eigen::MatrixXd A(2, 1);
  A << 1, -1;
  LinearProgram lp = polytope_lp(A, Eigen::Vector2d(0, -1));
  EXPECT_EQ(extent_of(lp, {}).status, ExtentStatus::empty);
}

TEST(CertifiedExtent, UnboundedCoordinatesAreInfiniteAndBoundedOnesStillHold) {
  // The half-plane y <= 1: x is free, y has no lower end.
  Eigen::MatrixXd A(1, 2);
  A << 0, 1;
  LinearProgram lp = polytope_lp(A, Eigen::VectorXd::Constant(1, 1.0));
  const Extent e = extent_of(lp, {Eigen::Vector2d(1, 0)});
  ASSERT_EQ(e.status, ExtentStatus::feasible);
  EXPECT_EQ(e.lo[0], -inf);
  EXPECT_EQ(e.hi[0], inf);
  EXPECT_EQ(e.lo[1], -inf);
  EXPECT_GE(e.hi[1], 1.0);
  ASSERT_EQ(e.maxima.size(), 1u);
  EXPECT_EQ(e.maxima[0], inf);  // x is unbounded above: nothing finite may be claimed
}

RC_GTEST_PROP(CertifiedExtent, CertifiedBoundsContainEverySampledPoint, ()) {
  // A random polytope around the origin inside [-2, 2]^n; points sampled uniformly in the box and
  // kept when exactly inside must lie within the certified extent and below every maximum.
  const int n = *rc::gen::inRange(1, 5);
  sets::test::Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const int m = 2 * n + 6;
  Eigen::MatrixXd A(m, n);
  Eigen::VectorXd b(m);
  A.topRows(n) = Eigen::MatrixXd::Identity(n, n);
  A.middleRows(n, n) = -Eigen::MatrixXd::Identity(n, n);
  b.head(2 * n).setConstant(2.0);
  for (int i = 2 * n; i < m; ++i) {
    A.row(i) = r.mat(1, n) * std::pow(10.0, r.u(-2, 2));  // rows of mixed scales
    b[i] = A.row(i).cwiseAbs().sum() * r.u(0.05, 1.0);     // keeps a neighbourhood of 0 inside
  }
  std::vector<Eigen::VectorXd> dirs;
  for (int k = 0; k < 4; ++k) dirs.push_back(r.mat(n, 1));
  LinearProgram lp = polytope_lp(A, b);
  const Extent e = extent_of(lp, dirs);
  RC_ASSERT(e.status == ExtentStatus::feasible);
  RC_ASSERT(e.certified);
  int inside = 0;
  for (int s = 0; s < 150; ++s) {
    Eigen::VectorXd x = 2 * r.mat(n, 1);
    // Every fourth sample is pushed onto the boundary along a random ray from the origin.
    if (s % 4 == 0) {
      double t = inf;
      for (int i = 0; i < m; ++i) {
        const double ax = A.row(i).dot(x);
        if (ax > 0) t = std::min(t, b[i] / ax);
      }
      x *= t;
    }
    if (!exactly_inside(A, b, x)) continue;
    ++inside;
    for (int j = 0; j < n; ++j) RC_ASSERT(e.lo[j] <= x[j] && x[j] <= e.hi[j]);
    for (std::size_t k = 0; k < dirs.size(); ++k) RC_ASSERT(exact_dot(dirs[k], x) <= mpq_class(e.maxima[k]));
  }
  RC_TAG(inside > 20 ? "many points inside" : "few points inside");
  // Tight: the certified ends are the floating-point ones to LP accuracy.
  for (int j = 0; j < n; ++j) {
    RC_ASSERT(e.hi[j] - e.float_hi[j] <= 1e-6 * (1 + std::abs(e.float_hi[j])));
    RC_ASSERT(e.float_lo[j] - e.lo[j] <= 1e-6 * (1 + std::abs(e.float_lo[j])));
  }
}
