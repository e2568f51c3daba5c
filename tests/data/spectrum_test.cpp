// Welch's spectrum: the segment rule, Parseval (the density integrates to the mean square), a
// sinusoid's power lands at its frequency, and the density scales with the square of the signal
// and not with anything else (the rules built on it must be free of units).

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "sets/core/error.hpp"
#include "sets/data/spectrum.hpp"

namespace {

Eigen::VectorXd white_noise(Eigen::Index n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  return Eigen::VectorXd::NullaryExpr(n, [&] { return g(rng); });
}

double integral(const sets::WelchSpectrum& s) { return s.density.sum() / s.segment; }  // bin width 1/segment

}  // namespace

TEST(WelchSpectrum, SegmentsFollowTheDocumentedRule) {
  const auto s = sets::welch_spectrum(white_noise(8192, 1));
  EXPECT_EQ(s.segment, 1024);   // 2^round(log2(8192 / 8))
  EXPECT_EQ(s.segments, 15);    // half-overlapping: (8192 - 1024) / 512 + 1
  ASSERT_EQ(s.frequency.size(), 512);
  EXPECT_DOUBLE_EQ(s.frequency[0], 1.0 / 1024);
  EXPECT_DOUBLE_EQ(s.frequency[511], 0.5);
  EXPECT_EQ(sets::welch_spectrum(white_noise(300, 1)).segment, 64);  // at least 64 samples
  EXPECT_EQ(sets::welch_spectrum(white_noise(40, 1)).segment, 40);   // at most N
  EXPECT_EQ(sets::welch_spectrum(white_noise(1000, 1), 100).segment, 100);
  EXPECT_THROW(sets::welch_spectrum(Eigen::VectorXd::Ones(3)), sets::InputError);
}

TEST(WelchSpectrum, WhiteNoiseIsFlatAndIntegratesToItsVariance) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Eigen::VectorXd x = 3.0 * white_noise(16384, seed);
    const auto s = sets::welch_spectrum(x);
    EXPECT_NEAR(integral(s), 9.0, 0.05 * 9.0) << "seed " << seed;
    // Flat: the mean density over each quarter of the band is the same (2 sigma^2 one-sided).
    const Eigen::Index q = s.density.size() / 4;
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(s.density.segment(k * q, q).mean(), 18.0, 0.1 * 18.0) << "seed " << seed;
  }
}

TEST(WelchSpectrum, ASinusoidsPowerIsAtItsFrequency) {
  const double f0 = 0.123, amplitude = 2.0;
  Eigen::VectorXd x(8192);
  for (Eigen::Index t = 0; t < x.size(); ++t) x[t] = amplitude * std::sin(2 * std::numbers::pi * f0 * t + 0.3);
  const auto s = sets::welch_spectrum(x);
  Eigen::Index peak = 0;
  s.density.maxCoeff(&peak);
  EXPECT_LE(std::abs(s.frequency[peak] - f0), 1.0 / s.segment);
  EXPECT_NEAR(integral(s), amplitude * amplitude / 2, 0.02 * amplitude * amplitude / 2);
}

TEST(WelchSpectrum, DensityScalesWithTheSquareOfTheSignalAndIgnoresItsOffset) {
  const Eigen::VectorXd x = white_noise(4096, 9);
  const auto a = sets::welch_spectrum(x);
  const auto b = sets::welch_spectrum((1e-3 * x.array() + 50.0).matrix());  // other units, an offset
  ASSERT_EQ(a.density.size(), b.density.size());
  for (Eigen::Index k = 0; k < a.density.size(); ++k)
    EXPECT_NEAR(b.density[k], 1e-6 * a.density[k], 1e-9 * 1e-6 * a.density.maxCoeff()) << k;
}
