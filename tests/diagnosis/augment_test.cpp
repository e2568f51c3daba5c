// The augment stage of the diagnosis (src/diagnosis/augment.cpp) on the Coulomb-friction plant: the
// augmented model fits better than the nominal on both records, the friction level's bounded-error
// interval holds the plant's true value (0.3) and its estimate, and its parts (output error,
// statistical) are ordered; and the global step over the effects' parameters on a plant whose
// search stops in a local optimum.

#include <gtest/gtest.h>

#include "sets/diagnosis/residual_tests.hpp"
#include "sets/examples/diagnosis_suite.hpp"
#include "sets/examples/random_plants.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

TEST(Augment, CoulombPlantFitsBetterAndTheIntervalHoldsTheTrueFrictionLevel) {
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  test::StageRun s(p, true, 1500);
  s.options.max_effects = 1;
  s.options.refine = 1;
  s.options.varying_segments = 10;
  const NominalFit nominal = calibrate_nominal(s.c(), s.d);
  const NoiseFloor noise = noise_floor(s.c(), nominal, s.d);
  s.d.nominal_tests = test_residual(*s.exact, nominal.calibration.parameters, nominal.simulation, noise.sigma);
  const HypothesisSearch h = search_hypotheses(s.c(), nominal, noise, s.d);
  ASSERT_EQ(s.d.effects.size(), 1u);
  augment(s.c(), nominal, h, s.d);
  const Diagnosis& d = s.d;
  ASSERT_EQ(d.fit_augmented_estimation.size(), 1u);
  ASSERT_EQ(d.fit_augmented_validation.size(), 1u);
  EXPECT_GT(d.fit_augmented_estimation[0], d.fit_nominal_estimation[0]);
  EXPECT_GT(d.fit_augmented_validation[0], d.fit_nominal_validation[0]);
  ASSERT_NE(d.augmented.parameter("Fc"), nullptr) << "the augmented model names the friction level";
  ASSERT_EQ(d.effects[0].parameters.size(), 1u);
  const EffectParameter& fc = d.effects[0].parameters[0];
  EXPECT_EQ(fc.role, "Fc");
  EXPECT_EQ(d.augmented.parameter(fc.name)->value, fc.estimate);
  EXPECT_LE(fc.lo, 0.3);
  EXPECT_GE(fc.hi, 0.3);
  EXPECT_LE(fc.lo, fc.estimate);
  EXPECT_GE(fc.hi, fc.estimate);
  EXPECT_LE(fc.oe_lo, fc.oe_hi);
  EXPECT_LE(fc.stat_lo, fc.stat_hi);
  ASSERT_EQ(fc.oe_delta.size(), 1u);
  EXPECT_GT(fc.oe_delta[0], 0.0);
  // The reported interval lies inside the output-error one (it is that one, or its intersection
  // with the equation-error one).
  EXPECT_GE(fc.lo, fc.oe_lo);
  EXPECT_LE(fc.hi, fc.oe_hi);
}

// The global step over the effects' parameters (augment.cpp), on development plant 800 015
// (Coulomb friction in the force balance and a dead zone on the drive, two threshold laws that
// trade off): the search stops in a local optimum where the output-error PUIs, linearised there
// and the only intervals (no equation-error PUI on this plant), leave out both true values. With
// the step the true values are inside; without it (global_step_starts = 0) they are not.
TEST(Augment, GlobalStepOverTheEffectsParametersPutsTheTrueValuesInsideTheIntervals) {
  const SyntheticPlant p = random_plant(800015);
  auto run = [&](int starts) {
    DiagnosisOptions o;
    o.threads = 1;  // as the suite runs each plant
    o.global_step_starts = starts;
    return run_suite_plant(p, o);
  };
  const SuitePlantResult without = run(0), with = run(2);
  ASSERT_TRUE(without.error.empty()) << without.error;
  ASSERT_TRUE(with.error.empty()) << with.error;
  ASSERT_EQ(with.coverage.size(), 2u);
  int outside_without = 0;
  for (const auto& c : without.coverage) outside_without += !c.inside;
  EXPECT_GT(outside_without, 0) << "the plant no longer shows the local optimum this test is about";
  for (const auto& c : with.coverage)
    EXPECT_TRUE(c.inside) << c.effect << " " << c.role << ": true " << c.truth << " not in [" << c.lo << ", " << c.hi << "]";
}
