// Boxes and interval matrices: every product and hull encloses the exact rational answer at
// sampled points of its operands; widths, radii and volumes are rounded the safe way.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpq.h>

#include <cmath>
#include <limits>

#include "sets/core/error.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace {

using sets::Interval;
using sets::IntervalMatrix;
using sets::IntervalVector;
using Q = CGAL::Gmpq;

bool encloses(const Interval& x, const Q& q) { return Q(x.lower()) <= q && q <= Q(x.upper()); }

// Doubles over many binades, so sums and products round.
rc::Gen<double> gen_double() {
  return rc::gen::map(rc::gen::pair(rc::gen::inRange(-1000000, 1000000), rc::gen::inRange(-30, 30)),
                      [](std::pair<int, int> m) { return std::ldexp(m.first / 997.0, m.second); });
}

rc::Gen<Interval> gen_interval() {
  return rc::gen::map(rc::gen::pair(gen_double(), gen_double()), [](std::pair<double, double> p) {
    return Interval(std::min(p.first, p.second), std::max(p.first, p.second));
  });
}

// A point of [x]: an end or a fraction of the way between them (rounded, then clamped inside).
double point_in(const Interval& x, int k) {
  if (k == 0) return x.lower();
  if (k == 1) return x.upper();
  const double t = (k % 7) / 7.0;
  return std::clamp(x.lower() + t * (x.upper() - x.lower()), x.lower(), x.upper());
}

}  // namespace

RC_GTEST_PROP(IntervalMatrix, ProductEnclosesExactProductsOfSampledPoints, ()) {
  const int m = *rc::gen::inRange(1, 5), n = *rc::gen::inRange(1, 5);
  IntervalMatrix A(m, n);
  IntervalVector x(n);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = *gen_interval();
  for (int j = 0; j < n; ++j) x(j) = *gen_interval();
  const IntervalVector y = sets::multiply(A, x);
  const Eigen::MatrixXd Apoint = sets::midpoint(A);
  const IntervalVector ypoint = sets::multiply(Apoint, x);
  RC_ASSERT(y.size() == m);
  for (int sample = 0; sample < 8; ++sample) {
    for (int i = 0; i < m; ++i) {
      Q exact(0), exact_point(0);
      for (int j = 0; j < n; ++j) {
        const double xj = point_in(x(j), sample + j);
        exact += Q(point_in(A(i, j), sample + 3 * i + j)) * Q(xj);
        exact_point += Q(Apoint(i, j)) * Q(xj);
      }
      RC_ASSERT(encloses(y(i), exact));
      RC_ASSERT(encloses(ypoint(i), exact_point));
    }
  }
}

RC_GTEST_PROP(IntervalMatrix, RadiusHullAndVolumeAreRoundedOutward, ()) {
  const int n = *rc::gen::inRange(1, 6);
  IntervalVector a(n), b(n);
  for (int j = 0; j < n; ++j) a(j) = *gen_interval(), b(j) = *gen_interval();
  const Eigen::VectorXd mid = sets::midpoint(a), rad = sets::radius(a);
  Q exact_volume(1);
  for (int j = 0; j < n; ++j) {
    // [mid - rad, mid + rad] covers [a] in exact arithmetic.
    RC_ASSERT(Q(mid(j)) - Q(rad(j)) <= Q(a(j).lower()));
    RC_ASSERT(Q(mid(j)) + Q(rad(j)) >= Q(a(j).upper()));
    exact_volume *= Q(a(j).upper()) - Q(a(j).lower());
  }
  RC_ASSERT(Q(sets::volume(a)) >= exact_volume);
  const IntervalVector h = sets::hull(a, b);
  for (int j = 0; j < n; ++j) {
    RC_ASSERT(h(j).lower() == std::min(a(j).lower(), b(j).lower()));
    RC_ASSERT(h(j).upper() == std::max(a(j).upper(), b(j).upper()));
  }
  RC_ASSERT(sets::contains(a, sets::lower(a)));
  RC_ASSERT(sets::contains(a, sets::upper(a)));
}

TEST(IntervalMatrix, BoxBoundsAreChecked) {
  const Eigen::Vector2d lo(0, 1), hi(1, 2);
  const IntervalVector box = sets::make_box(lo, hi);
  EXPECT_EQ(box(1).lower(), 1.0);
  EXPECT_EQ(box(1).upper(), 2.0);
  EXPECT_THROW(sets::make_box(hi, lo), sets::InputError);
  EXPECT_THROW(sets::make_box(Eigen::Vector2d(0, std::nan("")), hi), sets::InputError);
  EXPECT_FALSE(sets::contains(box, Eigen::Vector2d(0.5, std::nextafter(2.0, 3.0))));
  EXPECT_TRUE(sets::contains(box, Eigen::Vector2d(0.0, 2.0)));
}

// The batched midpoint/radius (one rounding-mode switch per call) give the scalar functions'
// doubles bit for bit, whatever mode the caller is in, infinite ends included.
RC_GTEST_PROP(IntervalMatrix, BatchedMidpointAndRadiusEqualTheScalarOnes, (bool upward_caller)) {
  const int rows = *rc::gen::inRange(0, 5), cols = *rc::gen::inRange(0, 5);
  const double inf = std::numeric_limits<double>::infinity();
  IntervalMatrix A(rows, cols);
  for (Eigen::Index k = 0; k < A.size(); ++k) {
    const int kind = *rc::gen::inRange(0, 8);
    A(k) = kind == 0 ? Interval(-inf, *gen_double()) : kind == 1 ? Interval(*gen_double(), inf) : *gen_interval();
  }
  const IntervalVector v = A.reshaped();
  Eigen::MatrixXd mid, rad;
  Eigen::VectorXd vmid, vrad;
  if (upward_caller) {
    sets::RoundingScope upward;
    mid = sets::midpoint(A), rad = sets::radius(A), vmid = sets::midpoint(v), vrad = sets::radius(v);
  } else {
    mid = sets::midpoint(A), rad = sets::radius(A), vmid = sets::midpoint(v), vrad = sets::radius(v);
  }
  const auto same = [](double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; };
  for (Eigen::Index k = 0; k < A.size(); ++k) {
    RC_ASSERT(same(mid(k), sets::midpoint(A(k))));
    RC_ASSERT(same(rad(k), sets::radius(A(k))));
    RC_ASSERT(same(vmid(k), mid(k)));
    RC_ASSERT(same(vrad(k), rad(k)));
  }
  // 1/3 + 1/3: the radius of [1/3 rounded down, 1/3 rounded up] is rounded up, not to nearest.
  const Interval third = Interval(1.0) / Interval(3.0);
  const IntervalVector t = IntervalVector::Constant(1, third);
  RC_ASSERT(Q(sets::midpoint(t)(0)) - Q(sets::radius(t)(0)) <= Q(third.lower()));
  RC_ASSERT(Q(sets::midpoint(t)(0)) + Q(sets::radius(t)(0)) >= Q(third.upper()));
}
