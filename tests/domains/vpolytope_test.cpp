// V-polytopes (src/domains/vpolytope.cpp): containment agrees with CGAL's exact 2-D hull, points on
// the boundary included.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/convex_hull_2.h>
#include <gmpxx.h>

#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>

#include "sets/domains/vpolytope.hpp"
#include "support/random_matrices.hpp"

namespace {

using sets::BoolInterval;
using sets::VPolytope;
using sets::test::Rng;
using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Q = mpq_class;  // every double is a rational; mpq_class(double) converts exactly
using QVector = std::vector<Q>;

// A double of random sign and magnitude 2^-20..2^20, so that products and sums round.
double entry(Rng& r) { return r.u() * std::ldexp(1.0, static_cast<int>(std::floor(r.u(-20, 20)))); }

// The exact image A x of a rational point x.
QVector exact_image(const Eigen::MatrixXd& A, const QVector& x) {
  QVector y(A.rows(), Q(0));
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    for (Eigen::Index j = 0; j < A.cols(); ++j) y[i] += Q(A(i, j)) * x[j];
  return y;
}

// d^T y <= max over the points p of d^T p, exactly: y lies on the inner side of the supporting
// hyperplane of the polytope with normal d (a necessary condition for y in the polytope).
bool below_support(const VPolytope& V, const Eigen::VectorXd& d, const QVector& y) {
  Q dy = 0, best = 0;
  for (std::size_t i = 0; i < y.size(); ++i) dy += Q(d[i]) * y[i];
  for (int k = 0; k < V.num_points(); ++k) {
    Q dp = 0;
    for (int i = 0; i < V.dimension(); ++i) dp += Q(d[i]) * Q(V.points()(i, k));
    if (k == 0 || dp > best) best = dp;
  }
  return dy <= best;
}

// y in V checked in the directions +-e_i and `random` random directions (exact arithmetic).
bool contains_in_directions(const VPolytope& V, const QVector& y, Rng& r, int random) {
  const int m = V.dimension();
  for (int i = 0; i < m; ++i)
    for (double s : {1.0, -1.0})
      if (!below_support(V, s * Eigen::VectorXd::Unit(m, i), y)) return false;
  for (int t = 0; t < random; ++t)
    if (!below_support(V, Eigen::VectorXd::NullaryExpr(m, [&] { return entry(r); }), y)) return false;
  return true;
}

}  // namespace

RC_GTEST_PROP(Polytope, VContainmentAgreesWithCgal2D, ()) {
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  // Integer points, so edge midpoints are exact and land exactly on the boundary.
  Eigen::MatrixXd P(2, 8);
  for (int k = 0; k < 8; ++k) P.col(k) << std::round(10 * r.u()), std::round(10 * r.u());
  const VPolytope V(P);
  std::vector<K::Point_2> pts, hull;
  for (int k = 0; k < 8; ++k) pts.emplace_back(P(0, k), P(1, k));
  CGAL::convex_hull_2(pts.begin(), pts.end(), std::back_inserter(hull));
  for (int s = 0; s < 20; ++s) {
    Eigen::Vector2d x(std::round(10 * r.u()) / 2, std::round(10 * r.u()) / 2);
    if (s < 4) x = 0.5 * (P.col(s) + P.col(s + 1));
    const auto side = CGAL::bounded_side_2(hull.begin(), hull.end(), K::Point_2(x[0], x[1]));
    const bool inside = hull.size() >= 3 ? side != CGAL::ON_UNBOUNDED_SIDE
                                         : sets::contains(V, x) == BoolInterval::yes;
    RC_ASSERT(sets::contains(V, x) == (inside ? BoolInterval::yes : BoolInterval::no));
  }
}

// linear_map(A, V) contains {A x : x in V}: sample the true set (the points and random convex
// combinations with rational weights), map each sample exactly in rationals, and check it
// against the computed polytope's support function in exact arithmetic (the axes and random
// directions). Entries of mixed magnitudes make the floating-point products round.
RC_GTEST_PROP(Polytope, LinearMapContainsTheExactImage, ()) {
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const int n = *rc::gen::inRange(1, 5), m = *rc::gen::inRange(1, 5), k = *rc::gen::inRange(1, 7);
  const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(m, n, [&] { return entry(r); });
  const VPolytope V(Eigen::MatrixXd::NullaryExpr(n, k, [&] { return entry(r); }));
  const VPolytope image = sets::linear_map(A, V);
  RC_ASSERT(image.dimension() == m);
  for (int s = 0; s < k + 5; ++s) {
    QVector x(n, Q(0));
    if (s < k) {
      for (int i = 0; i < n; ++i) x[i] = V.points()(i, s);  // a point itself
    } else {
      QVector w(k);
      Q total = 0;
      for (int j = 0; j < k; ++j) total += (w[j] = Q(static_cast<long>(std::floor(r.u(0, 1000)))));
      if (total == 0) continue;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < n; ++i) x[i] += w[j] / total * Q(V.points()(i, j));
    }
    RC_ASSERT(contains_in_directions(image, exact_image(A, x), r, 8));
  }
}

// The adversarial case: 1 + 2^-60 rounds to 1, so the floating-point image {1} of the point
// (1, 2^-60) under [1 1] misses the exact image. The outward map keeps it; the nearest one
// (unreliable_linear_map, for plots) does not, and says so in its name.
TEST(Polytope, LinearMapOfAPointWhoseImageRoundsStaysOutward) {
  const Eigen::RowVector2d A(1.0, 1.0);
  const VPolytope V(Eigen::Vector2d(1.0, std::ldexp(1.0, -60)));
  const QVector exact{Q(1) + Q(std::ldexp(1.0, -60))};
  Rng r(1);
  EXPECT_TRUE(contains_in_directions(sets::linear_map(A, V), exact, r, 0));
  // and only by a few units in the last place
  EXPECT_LE(sets::outer_box(sets::linear_map(A, V))[0].upper(), 1.0 + std::ldexp(1.0, -50));
  EXPECT_GE(sets::outer_box(sets::linear_map(A, V))[0].lower(), 1.0 - std::ldexp(1.0, -50));
  EXPECT_FALSE(contains_in_directions(sets::unreliable_linear_map(A, V), exact, r, 0));
}

// Products that are exact (a permutation, powers of 2) give exactly the mapped points: the
// outward rounding adds nothing when nothing rounds.
TEST(Polytope, LinearMapWithExactProductsIsExact) {
  Eigen::Matrix3d A;
  A << 0, 2, 0, 0, 0, -0.5, 1, 0, 0;
  Eigen::MatrixXd P(3, 4);
  P << 1, 2, 3, 4, -1, 0.5, 0.25, 8, 3, 3, 1, 0;
  const VPolytope image = sets::linear_map(A, VPolytope(P));
  ASSERT_EQ(image.num_points(), 4);
  EXPECT_EQ(image.points(), A * P);
  EXPECT_EQ(sets::unreliable_linear_map(A, VPolytope(P)).points(), A * P);
}
