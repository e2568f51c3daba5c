// The crane example: inputs within |u| <= 1, the tables' cases and perturbations, the noise level.

#include <gtest/gtest.h>

#include "sets/core/error.hpp"
#include "sets/examples/crane.hpp"

TEST(CraneExample, InputsStayWithinTheAmplitudeBound) {
  for (const char* kind : {"square", "prbs", "multisine"}) {
    const Eigen::MatrixXd u = sets::crane::input(kind, 400, 3);
    EXPECT_NEAR(u.cwiseAbs().maxCoeff(), 1.0, 1e-12) << kind;
  }
  const Eigen::MatrixXd sq = sets::crane::input("square", 100, 1);
  EXPECT_EQ(sq(39, 0), 1.0);   // period 4 s = 80 samples
  EXPECT_EQ(sq(40, 0), -1.0);
  EXPECT_NE(sets::crane::input("prbs", 400, 1), sets::crane::input("prbs", 400, 2));
  EXPECT_THROW(sets::crane::input("chirp", 10, 1), sets::InputError);
}

TEST(CraneExample, CasesAndPerturbationsOfTheTables) {
  EXPECT_EQ(sets::crane::cases("I").size(), 5u);
  EXPECT_EQ(sets::crane::cases("II").size(), 6u);
  EXPECT_EQ(sets::crane::cases("all").size(), 15u);
  const auto c = sets::crane::cases("I").front();
  const Eigen::MatrixXd pi = sets::crane::perturbation(c, 120);
  const Eigen::VectorXd peak = pi.cwiseAbs().colwise().maxCoeff().transpose();
  EXPECT_TRUE(peak.isApprox(c.amplitude)) << peak.transpose();
}

TEST(CraneExample, NoiseHasTheRequestedWindowNorm) {
  const auto w = sets::crane::window();
  const Eigen::VectorXd eta = sets::crane::noise(120, 0.1, w, 5);
  EXPECT_EQ(eta.size(), 121);
  EXPECT_NEAR(w(eta), 0.1, 1e-12);
}
