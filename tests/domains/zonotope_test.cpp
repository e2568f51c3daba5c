// Zonotopes: soundness of every outer operation by sampling, facet enumeration (tight and
// containing), three-valued containment, flat cases.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/LU>

#include <limits>
#include <random>

#include "sets/core/error.hpp"
#include "sets/domains/conversions.hpp"
#include "sets/domains/zonotope.hpp"

namespace {

using sets::BoolInterval;
using sets::ReductionMethod;
using sets::Zonotope;

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  double u(double lo = -1, double hi = 1) { return std::uniform_real_distribution<double>(lo, hi)(g); }
  Eigen::VectorXd vec(int n, double s = 1) { return Eigen::VectorXd::NullaryExpr(n, [&] { return s * u(); }); }
  Eigen::MatrixXd mat(int r, int c) { return Eigen::MatrixXd::NullaryExpr(r, c, [&] { return u(); }); }
};

constexpr double kShrink = 1 - 1e-9;  // sampled points stay clear of the boundary by more than rounding

// A point of Z: xi in [-1, 1]^m, often at a vertex (every |xi_j| = 1) to probe the boundary.
Eigen::VectorXd sample(Rng& r, const Zonotope& Z, bool vertex) {
  Eigen::VectorXd xi(Z.num_generators());
  for (int j = 0; j < xi.size(); ++j) xi[j] = vertex ? (r.u() > 0 ? 1.0 : -1.0) : r.u();
  return Z.center() + Z.generators() * (kShrink * xi);
}

bool full_rank(const Zonotope& Z) {
  return Z.num_generators() >= Z.dimension() &&
         Eigen::FullPivLU<Eigen::MatrixXd>(Z.generators()).rank() == Z.dimension();
}

}  // namespace

TEST(Zonotope, RejectsBadInput) {
  EXPECT_THROW(Zonotope(Eigen::VectorXd::Zero(2), Eigen::MatrixXd::Identity(3, 3)), sets::InputError);
  Eigen::MatrixXd G = Eigen::MatrixXd::Identity(2, 2);
  G(0, 1) = std::nan("");
  EXPECT_THROW(Zonotope(Eigen::VectorXd::Zero(2), G), sets::InputError);
  const Zonotope Z(Eigen::VectorXd::Zero(2), Eigen::MatrixXd::Identity(2, 2));
  EXPECT_THROW(sets::reduce_order(Z, 0.5), sets::InputError);
  EXPECT_THROW(sets::linear_map(Eigen::MatrixXd::Identity(3, 3), Z), sets::InputError);
  EXPECT_THROW(sets::contains(Z, Eigen::VectorXd::Zero(3)), sets::InputError);
  EXPECT_THROW(sets::polygon_vertices(Zonotope(Eigen::VectorXd::Zero(3), Eigen::MatrixXd::Identity(3, 3))),
               sets::InputError);
  sets::IntervalVector unbounded(1);
  unbounded[0] = sets::Interval(0.0, std::numeric_limits<double>::infinity());
  EXPECT_THROW(Zonotope::from_box(unbounded), sets::InputError);
}

TEST(Zonotope, BoxRoundTripAndContainment) {
  const auto box = sets::make_box(Eigen::Vector3d(-1, 0.1, 2), Eigen::Vector3d(1, 0.3, 2));
  const Zonotope Z = Zonotope::from_box(box);
  EXPECT_EQ(Z.num_generators(), 2);  // the flat coordinate needs no generator
  const auto back = sets::outer_box(Z);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LE(back[i].lower(), box[i].lower());
    EXPECT_GE(back[i].upper(), box[i].upper());
    EXPECT_NEAR(back[i].lower(), box[i].lower(), 1e-15);
  }
  const Zonotope S(Eigen::Vector2d(0, 0), Eigen::MatrixXd::Identity(2, 2));
  EXPECT_EQ(sets::contains(S, Eigen::Vector2d(0.5, -0.5)), BoolInterval::yes);
  EXPECT_EQ(sets::contains(S, Eigen::Vector2d(1, 1)), BoolInterval::yes);  // exact vertex
  EXPECT_EQ(sets::contains(S, Eigen::Vector2d(1.5, 0)), BoolInterval::no);
  // Inside the box hull but outside the rotated square.
  Eigen::MatrixXd G(2, 2);
  G << 1, 1, 1, -1;
  const Zonotope D(Eigen::Vector2d(0, 0), G);
  EXPECT_EQ(sets::contains(D, Eigen::Vector2d(1.5, 1.5)), BoolInterval::no);
  EXPECT_EQ(sets::contains(D, Eigen::Vector2d(1.5, 0.4)), BoolInterval::yes);
}

TEST(Zonotope, FlatZonotopeContainment) {
  // A segment in 3-D and a parallelogram in 3-D: off-plane points are certainly outside.
  Eigen::MatrixXd G(3, 2);
  G << 1, 0, 0, 1, 1, 1;
  const Zonotope Z(Eigen::Vector3d(0, 0, 0), G);
  EXPECT_EQ(sets::contains(Z, Eigen::Vector3d(0.5, 0.5, 1.0)), BoolInterval::yes);  // exact
  EXPECT_EQ(sets::contains(Z, Eigen::Vector3d(0.5, 0.5, 1.1)), BoolInterval::no);
  EXPECT_EQ(sets::contains(Z, Eigen::Vector3d(0.5, 1.5, 2.0)), BoolInterval::no);
  const auto H = sets::to_hpolytope(Z);
  const Eigen::Vector3d in(0.5, -0.5, 0.0), out(0.5, -0.5, 0.1);
  EXPECT_TRUE(((H.A() * in).array() <= H.b().array()).all());
  EXPECT_FALSE(((H.A() * out).array() <= H.b().array()).all());
}

RC_GTEST_PROP(Zonotope, LinearMapMinkowskiAndBoxAreSound, ()) {
  const int n = *rc::gen::inRange(1, 6), m = *rc::gen::inRange(0, 9), k = *rc::gen::inRange(1, 6);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Zonotope Z(r.vec(n, 3), r.mat(n, m)), W(r.vec(n), r.mat(n, *rc::gen::inRange(0, 6)));
  const Eigen::MatrixXd A = r.mat(k, n);
  const Zonotope AZ = sets::linear_map(A, Z), S = sets::minkowski_sum(Z, W);
  const auto box = sets::outer_box(S);
  for (int s = 0; s < 40; ++s) {
    const Eigen::VectorXd x = sample(r, Z, s % 2 == 0), w = sample(r, W, s % 3 == 0);
    const Eigen::VectorXd d = r.vec(k), e = r.vec(n);
    RC_ASSERT(d.dot(A * x) <= sets::support(AZ, d) + 1e-12);
    RC_ASSERT(e.dot(x + w) <= sets::support(S, e) + 1e-12);
    RC_ASSERT(sets::contains(box, x + w));
    if (full_rank(S) && s < 10) RC_ASSERT(sets::contains(S, x + w) != BoolInterval::no);
  }
}

RC_GTEST_PROP(Zonotope, OrderReductionIsSoundAndBounded, ()) {
  const int n = *rc::gen::inRange(1, 6), m = *rc::gen::inRange(1, 30);
  const double order = *rc::gen::element(1.0, 1.5, 2.0, 3.0);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Zonotope Z(r.vec(n), r.mat(n, m));
  for (auto method : {ReductionMethod::girard, ReductionMethod::combastel, ReductionMethod::pca}) {
    const Zonotope R = sets::reduce_order(Z, order, method);
    RC_ASSERT(R.num_generators() <= std::max(n, static_cast<int>(order * n)));
    for (int s = 0; s < 30; ++s) {
      const Eigen::VectorXd x = sample(r, Z, s % 2 == 0), d = r.vec(n);
      RC_ASSERT(d.dot(x) <= sets::support(R, d));
      if (s < 8 && full_rank(R)) RC_ASSERT(sets::contains(R, x) != BoolInterval::no);
    }
  }
}

RC_GTEST_PROP(Zonotope, FacetEnumerationIsTightAndContaining, ()) {
  const int n = *rc::gen::inRange(2, 4), m = *rc::gen::inRange(1, 7);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Zonotope Z(r.vec(n), r.mat(n, m));
  const auto H = sets::to_hpolytope(Z);
  // All 2^m sign vectors: every vertex candidate satisfies every facet, and every facet is
  // touched by some vertex (it is a supporting hyperplane, not a loose one).
  Eigen::VectorXd best = Eigen::VectorXd::Constant(H.num_constraints(), -std::numeric_limits<double>::infinity());
  for (int mask = 0; mask < (1 << m); ++mask) {
    Eigen::VectorXd xi(m);
    for (int j = 0; j < m; ++j) xi[j] = (mask >> j) & 1 ? 1.0 : -1.0;
    const Eigen::VectorXd v = Z.center() + Z.generators() * xi;
    const Eigen::VectorXd Av = H.A() * v;
    RC_ASSERT(((Av - H.b()).array() <= 1e-12).all());
    best = best.cwiseMax(Av);
  }
  RC_ASSERT(((H.b() - best).array() <= 1e-9).all());
  if (n == 2 && m >= 2) RC_ASSERT(H.num_constraints() == 2 * m);  // generic: one facet pair per generator
}

TEST(Zonotope, PolygonVerticesAreCounterClockwise) {
  Rng r(2);
  const Zonotope Z(r.vec(2), r.mat(2, 5));
  const Eigen::MatrixXd V = sets::polygon_vertices(Z);
  ASSERT_EQ(V.cols(), 10);
  for (int k = 0; k < 10; ++k) {
    const Eigen::Vector2d a = V.col(k), b = V.col((k + 1) % 10), c = V.col((k + 2) % 10);
    EXPECT_GT((b - a).x() * (c - b).y() - (b - a).y() * (c - b).x(), 0);
  }
}

RC_GTEST_PROP(Zonotope, StripUpdateContainsIntersection, ()) {
  const int n = *rc::gen::inRange(1, 5), m = *rc::gen::inRange(n, 8);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Zonotope Z(r.vec(n), r.mat(n, m));
  const Eigen::VectorXd a = r.vec(n);
  const Eigen::VectorXd x0 = sample(r, Z, false);
  const double delta = r.u(0.01, 0.5) * (sets::support(Z, a) + sets::support(Z, -a));
  const double y = a.dot(x0) + r.u() * delta;
  const auto R = sets::try_intersect_strip(Z, a, y, delta);
  RC_ASSERT(R.has_value());
  for (int s = 0; s < 200; ++s) {
    const Eigen::VectorXd x = sample(r, Z, s % 2 == 0);
    if (std::abs(y - a.dot(x)) > delta * kShrink) continue;
    const Eigen::VectorXd d = r.vec(n);
    RC_ASSERT(d.dot(x) <= sets::support(*R, d));
  }
  RC_ASSERT(!sets::try_intersect_strip(Z, a, sets::support(Z, a) + 1.0, 0.5).has_value());
}

