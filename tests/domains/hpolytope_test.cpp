// H-polytopes (src/domains/hpolytope.cpp): containment against exact rational arithmetic,
// redundancy, Chebyshev ball, intersection and linear maps; support and outer box of UNBOUNDED
// H-polytopes: finite (and certified) in the directions in which the polytope is bounded, +inf in
// the others. Checked in exact rational arithmetic.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpq.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "sets/domains/hpolytope.hpp"
#include "sets/domains/conversions.hpp"
#include "sets/domains/vpolytope.hpp"
#include "sets/numeric/linear_program.hpp"
#include "support/random_matrices.hpp"

namespace {

using Q = CGAL::Gmpq;
using sets::HPolytope;

bool exactly_inside(const HPolytope& P, const Eigen::VectorXd& x) {
  for (int i = 0; i < P.num_constraints(); ++i) {
    Q s = -Q(P.b()[i]);
    for (int j = 0; j < P.dimension(); ++j) s += Q(P.A()(i, j)) * Q(x[j]);
    if (s > 0) return false;
  }
  return true;
}

Q exact_dot(const Eigen::VectorXd& d, const Eigen::VectorXd& x) {
  Q s = 0;
  for (Eigen::Index j = 0; j < d.size(); ++j) s += Q(d[j]) * Q(x[j]);
  return s;
}

}  // namespace

TEST(HPolytopeSupport, QuadrantCornerHasFiniteLowerEnds) {
  // x >= 0, y >= 0, x + y >= 1: unbounded towards +x and +y.
  Eigen::MatrixXd A(3, 2);
  A << -1, 0, 0, -1, -1, -1;
  const HPolytope P(A, Eigen::Vector3d(0, 0, -1));
  const auto box = sets::outer_box(P);
  // Finite and tight to LP tolerance (GLPK accepts 1e-7 relative infeasibility).
  EXPECT_LE(box[0].lower(), 0.0);
  EXPECT_GE(box[0].lower(), -1e-7);
  EXPECT_LE(box[1].lower(), 0.0);
  EXPECT_GE(box[1].lower(), -1e-7);
  EXPECT_EQ(box[0].upper(), sets::inf);
  EXPECT_EQ(box[1].upper(), sets::inf);
  // max -(x + 2y) = -1 at (1, 0); max x is unbounded.
  const double s = sets::support(P, Eigen::Vector2d(-1, -2));
  EXPECT_GE(s, -1.0);
  EXPECT_LE(s, -1.0 + 1e-7);
  EXPECT_EQ(sets::support(P, Eigen::Vector2d(1, 0)), sets::inf);
}

// Random pointed polyhedra that contain x0 + the positive orthant (rows with a_i <= 0), so they
// are unbounded; directions d = sum lambda_i a_i (lambda >= 0) are bounded. The support must be
// finite, above d^T x for every sampled point of P (exact arithmetic), and agree with the support
// of P cut by a large box (a bounded polytope, certified by the box argument).
RC_GTEST_PROP(HPolytopeSupport, UnboundedPolytopeBoundedDirections, ()) {
  const int n = *rc::gen::inRange(2, 5);
  const int m = *rc::gen::inRange(n + 1, 3 * n + 2);
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  std::uniform_real_distribution<double> U(0, 1);
  Eigen::MatrixXd A(m, n);
  Eigen::VectorXd b(m);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < n; ++j) A(i, j) = -U(rng) * (U(rng) < 0.2 ? 0.0 : 1.0);
    if (A.row(i).isZero()) A(i, i % n) = -1;
    b[i] = 2 * U(rng) - 0.5;  // the origin may or may not be inside; P is never empty
  }
  for (int j = 0; j < n; ++j) A(j, j) = -(0.1 + U(rng));  // no free coordinate: P is pointed
  const HPolytope P(A, b);
  std::vector<Eigen::VectorXd> dirs;
  for (int k = 0; k < 4; ++k) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < m; ++i) d += U(rng) * A.row(i).transpose();
    dirs.push_back(d);
  }
  for (int j = 0; j < n; ++j) dirs.push_back(Eigen::VectorXd::Unit(n, j));  // unbounded: +inf
  const std::vector<double> s = sets::support(P, dirs);
  // The same polytope cut by a box far outside its vertices.
  Eigen::MatrixXd Ab(m + 2 * n, n);
  Eigen::VectorXd bb(m + 2 * n);
  Ab << A, Eigen::MatrixXd::Identity(n, n), -Eigen::MatrixXd::Identity(n, n);
  bb << b, Eigen::VectorXd::Constant(2 * n, 1e4);
  const std::vector<double> cut = sets::support(HPolytope(Ab, bb), dirs);
  // Points of P: a box around the region where the vertices lie, plus far points along +orthant.
  std::vector<Eigen::VectorXd> points;
  for (int k = 0; k < 3000 && points.size() < 200; ++k) {
    Eigen::VectorXd x(n);
    for (int j = 0; j < n; ++j) x[j] = 20 * U(rng) - 5;
    if (U(rng) < 0.2) x *= 50;
    if (exactly_inside(P, x)) points.push_back(x);
  }
  RC_TAG(points.size() > 10 ? "many points" : "few points");
  int finite = 0;
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    const bool bounded_dir = k < 4;
    if (!bounded_dir) {
      RC_ASSERT(s[k] == sets::inf);
      continue;
    }
    if (!std::isfinite(s[k])) continue;  // allowed (no vertex certificate), counted below
    ++finite;
    for (const auto& x : points) RC_ASSERT(exact_dot(dirs[k], x) <= Q(s[k]));
    RC_ASSERT(std::abs(s[k] - cut[k]) <= 1e-6 * (1 + std::abs(cut[k])));
  }
  RC_CLASSIFY(finite == 4, "all bounded directions certified");
  RC_ASSERT(finite >= 1);
}

namespace {

using sets::BoolInterval;
using sets::VPolytope;
using sets::test::Rng;

// Exact sign of max_i (a_i^T x - b_i): -1 strictly inside, 0 on the boundary, +1 outside.
int exact_side(const HPolytope& P, const Eigen::VectorXd& x) {
  int worst = -1;
  for (int i = 0; i < P.num_constraints(); ++i) {
    Q s = -Q(P.b()[i]);
    for (int j = 0; j < P.dimension(); ++j) s += Q(P.A()(i, j)) * Q(x[j]);
    worst = std::max(worst, s > 0 ? 1 : (s == 0 ? 0 : -1));
  }
  return worst;
}

HPolytope unit_box(int n) {
  return sets::to_hpolytope(sets::make_box(-Eigen::VectorXd::Ones(n), Eigen::VectorXd::Ones(n)));
}

}  // namespace

RC_GTEST_PROP(Polytope, HContainmentAgreesWithExactArithmetic, ()) {
  const int n = *rc::gen::inRange(2, 4);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  // Dyadic data (multiples of 1/4) put many points exactly on a facet; generic data test the
  // rest. Either way a decided answer must match the exact rational sign.
  const bool dyadic = *rc::gen::arbitrary<bool>();
  auto q = [&](double v) { return dyadic ? std::round(4 * v) / 4 : v; };
  Eigen::MatrixXd A = r.mat(8, n).unaryExpr(q);
  Eigen::VectorXd b = Eigen::VectorXd::NullaryExpr(8, [&] { return q(r.u(0.25, 1)); });
  const HPolytope P(A, b);
  int boundary = 0;
  for (int s = 0; s < 50; ++s) {
    const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return q(r.u()); });
    const auto res = sets::contains(P, x);
    const int side = exact_side(P, x);
    boundary += side == 0;
    if (res == BoolInterval::yes) RC_ASSERT(side <= 0);
    if (res == BoolInterval::no) RC_ASSERT(side > 0);
    if (dyadic) RC_ASSERT(res != BoolInterval::unknown);  // exact data: always decided
  }
  RC_TAG(boundary > 0 ? "hit a facet exactly" : "no boundary points");
}

TEST(Polytope, BoundaryPointsAreInsideOrUnknown) {
  HPolytope P = unit_box(2);
  EXPECT_EQ(sets::contains(P, Eigen::Vector2d(1, 1)), BoolInterval::yes);  // exact corner
  Eigen::MatrixXd A(1, 2);
  A << 0.1, 0.2;  // neither coefficient is a double-exact decimal
  const HPolytope H(A, Eigen::VectorXd::Constant(1, 0.3));
  // Exactly, 0.1 + 0.2 > 0.3 in doubles by 2.8e-17: outside, but within rounding of the facet.
  ASSERT_GT(exact_side(H, Eigen::Vector2d(1, 1)), 0);
  EXPECT_NE(sets::contains(H, Eigen::Vector2d(1, 1)), BoolInterval::yes);
}

TEST(Polytope, RedundancyChebyshevAndIntersection) {
  HPolytope P = unit_box(2);
  Eigen::MatrixXd A(3, 2);
  A << 1, 1, 2, 0, 1, 0;  // x + y <= 5 (redundant), 2x <= 2 (duplicate facet), x <= 1 (copy)
  const HPolytope Q = sets::intersect(P, HPolytope(A, Eigen::Vector3d(5, 2, 1)));
  EXPECT_EQ(Q.num_constraints(), 7);
  const HPolytope R = sets::remove_redundant(Q);
  EXPECT_EQ(R.num_constraints(), 4);
  const auto ball = sets::chebyshev_ball(sets::to_hpolytope(sets::make_box(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 4))));
  EXPECT_NEAR(ball.radius, 1.0, 1e-9);
  EXPECT_NEAR(ball.center[0], 1.0, 1e-9);
}

RC_GTEST_PROP(Polytope, LinearMapContainsTheImage, ()) {
  const int n = *rc::gen::inRange(2, 4);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const VPolytope V(r.mat(n, 12));
  const HPolytope H = sets::to_hpolytope(V);
  Eigen::MatrixXd M = r.mat(n, n) + 2 * Eigen::MatrixXd::Identity(n, n);
  const HPolytope MH = sets::linear_map(M, H);
  const VPolytope hull = sets::convex_hull(V);
  for (int k = 0; k < hull.num_points(); ++k)
    RC_ASSERT(sets::contains(MH, M * hull.points().col(k)) != BoolInterval::no);
  // Tight: every facet is touched by a mapped vertex (up to rounding).
  const Eigen::MatrixXd img = MH.A() * (M * hull.points());
  for (int i = 0; i < MH.num_constraints(); ++i)
    RC_ASSERT(MH.b()[i] - img.row(i).maxCoeff() <= 1e-8 * (1 + std::abs(MH.b()[i])));
}
