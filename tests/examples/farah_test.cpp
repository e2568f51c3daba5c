// The Farah et al. example: the printed system and data at the requested signal-to-noise ratio.

#include <gtest/gtest.h>

#include <cmath>

#include "sets/examples/farah.hpp"

TEST(FarahExample, DataHaveTheRequestedSnrAndBinaryInput) {
  const auto sys = sets::farah::system();
  ASSERT_EQ(sys.A.rows(), 3);
  ASSERT_EQ(sys.B.cols(), 2);
  ASSERT_EQ(sys.C.rows(), 2);
  std::mt19937_64 rng(7);
  const auto d = sets::farah::simulate(sys, 4000, 20.0, rng);
  EXPECT_TRUE((d.u.array().abs() == 1.0).all());
  const Eigen::MatrixXd clean = sets::simulate(sys, d.u);
  for (int j = 0; j < 2; ++j) {
    const Eigen::VectorXd noise = d.y.col(j) - clean.col(j);
    const double signal = (clean.col(j).array() - clean.col(j).mean()).square().mean();
    const double snr = 10 * std::log10(signal / noise.squaredNorm() * noise.size());
    EXPECT_NEAR(snr, 20.0, 0.3) << "output " << j;
  }
}

TEST(FarahExample, UniformNoiseIsBoundedAndHasTheRequestedSnr) {
  const auto sys = sets::farah::system();
  std::mt19937_64 rng(11);
  const auto d = sets::farah::simulate(sys, 4000, 20.0, rng, sets::farah::Noise::uniform);
  const Eigen::MatrixXd clean = sets::simulate(sys, d.u);
  for (int j = 0; j < 2; ++j) {
    const Eigen::VectorXd noise = d.y.col(j) - clean.col(j);
    EXPECT_DOUBLE_EQ(noise.cwiseAbs().maxCoeff(), d.largest_noise[j]);
    EXPECT_LE(d.largest_noise[j], std::sqrt(3.0) * d.sigma[j] * (1 + 1e-12)) << "output " << j;
    EXPECT_GT(d.largest_noise[j], 0.99 * std::sqrt(3.0) * d.sigma[j]);  // 4000 samples reach the edge
    const double signal = (clean.col(j).array() - clean.col(j).mean()).square().mean();
    EXPECT_NEAR(10 * std::log10(signal / noise.squaredNorm() * noise.size()), 20.0, 0.3) << "output " << j;
  }
}
