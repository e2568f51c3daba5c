// Residual tests: a correct model with white noise is within the noise, and with coloured (AR(1))
// noise once the residual is whitened by the pole the noise estimate reads from it; a model that
// leaves Coulomb friction out is not, with either noise.

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "sets/data/noise_level.hpp"
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

// The same with the noise level and AR(1) pole estimated from the calibrated residual, as the
// diagnosis does (sets/data/noise_level.hpp); `estimate` receives the estimate.
ResidualTests tests_with_estimated_noise(const ModelFile& nominal, const Recording& data, NoiseLevelEstimate& estimate) {
  Simulator s(nominal, data, {10});
  const auto cal = calibrate(s, s.parameter_values(), s.free_parameters());
  const SimulationResult at = s.simulate(cal.parameters);
  Eigen::MatrixXd u(data.rows(), 1);
  const auto& col = data.column(nominal.inputs.at(0).second);
  u.col(0) = Eigen::Map<const Eigen::VectorXd>(col.data(), data.rows());
  estimate = estimate_noise(s.measured().col(0), at.outputs.col(0), u);
  return test_residual(s, cal.parameters, at, {estimate.sigma}, {estimate.ar_pole});
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

TEST(ResidualTests, CorrectModelWithColouredNoiseIsTheNoiseReadFromIt) {
  // Whitened by the AR(1) pole the noise estimate reads (from the band above the signal), the
  // residual of the correct model is white: nothing is missing (on the raw residual, above, not).
  // (A pole above the estimate's largest, 0.9, is read as 0.9: the whitened residual may then
  // stay coloured, "not white" as before.)
  const SyntheticPlant p = synthetic_plant("clean_axis");
  const double sigma = 3 * p.noise_sigma.at(0);
  for (double a : {0.5, 0.8}) {
    NoiseLevelEstimate e;
    const ResidualTests t = tests_with_estimated_noise(p.nominal, with_ar_noise(p, a, sigma, 5), e);
    EXPECT_EQ(e.method, NoiseMethod::residual_coloured) << "AR pole " << a << ": " << e.reason;
    EXPECT_NEAR(e.ar_pole, a, 0.05) << e.reason;
    EXPECT_TRUE(t.white) << "AR pole " << a << ": " << t.summary();
    EXPECT_TRUE(t.within_noise()) << "AR pole " << a << ": " << t.summary();
  }
}

TEST(ResidualTests, MissingCoulombFrictionInColouredNoiseIsNotWhitenedAway) {
  // The guard: the pole is read above the signal's band, so a missing effect's residual, which
  // lives in that band, stays in the whitened residual. With a noise level so large (20x the
  // plant's) that the bound cannot falsify the model, the whitened residual is still not white.
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  for (double a : {0.5, 0.8, 0.95}) {
    NoiseLevelEstimate e;
    const ResidualTests t = tests_with_estimated_noise(p.nominal, with_ar_noise(p, a, 20 * p.noise_sigma.at(0), 5), e);
    EXPECT_NEAR(e.ar_pole, std::min(a, 0.9), 0.05) << e.reason;  // the noise's pole, not bent by the friction
    EXPECT_FALSE(t.falsified) << "AR pole " << a << ": " << e.reason << "; " << t.summary();
    EXPECT_FALSE(t.white) << "AR pole " << a << ": " << e.reason << "; " << t.summary();
    EXPECT_FALSE(t.within_noise());
  }
}

TEST(ResidualTests, MissingCoulombFrictionIsNotWithinTheNoise) {
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  const ResidualTests t = calibrated_tests(p.nominal, p.estimation, p.noise_sigma.at(0));
  EXPECT_TRUE(t.falsified) << t.summary();
  EXPECT_FALSE(t.within_noise());
}

TEST(ResidualTests, IndependenceDecidesWhenTheResidualFollowsAModelSignal) {
  // The correct model driven by an input drawn afresh each sample, white noise, and a residual part
  // that follows |u| sample by sample (a size no parameter of the linear model can take up): small
  // beside the noise, so the residual stays inside the bound, white and without bursts, yet it
  // correlates with |u| far beyond the threshold, which noise does not. Without that part the
  // same record is within the noise (its size is the only change).
  const SyntheticPlant p = synthetic_plant("clean_axis");
  const int n = 8000;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> draw(-1, 1);
  Recording r;
  std::vector<double> t(n), u(n);
  for (int k = 0; k < n; ++k) t[static_cast<std::size_t>(k)] = 0.01 * k, u[static_cast<std::size_t>(k)] = draw(rng);
  r.add("t", t);
  r.add("u", u);
  r.add("x_meas", std::vector<double>(n, 0.0));
  Simulator truth(p.truth, r, {10});
  const Eigen::VectorXd y = truth.simulate(truth.parameter_values()).outputs.col(0);
  const double sigma = 0.01 * std::sqrt((y.array() - y.mean()).square().mean());
  const Eigen::VectorXd size = Eigen::Map<const Eigen::VectorXd>(u.data(), n).cwiseAbs();
  const Eigen::VectorXd part = (size.array() - size.mean()) / std::sqrt((size.array() - size.mean()).square().mean());
  std::normal_distribution<double> e(0, sigma);
  for (double share : {0.0, 0.15}) {  // std of the |u| part over sigma
    std::vector<double> m(n);
    for (int k = 0; k < n; ++k) m[static_cast<std::size_t>(k)] = y[k] + e(rng) + share * sigma * part[k];
    r.add("x_meas", m);
    const ResidualTests tests = calibrated_tests(p.nominal, r, sigma);
    EXPECT_FALSE(tests.falsified) << share << ": " << tests.summary();
    EXPECT_TRUE(tests.white) << share << ": " << tests.summary();
    EXPECT_FALSE(tests.bursty) << share << ": " << tests.summary();
    EXPECT_EQ(tests.follows_model_signals(), share > 0) << share << ": " << tests.summary();
    EXPECT_EQ(tests.within_noise(), share == 0) << share << ": " << tests.summary();
  }
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
