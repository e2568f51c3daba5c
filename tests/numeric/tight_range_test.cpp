// Tight ranges of univariate functions: every sampled value lies in the computed range, and the
// range's ends are within the tolerance (plus the sampling grid's own error) of the sampled extremes.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <vector>

#include "sets/core/error.hpp"
#include "sets/numeric/tight_range.hpp"

namespace {

using sets::Interval;
using sets::UnivariateFunction;

struct GridExtremes {
  double min, max;
};

// Values on a uniform grid (ends included). The true extremum differs from the grid's by at most
// M2 h^2 / 8 (interior extremum, f' = 0 there) and not at all at an end.
GridExtremes grid(const std::function<double(double)>& f, double a, double b, int n) {
  GridExtremes g{INFINITY, -INFINITY};
  for (int i = 0; i <= n; ++i) {
    const double x = i == n ? b : a + (b - a) * i / n;
    g.min = std::min(g.min, f(x));
    g.max = std::max(g.max, f(x));
  }
  return g;
}

std::vector<double> random_coefficients() {
  const int degree = *rc::gen::inRange(0, 6);
  std::vector<double> c;
  for (int k = 0; k <= degree; ++k) c.push_back(*rc::gen::inRange(-2000, 2001) / 1000.0);
  return c;
}

}  // namespace

RC_GTEST_PROP(TightRange, PolynomialRangeContainsSamplesAndIsTight, ()) {
  const std::vector<double> c = random_coefficients();
  const double a = *rc::gen::inRange(-3000, 3000) / 1000.0;
  const double b = a + *rc::gen::inRange(0, 3000) / 1000.0;
  const auto f = UnivariateFunction::polynomial(c);
  const auto r = f.range(Interval(a, b));
  RC_ASSERT(r.tight);
  const int n = 20000;
  const GridExtremes g = grid([&](double x) { return f(x); }, a, b, n);
  // |f''| <= sum k(k-1)|c_k| R^(k-2) on [a, b].
  const double R = std::max(std::abs(a), std::abs(b));
  double m2 = 0;
  for (std::size_t k = 2; k < c.size(); ++k) m2 += k * (k - 1) * std::abs(c[k]) * std::pow(R, k - 2.0);
  const double h = (b - a) / n, grid_err = m2 * h * h / 8;
  const double fuzz = 1e-9 * (1 + std::abs(g.min) + std::abs(g.max));  // float evaluation of the samples
  RC_ASSERT(r.range.lower() <= g.min + fuzz);
  RC_ASSERT(r.range.upper() >= g.max - fuzz);
  RC_ASSERT(r.range.lower() >= g.min - grid_err - 1e-9 * std::max(1.0, std::abs(g.min)) - fuzz);
  RC_ASSERT(r.range.upper() <= g.max + grid_err + 1e-9 * std::max(1.0, std::abs(g.max)) + fuzz);
  // Every sample, including random interior points, lies inside.
  for (int i = 0; i < 50; ++i) {
    const double x = a + (b - a) * *rc::gen::inRange(0, 1001) / 1000.0;
    const Interval v = f.extension(Interval(x));
    RC_ASSERT(v.lower() >= r.range.lower() - fuzz && v.upper() <= r.range.upper() + fuzz);
  }
}

RC_GTEST_PROP(TightRange, GeneralFunctionByBranchAndBoundIsTight, ()) {
  // f(x) = sin(k x) + q x^2, given only as value + extension (+ derivative when `with_derivative`).
  const double k = *rc::gen::inRange(1, 8);
  const double q = *rc::gen::inRange(-1000, 1001) / 1000.0;
  const bool with_derivative = *rc::gen::arbitrary<bool>();
  const double a = *rc::gen::inRange(-3000, 3000) / 1000.0;
  const double b = a + *rc::gen::inRange(1, 3000) / 1000.0;
  auto value = [=](double x) { return std::sin(k * x) + q * x * x; };
  auto ext = [=](const Interval& x) { return boost::numeric::sin(Interval(k) * x) + Interval(q) * sets::pow(x, 2); };
  sets::IntervalFunction der;
  if (with_derivative)
    der = [=](const Interval& x) { return Interval(k) * boost::numeric::cos(Interval(k) * x) + Interval(2 * q) * x; };
  const auto f = UnivariateFunction::general("f", value, ext, der);
  const sets::RangeOptions opt{1e-7, 1 << 16};
  const auto r = f.range(Interval(a, b), opt);
  RC_ASSERT(r.tight);
  const int n = 20000;
  const GridExtremes g = grid(value, a, b, n);
  const double h = (b - a) / n, grid_err = (k * k + 2 * std::abs(q)) * h * h / 8;
  RC_ASSERT(r.range.lower() <= g.min + 1e-12);
  RC_ASSERT(r.range.upper() >= g.max - 1e-12);
  RC_ASSERT(r.range.lower() >= g.min - grid_err - 1e-7 * std::max(1.0, std::abs(g.min)) - 1e-12);
  RC_ASSERT(r.range.upper() <= g.max + grid_err + 1e-7 * std::max(1.0, std::abs(g.max)) + 1e-12);
}

TEST(TightRange, SquareOfAnIntervalContainingZeroStartsAtZero) {
  // Cerone–Regruto eqs. 23–24 with f = lambda^2: the interval square, not [-ab, ..].
  const auto sq = UnivariateFunction::monomial(2);
  const auto r = sq.range(Interval(-0.5, 1.0)).range;
  EXPECT_EQ(r.lower(), 0.0);
  EXPECT_EQ(r.upper(), 1.0);
  const auto r2 = sq.range(Interval(-1.0, -0.5)).range;
  EXPECT_EQ(r2.lower(), 0.25);
  EXPECT_EQ(r2.upper(), 1.0);
  // x^2 - 2x over [0, 2] is [-1, 0]; Horner's natural extension gives [-4, 4].
  const auto p = UnivariateFunction::polynomial({0, -2, 1});
  const auto rp = p.range(Interval(0, 2)).range;
  EXPECT_NEAR(rp.lower(), -1.0, 1e-15);
  EXPECT_NEAR(rp.upper(), 0.0, 1e-15);
  EXPECT_LE(rp.lower(), -1.0);
  EXPECT_GE(rp.upper(), 0.0);
  EXPECT_LT(p.extension(Interval(0, 2)).lower(), -1.5);  // the natural extension really is loose
}

TEST(TightRange, CubicWithTwoInteriorExtremaViaBranchAndBound) {
  // x^3 - x on [-1, 1]: extrema +-2/(3 sqrt 3) at x = -+1/sqrt 3.
  const auto p = UnivariateFunction::polynomial({0, -1, 0, 1});
  const auto r = p.range(Interval(-1, 1), {1e-12, 4096});
  const double e = 2 / (3 * std::sqrt(3.0));
  EXPECT_TRUE(r.tight);
  EXPECT_LE(r.range.lower(), -e);
  EXPECT_GE(r.range.upper(), e);
  EXPECT_NEAR(r.range.lower(), -e, 1e-11);
  EXPECT_NEAR(r.range.upper(), e, 1e-11);
}

TEST(TightRange, BuiltinsAndMonotoneUserFunctions) {
  const auto s = UnivariateFunction::builtin("sin");
  const auto r = s.range(Interval(1, 2)).range;
  EXPECT_LE(r.lower(), std::sin(1.0));
  EXPECT_NEAR(r.lower(), std::sin(1.0), 1e-9);
  EXPECT_GE(r.upper(), 1.0);
  EXPECT_NEAR(r.upper(), 1.0, 1e-9);
  const auto cube_root = UnivariateFunction::monotone(
      "cbrt", [](double x) { return std::cbrt(x); },
      [](const Interval& x) {
        return Interval(sets::detail::step_down(std::cbrt(x.lower())), sets::detail::step_up(std::cbrt(x.upper())));
      },
      true);
  const auto rc = cube_root.range(Interval(-8, 27)).range;
  EXPECT_LE(rc.lower(), -2.0);
  EXPECT_GE(rc.upper(), 3.0);
  EXPECT_NEAR(rc.lower(), -2.0, 1e-14);
  EXPECT_NEAR(rc.upper(), 3.0, 1e-14);
  EXPECT_THROW(UnivariateFunction::builtin("gamma"), sets::InputError);
}

TEST(TightRange, ExhaustedBudgetStillEncloses) {
  // x (1 - x) on [0, 1] without a derivative and a budget of 4 pieces: not tight, still an enclosure.
  auto ext = [](const Interval& x) { return x * (Interval(1.0) - x); };
  const auto r = sets::branch_and_bound_range(ext, {}, Interval(0, 1), {1e-12, 4});
  EXPECT_FALSE(r.tight);
  EXPECT_LE(r.range.lower(), 0.0);
  EXPECT_GE(r.range.upper(), 0.25);
  const auto tight = sets::branch_and_bound_range(ext, {}, Interval(0, 1), {1e-6, 1 << 20});
  EXPECT_TRUE(tight.tight);
  EXPECT_NEAR(tight.range.upper(), 0.25, 1e-5);
  EXPECT_GE(tight.range.upper(), 0.25);
}
