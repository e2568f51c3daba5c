// The augment stage of the diagnosis (src/diagnosis/augment.cpp) on the Coulomb-friction plant: the
// augmented model fits better than the nominal on both records, the friction level's bounded-error
// interval holds the plant's true value (0.3) and its estimate, and its parts (output error,
// statistical) are ordered.

#include <gtest/gtest.h>

#include "sets/diagnosis/residual_tests.hpp"
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
