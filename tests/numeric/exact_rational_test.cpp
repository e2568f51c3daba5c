// Exact rational arithmetic on double data (src/numeric/exact_rational.cpp): Gaussian elimination
// in GMP rationals gives the exact solution (not one rounded to doubles), says when the matrix is
// singular, and enclose() returns the tightest interval of doubles around a rational.

#include "numeric/exact_rational.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "support/random_matrices.hpp"

using sets::detail::enclose;
using sets::detail::Rational;
using sets::detail::solve_exact;

namespace {

// The interval [lo, hi] holds q exactly (compared in rationals, not in doubles).
bool holds(const sets::Interval& I, const Rational& q) {
  return (std::isinf(I.lower()) || Rational(I.lower()) <= q) && (std::isinf(I.upper()) || q <= Rational(I.upper()));
}

}  // namespace

TEST(ExactRational, SolvesASmallSystemExactly) {
  // [2 1; 1 3] x = [3; 5]  ->  x = [4/5; 7/5], which no double holds.
  std::vector<Rational> x;
  ASSERT_TRUE(solve_exact({2, 1, 1, 3}, {3, 5}, 2, x));
  ASSERT_EQ(x.size(), 2u);
  EXPECT_EQ(x[0], Rational(4, 5));
  EXPECT_EQ(x[1], Rational(7, 5));
}

TEST(ExactRational, PivotsPastAZeroAndReportsSingularMatrices) {
  std::vector<Rational> x;
  // A zero in the corner needs a row swap: [0 1; 1 0] x = [2; 3] -> x = [3; 2].
  ASSERT_TRUE(solve_exact({0, 1, 1, 0}, {2, 3}, 2, x));
  EXPECT_EQ(x[0], Rational(3));
  EXPECT_EQ(x[1], Rational(2));
  // 2 * double(0.1) == double(0.2) exactly (a power-of-two scaling): singular.
  EXPECT_FALSE(solve_exact({0.1, 0.2, 0.2, 0.4}, {1, 2}, 2, x));
  // (0.1, 0.3) and (0.3, 0.9): 3 * double(0.1) != double(0.3), so the exact matrix is regular
  // although floating-point elimination calls it singular.
  EXPECT_TRUE(solve_exact({0.1, 0.3, 0.3, 0.9}, {1, 2}, 2, x));
  EXPECT_FALSE(solve_exact({1, 2, 3, 2, 4, 6, 0, 1, 1}, {1, 2, 3}, 3, x));  // row 2 = 2 * row 1
}

RC_GTEST_PROP(ExactRational, SolutionOfARandomSystemIsTheExactOne, ()) {
  // b = M x computed in rationals from double M and x: solve_exact must give x back exactly.
  const int n = *rc::gen::inRange(1, 6);
  sets::test::Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Eigen::MatrixXd M = r.mat(n, n) * std::pow(10.0, r.u(-3, 3));
  const Eigen::VectorXd xd = r.mat(n, 1) * std::pow(10.0, r.u(-3, 3));
  std::vector<Rational> Mq, b(static_cast<std::size_t>(n), Rational(0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Mq.emplace_back(M(i, j));
      b[static_cast<std::size_t>(i)] += Rational(M(i, j)) * Rational(xd[j]);
    }
  std::vector<Rational> x;
  RC_ASSERT(solve_exact(Mq, b, n, x));  // random doubles: regular with probability 1
  for (int j = 0; j < n; ++j) RC_ASSERT(x[static_cast<std::size_t>(j)] == Rational(xd[j]));
}

TEST(ExactRational, EncloseIsTheTightestIntervalOfDoubles) {
  // A double encloses as itself.
  const sets::Interval e = enclose(Rational(0.1));
  EXPECT_EQ(e.lower(), 0.1);
  EXPECT_EQ(e.upper(), 0.1);
  // 1/3 and -1/3: a one-ulp interval holding it.
  for (const Rational& q : {Rational(1, 3), Rational(-1, 3), Rational(Rational(2, 7) * Rational(1e-300))}) {
    const sets::Interval I = enclose(q);
    EXPECT_TRUE(holds(I, q)) << q.get_str();
    EXPECT_LT(I.lower(), I.upper()) << q.get_str();
    EXPECT_EQ(std::nextafter(I.lower(), std::numeric_limits<double>::infinity()), I.upper()) << q.get_str();
  }
  // Beyond the largest double: [max, +inf] (and its mirror).
  const Rational huge = Rational(std::numeric_limits<double>::max()) * 4;
  const sets::Interval H = enclose(huge), N = enclose(-huge);
  EXPECT_TRUE(holds(H, huge));
  EXPECT_TRUE(std::isinf(H.upper()));
  EXPECT_EQ(H.lower(), std::numeric_limits<double>::max());
  EXPECT_TRUE(holds(N, -huge));
  EXPECT_TRUE(std::isinf(N.lower()));
}

RC_GTEST_PROP(ExactRational, EncloseHoldsEveryQuotientOfTwoDoubles, ()) {
  sets::test::Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const double a = r.u(-1e6, 1e6), b = r.u(0.001, 1e3);
  const Rational q = Rational(a) / Rational(b);
  const sets::Interval I = enclose(q);
  RC_ASSERT(holds(I, q));
  RC_ASSERT(I.upper() == I.lower() || std::nextafter(I.lower(), std::numeric_limits<double>::infinity()) == I.upper());
}
