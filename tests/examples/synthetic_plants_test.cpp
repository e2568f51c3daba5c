// The synthetic plants of the diagnosis suite (src/examples/synthetic_plants.cpp): deterministic,
// one per catalogue entry plus clean ones, the effect in the truth and not in the nominal, noise of
// 1 % of the output's spread, two different records.

#include "sets/examples/synthetic_plants.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "sets/core/error.hpp"
#include "sets/data/simulation.hpp"
#include "support/messages.hpp"

using namespace sets;

TEST(SyntheticPlants, SameNameSamePlantAndUnknownNamesAreNamed) {
  const SyntheticPlant a = synthetic_plant("coulomb_friction"), b = synthetic_plant("coulomb_friction");
  EXPECT_EQ(a.estimation.columns, b.estimation.columns);
  EXPECT_EQ(a.validation.columns, b.validation.columns);
  EXPECT_NE(a.estimation.columns, a.validation.columns);  // another seed
  const std::string m = test::input_error_of([] { synthetic_plant("warp_drive"); });
  EXPECT_TRUE(test::contains(m, "warp_drive")) << m;
}

TEST(SyntheticPlants, EveryNameIsAPlantWithItsEffectOnlyInTheTruth) {
  const auto names = synthetic_plant_names();
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  for (const auto& name : names) {
    SCOPED_TRACE(name);
    const SyntheticPlant p = synthetic_plant(name);
    const bool clean = name.rfind("clean", 0) == 0;
    EXPECT_EQ(p.true_effect, clean ? "none" : name);
    EXPECT_EQ(p.effects.empty(), clean);
    EXPECT_EQ(p.estimation.rows(), p.validation.rows());
    ASSERT_EQ(p.noise_sigma.size(), 1u);
    // The nominal simulated on the estimation inputs differs from the truth unless the plant is
    // clean; the truth's spread sets the noise: sigma = 1 % of it.
    Simulator truth(p.truth, p.estimation), nominal(p.nominal, p.estimation);
    const Eigen::VectorXd yt = truth.simulate(truth.parameter_values()).outputs.col(0);
    const Eigen::VectorXd yn = nominal.simulate(nominal.parameter_values()).outputs.col(0);
    const double sd = std::sqrt((yt.array() - yt.mean()).square().mean());
    EXPECT_NEAR(p.noise_sigma[0], 0.01 * sd, 0.002 * sd);
    const Eigen::VectorXd noise = truth.measured().col(0) - yt;
    const double measured_sd = std::sqrt((noise.array() - noise.mean()).square().mean());
    EXPECT_NEAR(measured_sd, p.noise_sigma[0], 0.1 * p.noise_sigma[0]);
    if (!clean) {
      EXPECT_GT((yt - yn).cwiseAbs().maxCoeff(), 0.0);
    }
  }
}
