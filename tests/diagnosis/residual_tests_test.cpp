// Residual tests: a correct model with white or coloured (AR(1)) noise is within the noise; a
// model that leaves Coulomb friction out is not.

#include <gtest/gtest.h>

#include <random>

#include "sets/data/simulation.hpp"
#include "sets/diagnosis/calibration.hpp"
#include "sets/diagnosis/residual_tests.hpp"
#include "sets/examples/synthetic_plants.hpp"

using namespace sets;

namespace {

// The nominal calibrated on `data`, and its residual tests with noise level `sigma`.
ResidualTests calibrated_tests(const ModelFile& nominal, const Recording& data, double sigma) {
  Simulator s(nominal, data, {10});
  const auto cal = calibrate(s, s.parameter_values(), s.free_parameters());
  return test_residual(s, cal.parameters, s.simulate(cal.parameters), {sigma});
}

// The clean axis' estimation record with its noise replaced by AR(1) noise of pole a, marginal std sigma.
Recording with_ar_noise(const SyntheticPlant& p, double a, double sigma, unsigned seed) {
  Simulator truth(p.truth, p.estimation, {10});
  const Eigen::VectorXd y = truth.simulate(truth.parameter_values()).outputs.col(0);
  std::mt19937 rng(seed);
  std::normal_distribution<double> e(0, 1);
  std::vector<double> m(static_cast<std::size_t>(y.size()));
  double w = 0;
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    w = a * w + std::sqrt(1 - a * a) * sigma * e(rng);
    m[static_cast<std::size_t>(k)] = y[k] + w;
  }
  Recording r = p.estimation;
  r.add("x_meas", m);
  return r;
}

}  // namespace

TEST(ResidualTests, CorrectModelWithWhiteNoiseIsWithinTheNoise) {
  const SyntheticPlant p = synthetic_plant("clean_axis");
  const ResidualTests t = calibrated_tests(p.nominal, p.estimation, p.noise_sigma.at(0));
  EXPECT_FALSE(t.falsified) << t.summary();
  EXPECT_TRUE(t.independent) << t.summary();
  EXPECT_TRUE(t.within_noise());
}

TEST(ResidualTests, CorrectModelWithColouredNoiseIsInsideTheBoundButNotWhite) {
  // What the diagnosis can and cannot say: coloured noise is inside the bound and independent of
  // the model's signals, but not white, so "nothing is missing" is not claimed.
  const SyntheticPlant p = synthetic_plant("clean_axis");
  const double sigma = 3 * p.noise_sigma.at(0);
  for (double a : {0.8, 0.95}) {
    const ResidualTests t = calibrated_tests(p.nominal, with_ar_noise(p, a, sigma, 5), sigma);
    EXPECT_FALSE(t.falsified) << "AR pole " << a << ": " << t.summary();
    EXPECT_TRUE(t.independent) << "AR pole " << a << ": " << t.summary();
    EXPECT_FALSE(t.white) << "AR pole " << a << ": " << t.summary();
    EXPECT_FALSE(t.within_noise());
  }
}

TEST(ResidualTests, MissingCoulombFrictionIsNotWithinTheNoise) {
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  const ResidualTests t = calibrated_tests(p.nominal, p.estimation, p.noise_sigma.at(0));
  EXPECT_TRUE(t.falsified) << t.summary();
  EXPECT_FALSE(t.within_noise());
}

TEST(ResidualTests, WhitenessAloneCatchesASystematicResidual) {
  // With a noise level so large that the bound cannot falsify it, the residual of the Coulomb
  // plant is still far from white.
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  const ResidualTests t = calibrated_tests(p.nominal, p.estimation, 100 * p.noise_sigma.at(0));
  EXPECT_FALSE(t.falsified);
  EXPECT_FALSE(t.white) << t.summary();
  EXPECT_FALSE(t.within_noise());
}
