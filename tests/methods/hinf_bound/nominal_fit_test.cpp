// Tests of hinf_bound (Hakvoort-Van den Hof), step 2, the nominal model fitted to the regions:
// src/methods/hinf_bound/nominal_fit.cpp.

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

#include "sets/core/error.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"
#include "support/hinf_fixtures.hpp"

using namespace sets;
using namespace sets::testing;

TEST(HinfInput, NominalOrderThatCannotBeMetIsRejected) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd u(400);
  for (auto& x : u) x = U(rng);
  const FirstOrderSum G{{0.5}, {0.5}};
  const Eigen::VectorXd y = G.simulate(u);
  HinfPriors p;
  p.M = 1;
  p.rho = 0.6;
  const UncertaintySet S = uncertainty_set(u, y, OrthonormalBasis::fir(), 8, uniform_grid(5), p);
  NominalOptions o;
  o.order = 5;  // 11 coefficients, 10 real equations
  EXPECT_THROW(fit_nominal(S, o), InputError);
  o.order = -1;
  EXPECT_THROW(fit_nominal(S, o), InputError);
  o.order = 2;
  o.polygon_sides = 2;
  EXPECT_THROW(fit_nominal(S, o), InputError);
}

TEST(HinfNominal, RecoversAStableSecondOrderModelFromExactCentres) {
  TransferFunction G;
  G.b = Eigen::Vector3d(0, 0.3, 0.1);
  G.a = Eigen::Vector3d(1, -1.5, 0.8);
  UncertaintySet S;
  S.frequencies = uniform_grid(120);
  for (double w : S.frequencies) {
    FrequencyRegion P;
    P.centre = G(w);
    P.half_re = P.half_im = 0.01;
    S.regions.push_back(P);
  }
  const NominalFit f = fit_nominal(S);
  EXPECT_TRUE(f.model.stable());
  EXPECT_EQ(f.polygon_sides, 16);
  EXPECT_LT(f.max_error, 1e-3);
  EXPECT_NEAR(f.model.a[1], -1.5, 1e-3);
  EXPECT_NEAR(f.model.a[2], 0.8, 1e-3);
}

TEST(HinfNominal, StaysStableWhenTheDataLookUnstable) {
  // Centres of an unstable system 1/(1 - 1.2 z^-1): the best stable fit must still be stable.
  UncertaintySet S;
  S.frequencies = uniform_grid(60);
  for (double w : S.frequencies) {
    FrequencyRegion P;
    P.centre = 1.0 / (1.0 - 1.2 * std::polar(1.0, -w));
    S.regions.push_back(P);
  }
  NominalOptions o;
  o.order = 1;
  const NominalFit f = fit_nominal(S, o);
  EXPECT_TRUE(f.model.stable());
}
