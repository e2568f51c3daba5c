// Neumaier–Shcherbina safe bounds. A multiplier with the wrong sign for a one-sided row (solver
// noise) must not turn the bound into -inf: any multipliers give a valid bound, so that row is dropped.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpq.h>

#include <cmath>

#include "sets/numeric/safe_bound.hpp"

TEST(SafeBoundSign, WrongSignMultiplierOnOneSidedRowIsIgnored) {
  // min x  s.t.  x >= 1 (row 0),  x <= 5 (row 1),  0 <= x <= 10.  Optimum 1.
  sets::LpRows rows;
  rows.entries = {{{0, 1.0}}, {{0, 1.0}}};
  rows.lo = {1.0, -INFINITY};
  rows.hi = {INFINITY, 5.0};
  const Eigen::VectorXd c = Eigen::VectorXd::Ones(1);
  const Eigen::VectorXd lo = Eigen::VectorXd::Zero(1), hi = Eigen::VectorXd::Constant(1, 10.0);
  const double exact = sets::safe_lower_bound(c, rows, lo, hi, Eigen::Vector2d(1.0, 0.0));
  EXPECT_EQ(exact, 1.0);
  // Row 1 is x <= 5: for a lower bound its multiplier must be <= 0; +1e-18 is noise.
  const double noisy = sets::safe_lower_bound(c, rows, lo, hi, Eigen::Vector2d(1.0, 1e-18));
  EXPECT_EQ(noisy, 1.0);
  // Still a bound for any multipliers: a bad y gives a weaker but valid bound.
  const double weak = sets::safe_lower_bound(c, rows, lo, hi, Eigen::Vector2d(0.5, 0.0));
  EXPECT_LE(weak, 1.0);
  EXPECT_EQ(weak, 0.5);  // 0.5 * 1 + inf((1 - 0.5) * [0, 10]) = 0.5
}

// The bound holds for ANY multipliers, so a random y must never exceed the objective at a feasible
// point, compared in exact rationals. The LP is built around a known feasible point x0, with rows
// and columns of very different scales, one-sided and free rows.
namespace {

rc::Gen<double> gen_scaled() {
  return rc::gen::map(rc::gen::pair(rc::gen::inRange(-1000000, 1000000), rc::gen::inRange(-20, 20)),
                      [](std::pair<int, int> m) { return std::ldexp(m.first / 997.0, m.second); });
}

}  // namespace

RC_GTEST_PROP(SafeBound, AnyMultipliersBoundTheObjectiveAtEveryFeasiblePoint, ()) {
  using Q = CGAL::Gmpq;
  const int n = *rc::gen::inRange(1, 6), m = *rc::gen::inRange(0, 6);
  Eigen::VectorXd x0(n), col_lo(n), col_hi(n), c(n), y(m);
  for (int j = 0; j < n; ++j) {
    x0(j) = *gen_scaled();
    const double a = std::abs(*gen_scaled()), b = std::abs(*gen_scaled());
    const bool free_below = *rc::gen::inRange(0, 6) == 0, free_above = *rc::gen::inRange(0, 6) == 0;
    col_lo(j) = free_below ? -INFINITY : x0(j) - a;
    col_hi(j) = free_above ? INFINITY : x0(j) + b;
    if (col_lo(j) > x0(j)) col_lo(j) = x0(j);  // rounding of x0 - a
    if (col_hi(j) < x0(j)) col_hi(j) = x0(j);
    c(j) = *gen_scaled();
  }
  sets::LpRows rows;
  for (int i = 0; i < m; ++i) {
    std::vector<std::pair<int, double>> row;
    Q ax(0);
    for (int j = 0; j < n; ++j)
      if (*rc::gen::inRange(0, 3) != 0) {
        row.emplace_back(j, *gen_scaled());
        ax += Q(row.back().second) * Q(x0(j));
      }
    // Row bounds that contain A x0 exactly (nextafter steps past the rounded value).
    const double v = CGAL::to_double(ax);
    double lo = std::nextafter(v, -INFINITY), hi = std::nextafter(v, INFINITY);
    while (Q(lo) > ax) lo = std::nextafter(lo, -INFINITY);
    while (Q(hi) < ax) hi = std::nextafter(hi, INFINITY);
    const int kind = *rc::gen::inRange(0, 4);
    rows.entries.push_back(row);
    rows.lo.push_back(kind == 1 ? -INFINITY : lo - std::abs(*gen_scaled()));
    rows.hi.push_back(kind == 2 ? INFINITY : hi + std::abs(*gen_scaled()));
    y(i) = *gen_scaled();
  }
  Q objective(0);
  for (int j = 0; j < n; ++j) objective += Q(c(j)) * Q(x0(j));
  const double lower = sets::safe_lower_bound(c, rows, col_lo, col_hi, y);
  const double upper = sets::safe_upper_bound(c, rows, col_lo, col_hi, y);
  RC_ASSERT(!std::isnan(lower));
  RC_ASSERT(!std::isnan(upper));
  if (std::isfinite(lower)) RC_ASSERT(Q(lower) <= objective);
  if (std::isfinite(upper)) RC_ASSERT(Q(upper) >= objective);
  RC_ASSERT(lower <= upper);
}
