// Support and outer box of UNBOUNDED H-polytopes: finite (and certified) in the directions in
// which the polytope is bounded, +inf in the others. Checked in exact rational arithmetic.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpq.h>

#include <cmath>
#include <random>

#include "sets/domains/hpolytope.hpp"
#include "sets/numeric/linear_program.hpp"

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
