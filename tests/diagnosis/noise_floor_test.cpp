// The noise-floor stage of the diagnosis (src/diagnosis/noise_floor.cpp) on synthetic plants whose
// measurement noise is known: the estimate per output is within a factor 2 of the truth (the
// target of the diagnosis issue), it is recorded per output, and its cost is sigma^2 N / ||y - mean||^2.

#include <gtest/gtest.h>

#include "sets/data/simulation.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/examples/random_plants.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"
#include "support/plant_fixtures.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

TEST(NoiseFloor, EstimateIsWithinAFactorTwoOfTheKnownNoise) {
  for (const char* name : {"clean_axis", "coulomb_friction"}) {
    SCOPED_TRACE(name);
    const SyntheticPlant p = synthetic_plant(name);
    test::StageRun s(p);
    const NominalFit nominal = calibrate_nominal(s.c(), s.d);
    const NoiseFloor noise = noise_floor(s.c(), nominal, s.d);
    ASSERT_EQ(noise.sigma.size(), 1u);
    EXPECT_GT(noise.sigma[0], 0.5 * p.noise_sigma[0]);
    EXPECT_LT(noise.sigma[0], 2.0 * p.noise_sigma[0]);
    ASSERT_EQ(s.d.noise.size(), 1u);
    EXPECT_EQ(s.d.noise[0].output, "x_meas");
    EXPECT_EQ(s.d.noise[0].estimate.sigma, noise.sigma[0]);
    ASSERT_EQ(noise.pole.size(), 1u);  // the pole the residual tests whiten by: the estimate's
    EXPECT_EQ(s.d.noise[0].estimate.ar_pole, noise.pole[0]);
    EXPECT_TRUE(s.d.noise[0].record == "estimation" || s.d.noise[0].record == "validation") << s.d.noise[0].record;
    const Eigen::VectorXd y = s.exact->measured().col(0);
    const double spread = (y.array() - y.mean()).matrix().squaredNorm();
    EXPECT_NEAR(noise.cost, noise.sigma[0] * noise.sigma[0] * static_cast<double>(y.size()) / spread, 1e-12);
  }
}

TEST(NoiseFloor, WithoutAValidationRecordTheEstimationRecordIsUsed) {
  const SyntheticPlant p = synthetic_plant("clean_axis");
  test::StageRun s(p, false);
  const NominalFit nominal = calibrate_nominal(s.c(), s.d);
  const NoiseFloor noise = noise_floor(s.c(), nominal, s.d);
  ASSERT_EQ(s.d.noise.size(), 1u);
  EXPECT_EQ(s.d.noise[0].record, "estimation");
  EXPECT_GT(noise.sigma[0], 0.5 * p.noise_sigma[0]);
  EXPECT_LT(noise.sigma[0], 2.0 * p.noise_sigma[0]);
}

// A concealed effect left in the nominal's residual misleads the floor read from it (here a
// hysteresis the AR(1) shape mistakes for coloured noise, 26x the truth); the augmented model,
// which names and fits it, leaves the noise alone: the final estimate is within a factor 2. The
// rules keep the nominal's floor (d.noise); the final model's residual tests use the final
// estimate; the report gives both, each saying whose residual it is.
TEST(NoiseFloor, TheFinalEstimateIsReadFromTheAugmentedModelsResidual) {
  const SyntheticPlant p = random_plant(800029);  // development seed (docs/reproduction/diagnosis.md)
  const Diagnosis d = test::diagnosed(p);
  ASSERT_FALSE(d.effects.empty());
  ASSERT_EQ(d.noise.size(), 1u);
  ASSERT_EQ(d.noise_final.size(), 1u);
  const double truth = p.noise_sigma.at(0);
  EXPECT_GT(d.noise[0].estimate.sigma, 2 * truth);  // the premise: the nominal's reading is inflated
  EXPECT_EQ(d.noise_sigma.at(0), d.noise[0].estimate.sigma);  // the rules' floor is the nominal's
  EXPECT_EQ(d.noise[0].model, "nominal");
  EXPECT_EQ(d.noise_final[0].model, "augmented");
  EXPECT_GT(d.noise_final[0].estimate.sigma, 0.5 * truth) << d.noise_final[0].estimate.reason;
  EXPECT_LT(d.noise_final[0].estimate.sigma, 2.0 * truth) << d.noise_final[0].estimate.reason;
  // The augmented model is tested against the noise its own residual leaves, as the nominal is
  // against its own: the nominal's inflated floor gives a bound that a model still missing an
  // effect can pass.
  ASSERT_EQ(d.final_tests.bound.size(), 1u);
  ASSERT_EQ(d.nominal_tests.bound.size(), 1u);
  const double c_N = noise_bound_factor(p.estimation.rows());
  EXPECT_NEAR(d.final_tests.bound[0], c_N * d.noise_final[0].estimate.sigma, 1e-9 * d.final_tests.bound[0]);
  EXPECT_NEAR(d.nominal_tests.bound[0], c_N * d.noise[0].estimate.sigma, 1e-9 * d.nominal_tests.bound[0]);
  EXPECT_EQ(d.final_tests.whitened_by.at(0), d.noise_final[0].estimate.ar_pole);
  EXPECT_NE(d.verdict.find("noise read from"), std::string::npos) << d.verdict;
  const std::string json = diagnosis_json(d, "");
  EXPECT_NE(json.find("\"noise_level_final\""), std::string::npos);
  EXPECT_NE(json.find("\"model\": \"augmented\""), std::string::npos);
  EXPECT_NE(diagnosis_text(d).find("Noise level from the augmented model's residual"), std::string::npos);
}

TEST(NoiseFloor, WithoutANamedEffectTheFinalEstimateIsTheNominals) {
  const SyntheticPlant p = synthetic_plant("clean_axis");
  const Diagnosis d = test::diagnosed(p);
  ASSERT_TRUE(d.effects.empty());
  ASSERT_EQ(d.noise_final.size(), d.noise.size());
  for (std::size_t j = 0; j < d.noise.size(); ++j) {
    EXPECT_EQ(d.noise_final[j].estimate.sigma, d.noise[j].estimate.sigma);
    EXPECT_EQ(d.noise_final[j].model, "nominal");
  }
}

TEST(NoiseFloor, AQuantisedOutputsModelErrorIsNotReadAsNoiseBeyondTheQuantiser) {
  // Random plant 5 004 919 (a sampled PD position loop; the position quantised, the drive's
  // command with AR(1) noise; Stribeck friction in the truth, named right). The augmented model
  // below is the diagnosis' own (main d3b9b41), written out as it named it. Its low-frequency error
  // on the quantised position holds the AR(1) shape from 1/128 to 1/2 cycles/sample and was read as
  // a = 0.88 noise, 2.95x the truth, although the top band holds no more than the quantiser's own
  // white error: there is no noise beyond the quantisation to extrapolate. The level read is the
  // quantiser's; the residual's colour is kept for the residual tests to whiten by.
  const ModelFile augmented = parse_model(R"({
    "time": "t_x", "inputs": {"r": "ref_1"}, "intersample": {"r": "zoh"},
    "parameters": {"da": 0.6043219012804127, "visc": 5.12038227209221, "kf": 0.18090552849317065,
                   "kp2": 5811.21209430931, "kd7": 167.49182990604342, "Fc": 3.5894378540582346,
                   "Fs": 0.4352060605106425, "vs": 0.9338830274932476},
    "states": {"x": "pos", "qd2": 0.0},
    "sampled": {"nuv": "kp2*(r - x) - kd7*(x - prev(x, 1))/Ts"},
    "derivatives": {"x": "qd2", "qd2": "(kf*nuv - visc*qd2 - sign(qd2)*(Fc + Fs*exp(-(qd2/vs)^2)))/da"},
    "outputs": {"x": "pos", "nuv": "u_x"}})");
  const SyntheticPlant p = random_plant(5004919);
  for (const Recording* r : {&p.estimation, &p.validation}) {
    const Simulator s(augmented, *r);
    const Eigen::MatrixXd simulated = s.simulate(s.parameter_values()).outputs;
    const auto& ref = r->column("ref_1");
    const NoiseLevelEstimate e = estimate_noise(s.measured().col(0), simulated.col(0),
                                                Eigen::Map<const Eigen::VectorXd>(ref.data(), r->rows()));
    const double truth = r == &p.estimation ? p.noise_sigma[0] : p.noise_sigma_validation[0];
    ASSERT_GT(e.quantisation_step, 0);
    EXPECT_NEAR(e.sigma / truth, 1.0, 0.1) << e.reason;
    EXPECT_NE(e.reason.find("quantiser"), std::string::npos) << e.reason;
  }
}

// Random plant 5 007 815 (a position loop stepped a few times, its position seen through a sensor
// play and quantised; held out in the twenty-ninth range, development since): the recorded
// position changes 6 times in 2 791 samples, each time by several quantiser levels, so its lattice
// was not recognised, the augmented model reproduced the staircase exactly and the noise was read
// at 1e-14 of the truth. The level is now the quantiser's, within a factor 2, and the effect named
// is unchanged.
TEST(NoiseFloor, AQuantisedOutputThatStepsRarelyIsNotReadBelowItsQuantiser) {
  const SyntheticPlant p = random_plant(5007815);
  const Diagnosis d = test::diagnosed(p);
  ASSERT_EQ(d.effects.size(), 1u);
  EXPECT_EQ(d.effects[0].name, "hysteresis");
  ASSERT_EQ(d.noise_final.size(), 1u);
  const double truth = d.noise_final[0].record == "estimation" ? p.noise_sigma[0] : p.noise_sigma_validation[0];
  EXPECT_GT(d.noise_final[0].estimate.quantisation_step, 0);
  EXPECT_GT(d.noise_final[0].estimate.sigma, 0.5 * truth) << d.noise_final[0].estimate.reason;
  EXPECT_LT(d.noise_final[0].estimate.sigma, 2.0 * truth) << d.noise_final[0].estimate.reason;
}

// The floor is bounded by what a calibrated hypothesis leaves: an output whose least misfit is a
// quarter of the floor's own has its level halved (the misfit goes as sigma^2) and the note names
// it; one whose least misfit equals or exceeds the floor's, or that has no fit (negative), keeps
// its level and adds nothing to the note.
TEST(NoiseFloor, AFloorAboveWhatAFitLeavesIsLoweredToIt) {
  const SyntheticPlant p = random_plant(800029);  // one output; the test runs the floor twice
  test::StageRun s(p);
  const NominalFit nominal = calibrate_nominal(s.c(), s.d);
  const NoiseFloor floor = noise_floor(s.c(), nominal, s.d);
  ASSERT_EQ(floor.costs.size(), 1u);
  const NoiseFloor lowered = floor_within_fits(s.c(), floor, {0.25 * floor.costs[0]}, s.d.outputs);
  EXPECT_NEAR(lowered.sigma[0], 0.5 * floor.sigma[0], 1e-12 * floor.sigma[0]);
  EXPECT_NEAR(lowered.costs[0], 0.25 * floor.costs[0], 1e-9 * floor.costs[0]);
  EXPECT_LT(lowered.cost_validation, floor.cost_validation);
  EXPECT_NE(lowered.note.find(s.d.outputs[0]), std::string::npos) << lowered.note;
  for (double least : {floor.costs[0], 2 * floor.costs[0], -1.0}) {
    const NoiseFloor kept = floor_within_fits(s.c(), floor, {least}, s.d.outputs);
    EXPECT_EQ(kept.sigma[0], floor.sigma[0]);
    EXPECT_TRUE(kept.note.empty()) << kept.note;
  }
}

// Random plant 5 005 586 (development; an absolute-value sensor and a dead zone at the drive,
// quantised output): the floor read on the nominal (fit -61 %) is 31x the truth, and with the
// sensor named the dead zone removed 99.8 % of what was left and still failed the noise rule
// against it. A hypothesis that leaves less than the floor lowers it: both effects are named.
TEST(NoiseFloor, AnEffectHiddenByAFloorTheNominalInflatedIsNamedOnceAFitLeavesLess) {
  const SyntheticPlant p = random_plant(5005586);
  const Diagnosis d = test::diagnosed(p);
  ASSERT_EQ(d.effects.size(), 2u);
  EXPECT_EQ(d.effects[0].name, "absolute_value_sensor");
  EXPECT_EQ(d.effects[1].name, "dead_zone");
  EXPECT_NE(d.noise_note.find("floor lowered"), std::string::npos) << d.noise_note;
}
