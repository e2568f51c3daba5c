// A multiplier with the wrong sign for a one-sided row (solver noise) must not turn the
// Neumaier–Shcherbina bound into -inf: any multipliers give a valid bound, so that row is dropped.

#include <gtest/gtest.h>

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
