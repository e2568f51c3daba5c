// Ellipsoids: soundness of every outer operation by sampling, exact projection/slice checks,
// three-valued containment, degenerate (flat) ellipsoids and bad input.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <numbers>
#include <random>

#include "sets/domains/conversions.hpp"
#include "sets/domains/ellipsoid.hpp"
#include "sets/core/error.hpp"

namespace {

using sets::BoolInterval;
using sets::Ellipsoid;
using sets::EllipsoidCriterion;

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  double u(double lo = -1, double hi = 1) { return std::uniform_real_distribution<double>(lo, hi)(g); }
  double n() { return std::normal_distribution<double>()(g); }
  Eigen::VectorXd vec(int n, double s = 1) {
    return Eigen::VectorXd::NullaryExpr(n, [&] { return s * u(); });
  }
  // A point uniformly in the unit ball, shrunk by `shrink` to stay clear of the boundary.
  Eigen::VectorXd in_ball(int d, double shrink = 1 - 1e-9) {
    Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(d, [&] { return n(); });
    const double r = std::pow(u(0, 1), 1.0 / d);
    return shrink * r * x / x.norm();
  }
  Eigen::VectorXd on_sphere(int d, double shrink = 1 - 1e-9) {
    Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(d, [&] { return n(); });
    return shrink * x / x.norm();
  }
};

// Random ellipsoid; rank < n gives a flat one.
Ellipsoid random_ellipsoid(Rng& r, int n, int rank) {
  Eigen::MatrixXd L = Eigen::MatrixXd::NullaryExpr(n, rank, [&] { return r.u(); });
  return Ellipsoid(r.vec(n, 3), L * L.transpose() + 0.0 * Eigen::MatrixXd::Identity(n, n));
}

// A square root: P = S S^T (eigenvalues at rounding level set to 0, so flat stays flat).
Eigen::MatrixXd sqrt_shape(const Ellipsoid& E) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(E.shape());
  Eigen::VectorXd l = es.eigenvalues();
  const double cut = 1e-12 * std::max(l.maxCoeff(), 0.0);
  for (Eigen::Index i = 0; i < l.size(); ++i) l[i] = l[i] > cut ? std::sqrt(l[i]) : 0.0;
  return es.eigenvectors() * l.asDiagonal();
}

// Sampled points of a flat ellipsoid are off its affine hull by rounding (~1e-16), so they are
// genuinely outside; the checks below allow that much slack for flat sets only.
constexpr double kSlack = 1e-12;

Eigen::VectorXd sample(Rng& r, const Ellipsoid& E, bool boundary = false) {
  const int n = E.dimension();
  return E.center() + sqrt_shape(E) * (boundary ? r.on_sphere(n) : r.in_ball(n));
}

// A sample meant to lie in E can land outside it by rounding (c + L u in doubles: relative error
// up to cond(L) * eps; 2e-8 outside was seen, seed 6661860393174795560), and then "no" is the
// right answer. Containment is asserted only for points inside E by a margin, judged in long
// double (error ~ cond * 1e-19, far below the margin).
bool clearly_inside(const Ellipsoid& E, const Eigen::VectorXd& x) {
  using VectorXld = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
  using MatrixXld = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
  const VectorXld v = x.cast<long double>() - E.center().cast<long double>();
  const Eigen::LDLT<MatrixXld> ldlt(E.shape().cast<long double>());
  return v.dot(ldlt.solve(v)) <= 1 - 1e-9L;
}

double quad_form(const Ellipsoid& E, const Eigen::VectorXd& x) {
  const Eigen::VectorXd v = x - E.center();
  return v.dot(E.shape().ldlt().solve(v));
}

}  // namespace

TEST(Ellipsoid, RejectsBadInput) {
  EXPECT_THROW(Ellipsoid(Eigen::VectorXd::Zero(2), Eigen::MatrixXd::Identity(3, 3)), sets::InputError);
  Eigen::MatrixXd ns(2, 2);
  ns << 1, 0.5, 0, 1;
  EXPECT_THROW(Ellipsoid(Eigen::VectorXd::Zero(2), ns), sets::InputError);
  Eigen::MatrixXd indefinite(2, 2);
  indefinite << 1, 0, 0, -1;
  EXPECT_THROW(Ellipsoid(Eigen::VectorXd::Zero(2), indefinite), sets::InputError);
  Eigen::VectorXd nan = Eigen::VectorXd::Zero(2);
  nan[1] = std::nan("");
  EXPECT_THROW(Ellipsoid(nan, Eigen::MatrixXd::Identity(2, 2)), sets::InputError);
  Eigen::MatrixXd singular = Eigen::MatrixXd::Zero(2, 2);
  singular(0, 0) = 1;
  EXPECT_THROW(Ellipsoid::from_level_set(Eigen::VectorXd::Zero(2), singular, 1.0), sets::InputError);
  EXPECT_THROW(Ellipsoid::from_level_set(Eigen::VectorXd::Zero(2), Eigen::MatrixXd::Identity(2, 2), -1),
               sets::InputError);
  const Ellipsoid E = Ellipsoid::ball(Eigen::VectorXd::Zero(3), 1.0);
  EXPECT_THROW(sets::project(E, {0, 3}), sets::InputError);
  EXPECT_THROW(sets::slice(E, {0}, Eigen::VectorXd::Zero(1)), sets::InputError);
  EXPECT_THROW(sets::support(E, Eigen::VectorXd::Zero(2)), sets::InputError);
  EXPECT_THROW(sets::intersect_strip(E, Eigen::VectorXd::Ones(3), 0.0, -1.0), sets::InputError);
}

TEST(Ellipsoid, VolumeOfKnownShapes) {
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(2, 2);
  P.diagonal() << 4, 9;
  EXPECT_NEAR(sets::volume(Ellipsoid(Eigen::VectorXd::Zero(2), P)), 6 * std::numbers::pi, 1e-12);
  EXPECT_NEAR(sets::volume(Ellipsoid::ball(Eigen::VectorXd::Zero(3), 2.0)), 32.0 / 3 * std::numbers::pi,
              1e-10);
  P(1, 1) = 0;
  EXPECT_EQ(sets::volume(Ellipsoid(Eigen::VectorXd::Zero(2), P)), 0.0);
}

TEST(Ellipsoid, ContainmentIsThreeValued) {
  Eigen::MatrixXd P(2, 2);
  P << 4, 1, 1, 2;
  const Ellipsoid E(Eigen::Vector2d(1, -1), P);
  EXPECT_EQ(sets::contains(E, Eigen::Vector2d(1, -1)), BoolInterval::yes);
  EXPECT_EQ(sets::contains(E, Eigen::Vector2d(10, 0)), BoolInterval::no);
  // A boundary point (up to rounding) is not decided by a guess.
  Rng r(7);
  int undecided = 0;
  for (int k = 0; k < 200; ++k) {
    const Eigen::VectorXd x = E.center() + sqrt_shape(E) * r.on_sphere(2, 1.0);
    const auto b = sets::contains(E, x);
    const double q = quad_form(E, x);
    if (q < 1 - 1e-9) {
      EXPECT_NE(b, BoolInterval::no);
    }
    if (q > 1 + 1e-9) {
      EXPECT_NE(b, BoolInterval::yes);
    }
    undecided += b == BoolInterval::unknown;
  }
  EXPECT_GT(undecided, 0);  // some boundary points land within rounding of it
}

TEST(Ellipsoid, FlatEllipsoidContainment) {
  // The segment {(t, 0) : |t| <= 2} as an ellipsoid with a singular shape matrix.
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(2, 2);
  P(0, 0) = 4;
  const Ellipsoid E(Eigen::Vector2d(0, 0), P);
  EXPECT_EQ(sets::contains(E, Eigen::Vector2d(1, 0)), BoolInterval::yes);
  EXPECT_EQ(sets::contains(E, Eigen::Vector2d(3, 0)), BoolInterval::no);
  EXPECT_EQ(sets::contains(E, Eigen::Vector2d(1, 1e-3)), BoolInterval::no);
  EXPECT_EQ(sets::volume(E), 0.0);
  const auto box = sets::outer_box(E);
  EXPECT_LE(box[0].lower(), -2);
  EXPECT_GE(box[0].upper(), 2);
  EXPECT_LE(box[1].lower(), 0);
  EXPECT_GE(box[1].upper(), 0);
  // A tilted flat ellipsoid: points on it are unknown or yes, points off it are no.
  Rng r(3);
  const Ellipsoid F = random_ellipsoid(r, 3, 2);
  for (int k = 0; k < 50; ++k) {
    const Eigen::VectorXd x = sample(r, F);
    EXPECT_NE(sets::contains(F, x), BoolInterval::no);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(F.shape());
    EXPECT_EQ(sets::contains(F, x + 1e-3 * es.eigenvectors().col(0)), BoolInterval::no);
  }
}

RC_GTEST_PROP(Ellipsoid, SupportBoxAndContainmentAreSound, ()) {
  const int n = *rc::gen::inRange(1, 7);
  const int rank = *rc::gen::inRange(1, n + 1);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Ellipsoid E = random_ellipsoid(r, n, rank);
  const auto box = sets::outer_box(E);
  for (int k = 0; k < 100; ++k) {
    const Eigen::VectorXd x = sample(r, E, k % 2 == 0);
    const Eigen::VectorXd d = r.vec(n);
    if (rank == n) {
      RC_ASSERT(sets::contains(box, x));
      RC_ASSERT(d.dot(x) <= sets::support(E, d));
      if (clearly_inside(E, x)) RC_ASSERT(sets::contains(E, x) != BoolInterval::no);
    } else {
      RC_ASSERT(d.dot(x) <= sets::support(E, d) + kSlack);
    }
  }
  // The support is attained (tight): within rounding of d^T c + sqrt(d^T P d).
  const Eigen::VectorXd d = r.vec(n);
  const double exact = d.dot(E.center()) + std::sqrt(d.dot(E.shape() * d));
  RC_ASSERT(sets::support(E, d) - exact <= 1e-12 * (1 + std::abs(exact)));
}

RC_GTEST_PROP(Ellipsoid, StripUpdateContainsIntersection, ()) {
  const int n = *rc::gen::inRange(1, 6);
  const int rank = *rc::gen::inRange(1, n + 1);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Ellipsoid E = random_ellipsoid(r, n, rank);
  const Eigen::VectorXd a = r.vec(n);
  const Eigen::VectorXd x0 = sample(r, E);
  const double g = std::sqrt(a.dot(E.shape() * a));
  const double delta = r.u(0.01, 1.0) * g;
  const double y = a.dot(x0) + r.u() * delta;
  const auto vol = sets::intersect_strip(E, a, y, delta, EllipsoidCriterion::min_volume);
  const auto tr = sets::intersect_strip(E, a, y, delta, EllipsoidCriterion::min_trace);
  int inside = 0;
  for (int k = 0; k < 400; ++k) {
    const Eigen::VectorXd x = sample(r, E, k % 3 == 0);
    if (std::abs(y - a.dot(x)) > delta * (1 - 1e-9)) continue;
    if (rank == n && !clearly_inside(E, x)) continue;
    ++inside;
    RC_ASSERT(sets::contains(vol, x) != BoolInterval::no);
    RC_ASSERT(sets::contains(tr, x) != BoolInterval::no);
  }
  RC_TAG(inside > 0 ? "sampled" : "no samples");
  // Each criterion is no worse than the other on its own measure, and never worse than E.
  if (rank == n) {
    RC_ASSERT(sets::volume(vol) <= sets::volume(E) * (1 + 1e-6));
    RC_ASSERT(sets::volume(vol) <= sets::volume(tr) * (1 + 1e-6));
  }
  RC_ASSERT(tr.shape().trace() <= E.shape().trace() * (1 + 1e-6) + 1e-12);
  RC_ASSERT(tr.shape().trace() <= vol.shape().trace() * (1 + 1e-6) + 1e-12);
}

TEST(Ellipsoid, StripOnHyperplaneAndEmptyIntersection) {
  const Ellipsoid E = Ellipsoid::ball(Eigen::Vector2d(0, 0), 1.0);
  // delta = 0: the exact chord x_1 = 0.6, |x_2| <= 0.8.
  const Ellipsoid H = sets::intersect_strip(E, Eigen::Vector2d(1, 0), 0.6, 0.0);
  EXPECT_NEAR(H.center()[0], 0.6, 1e-12);
  EXPECT_NEAR(H.shape()(1, 1), 0.64, 1e-12);
  EXPECT_NEAR(H.shape()(0, 0), 0.0, 1e-12);
  EXPECT_NE(sets::contains(H, Eigen::Vector2d(0.6, 0.79)), BoolInterval::no);
  EXPECT_EQ(sets::contains(H, Eigen::Vector2d(0.6, 0.81)), BoolInterval::no);
  // Disjoint: the data falsify the ellipsoid.
  EXPECT_FALSE(sets::try_intersect_strip(E, Eigen::Vector2d(1, 0), 3.0, 0.5).has_value());
  EXPECT_THROW(sets::intersect_strip(E, Eigen::Vector2d(1, 0), 3.0, 0.5), sets::EmptySetError);
  // A strip wider than E leaves E unchanged.
  const Ellipsoid W = sets::intersect_strip(E, Eigen::Vector2d(1, 0), 0.0, 5.0);
  EXPECT_EQ(W.shape(), E.shape());
  // 1-D: the exact interval.
  const Ellipsoid L = sets::intersect_strip(Ellipsoid::ball(Eigen::VectorXd::Zero(1), 1.0),
                                            Eigen::VectorXd::Constant(1, 2.0), 1.0, 0.5);
  EXPECT_NEAR(L.center()[0], 0.5, 1e-12);  // [-1, 1] meets 2x in [0.5, 1.5]: x in [0.25, 0.75]
  EXPECT_NEAR(L.shape()(0, 0), 0.25 * 0.25, 1e-12);
}

TEST(Ellipsoid, RecursiveObeKeepsTheTrueParameter) {
  // Bounded-error data y = phi^T theta + e, |e| <= delta, processed strip by strip.
  Rng r(11);
  const int p = 4;
  const Eigen::VectorXd theta = r.vec(p, 2);
  for (auto crit : {EllipsoidCriterion::min_volume, EllipsoidCriterion::min_trace}) {
    Ellipsoid E = Ellipsoid::ball(Eigen::VectorXd::Zero(p), 100.0);
    const double v0 = sets::volume(E);
    for (int t = 0; t < 300; ++t) {
      const Eigen::VectorXd phi = r.vec(p);
      const double delta = 0.1;
      const double y = phi.dot(theta) + r.u() * delta;
      E = sets::intersect_strip(E, phi, y, delta, crit);
      ASSERT_NE(sets::contains(E, theta), BoolInterval::no) << "sample " << t;
    }
    EXPECT_LT(sets::volume(E), 1e-6 * v0);  // the data do shrink the set
  }
}

RC_GTEST_PROP(Ellipsoid, ProjectionIsTheShadow, ()) {
  const int n = *rc::gen::inRange(2, 7);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Ellipsoid E = random_ellipsoid(r, n, *rc::gen::inRange(1, n + 1));
  std::vector<int> coords;
  for (int i = 0; i < n; ++i)
    if (r.u() > 0) coords.push_back(i);
  if (coords.empty()) coords.push_back(n - 1);
  const Ellipsoid Q = sets::project(E, coords);
  const auto k = static_cast<int>(coords.size());
  for (int s = 0; s < 50; ++s) {
    const Eigen::VectorXd x = sample(r, E, s % 2 == 0);
    Eigen::VectorXd xk(k);
    for (int i = 0; i < k; ++i) xk[i] = x[coords[i]];
    const Eigen::VectorXd d = r.vec(k);
    RC_ASSERT(d.dot(xk) <= sets::support(Q, d) + kSlack);
    // The shadow is exact: its support equals E's in the embedded direction.
    Eigen::VectorXd D = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < k; ++i) D[coords[i]] += d[i];
    RC_ASSERT(std::abs(sets::support(Q, d) - sets::support(E, D)) <= 1e-9 * (1 + std::abs(sets::support(E, D))));
  }
}

RC_GTEST_PROP(Ellipsoid, SliceAgreesWithSampling, ()) {
  const int n = *rc::gen::inRange(2, 6);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Ellipsoid E = random_ellipsoid(r, n, n);
  const int k = *rc::gen::inRange(1, n);
  std::vector<int> kept, fixed;
  for (int i = 0; i < n; ++i) (i < k ? kept : fixed).push_back(i);
  // A point of E fixes the other coordinates; its kept part must lie in the slice, and every
  // point of the slice (re-assembled) must lie in E, with its boundary on E's boundary.
  const Eigen::VectorXd x = sample(r, E);
  Eigen::VectorXd v(n - k), xk(k);
  for (int i = 0; i < n - k; ++i) v[i] = x[fixed[i]];
  for (int i = 0; i < k; ++i) xk[i] = x[kept[i]];
  const auto S = sets::slice(E, kept, v);
  RC_ASSERT(S.has_value());
  const double qs = quad_form(*S, xk);
  RC_ASSERT(qs <= 1 + 1e-6);
  const Ellipsoid P = sets::project(E, kept);
  for (int s = 0; s < 30; ++s) {
    const Eigen::VectorXd u = sample(r, *S, true);
    Eigen::VectorXd full(n);
    for (int i = 0; i < k; ++i) full[kept[i]] = u[i];
    for (int i = 0; i < n - k; ++i) full[fixed[i]] = v[i];
    RC_ASSERT(std::abs(quad_form(E, full) - 1) <= 1e-6);
    RC_ASSERT(sets::contains(P, u) != BoolInterval::no);  // slice inside projection
  }
  // Far outside: empty.
  RC_ASSERT(!sets::slice(E, kept, v + Eigen::VectorXd::Constant(n - k, 1e3)).has_value());
}

TEST(Ellipsoid, SliceVersusProjectionOfATiltedEllipse) {
  // x^2 + y^2 + 1.6 x y <= 1 (scaled): the shadow on x is wider than the slice at y = 0.
  Eigen::MatrixXd R(2, 2);
  R << 1, 0.8, 0.8, 1;
  const Ellipsoid E = Ellipsoid::from_level_set(Eigen::Vector2d(0, 0), R, 1.0);
  const Ellipsoid proj = sets::project(E, {0});
  const auto sl = sets::slice(E, {0}, Eigen::VectorXd::Zero(1));
  ASSERT_TRUE(sl.has_value());
  EXPECT_NEAR(sl->shape()(0, 0), 1.0, 1e-9);             // x^2 <= 1 at y = 0
  EXPECT_NEAR(proj.shape()(0, 0), 1.0 / 0.36, 1e-9);     // (R^{-1})_00 = 1 / (1 - 0.64)
}

RC_GTEST_PROP(Ellipsoid, LinearMapAndMinkowskiSumAreSound, ()) {
  const int n = *rc::gen::inRange(1, 6);
  const int m = *rc::gen::inRange(1, 6);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Ellipsoid E = random_ellipsoid(r, n, *rc::gen::inRange(1, n + 1));
  const Ellipsoid F = random_ellipsoid(r, n, *rc::gen::inRange(1, n + 1));
  const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(m, n, [&] { return r.u(); });
  const Ellipsoid AE = sets::linear_map(A, E);
  const Ellipsoid S1 = sets::minkowski_sum(E, F, EllipsoidCriterion::min_trace);
  const Ellipsoid S2 = sets::minkowski_sum(E, F, EllipsoidCriterion::min_volume);
  for (int s = 0; s < 100; ++s) {
    const Eigen::VectorXd x = sample(r, E, s % 2 == 0), z = sample(r, F, s % 3 == 0);
    const Eigen::VectorXd d = r.vec(m);
    RC_ASSERT(d.dot(A * x) <= sets::support(AE, d) + 1e-12);
    RC_ASSERT(sets::contains(S1, x + z) != BoolInterval::no);
    RC_ASSERT(sets::contains(S2, x + z) != BoolInterval::no);
  }
}

RC_GTEST_PROP(Ellipsoid, LevelSetContainsItsPoints, ()) {
  const int n = *rc::gen::inRange(1, 6);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  Eigen::MatrixXd L = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return r.u(); });
  const Eigen::MatrixXd R = L * L.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd t0 = r.vec(n);
  const double gamma = r.u(0.1, 10);
  const Ellipsoid E = Ellipsoid::from_level_set(t0, R, gamma);
  for (int s = 0; s < 100; ++s) {
    Eigen::VectorXd d = Eigen::VectorXd::NullaryExpr(n, [&] { return r.n(); });
    // The boundary point of the level set along d.
    const Eigen::VectorXd x = t0 + std::sqrt(gamma / d.dot(R * d)) * d * (1 - 1e-9);
    RC_ASSERT(sets::contains(E, x) != BoolInterval::no);
  }
}

TEST(Ellipsoid, OuterPolygonContainsTheEllipse) {
  Rng r(5);
  const Ellipsoid E = random_ellipsoid(r, 2, 2);
  const Eigen::MatrixXd V = sets::outer_polygon(E, 32);
  ASSERT_EQ(V.cols(), 32);
  for (int s = 0; s < 200; ++s) {
    const Eigen::VectorXd x = sample(r, E, true);
    // Inside the convex polygon: left of every edge (vertices are counter-clockwise in the
    // unit-disc frame; the map may flip orientation, so test consistent sign).
    int pos = 0, neg = 0;
    for (int k = 0; k < 32; ++k) {
      const Eigen::Vector2d p = V.col(k), q = V.col((k + 1) % 32);
      const double cr = (q - p).x() * (x - p).y() - (q - p).y() * (x - p).x();
      pos += cr >= 0;
      neg += cr <= 0;
    }
    EXPECT_TRUE(pos == 32 || neg == 32);
  }
}
