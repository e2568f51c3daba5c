// Tests of hinf_bound (Hakvoort-Van den Hof), step 3, the frequency weight W fitted above the additive error:
// src/methods/hinf_bound/weight_fit.cpp.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Dense>

#include <cmath>

#include "sets/methods/hinf_bound/hinf_bound.hpp"
#include "support/hinf_fixtures.hpp"

using namespace sets;
using namespace sets::testing;

RC_GTEST_PROP(HinfWeight, InverseWeightIsMinimumPhaseAndAboveDelta, ()) {
  const int n = *rc::gen::inRange(10, 60);
  const Eigen::VectorXd grid = uniform_grid(n);
  Eigen::VectorXd delta(n);
  const double peak = *rc::gen::inRange(1, 30) / 10.0, centre = *rc::gen::inRange(1, 30) / 10.0;
  for (int j = 0; j < n; ++j) delta[j] = 0.05 + peak / (1 + 20 * std::pow(grid[j] - centre, 2));
  WeightOptions o;
  o.degree = *rc::gen::inRange(2, 16);
  const WeightFit W = fit_weight(grid, delta, o);
  for (int j = 0; j < n; ++j) RC_ASSERT(std::abs(W.inverse(grid[j])) >= delta[j]);
  // Minimum phase: the zeros of h(z) = sum h_k z^-k lie inside the unit circle.
  TransferFunction Hinv;
  Hinv.a = W.h / W.h[0];
  Hinv.b = Eigen::VectorXd::Ones(1);
  RC_ASSERT(Hinv.stable());
}

// N = 500, the 15th data set: the first LP solution for |W^-1|^2 dipped below zero between its
// 2048 floor rows ("not certified positive", the run failed). The cutting planes add the dips as
// rows; the weight is then certified positive on all of [0, pi].
TEST(HinfWeight, StaysPositiveBetweenTheLpRows) {
  TransferFunction G0;
  expect_a_valid_weight(app_example_run(500, 15, G0), G0);
}

// N = 1 000, the 28th data set: GLPK failed on the unscaled LP (delta in [0.02, 0.78], rows up to
// 1/delta^2); with the variables in units of max delta^2 it solves.
TEST(HinfWeight, LpInUnitsOfTheLargestDelta) {
  TransferFunction G0;
  expect_a_valid_weight(app_example_run(1000, 28, G0), G0);
}
