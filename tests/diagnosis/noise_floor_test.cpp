// The noise-floor stage of the diagnosis (src/diagnosis/noise_floor.cpp) on synthetic plants whose
// measurement noise is known: the estimate per output is within a factor 2 of the truth (the
// target of the diagnosis issue), it is recorded per output, and its cost is sigma^2 N / ||y - mean||^2.

#include <gtest/gtest.h>

#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"

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
