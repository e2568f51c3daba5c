// Bursts in a signal's fast part: none in noise of any colour or in quantised noise, at any scale;
// a switching mismatch (a relay whose reversals are a few samples each) has them, even where its
// power is a small part of the signal's.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sets/data/bursts.hpp"

using namespace sets;

namespace {

// AR(1) noise of pole a and unit marginal variance.
Eigen::VectorXd ar_noise(int N, double a, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> e(0, 1);
  Eigen::VectorXd x(N);
  double w = 0;
  for (int k = 0; k < N; ++k) x[k] = w = a * w + std::sqrt(1 - a * a) * e(rng);
  return x;
}

// A relay of height h that reverses at random, on average every `mean_run` samples, through a
// first-order lag of `lag` samples (a hysteresis' or backlash's reversals seen through a plant).
Eigen::VectorXd switching(int N, double h, int mean_run, double lag, unsigned seed) {
  std::mt19937 rng(seed);
  std::geometric_distribution<int> run(1.0 / mean_run);
  Eigen::VectorXd x(N);
  double state = h, out = 0;
  for (int k = 0, next = run(rng); k < N; ++k) {
    if (k == next) state = -state, next = k + 1 + run(rng);
    out += (state - out) / lag;
    x[k] = out;
  }
  return x;
}

}  // namespace

TEST(Bursts, NoiseOfAnyColourAndScaleHasNone) {
  for (double a : {0.0, 0.5, 0.9, 0.97})
    for (double scale : {1e-7, 1.0, 1e5}) {
      const double b = burst_ratio(scale * ar_noise(3000, a, 11));
      EXPECT_LT(b, 1.05) << "a = " << a << ", scale " << scale;
      EXPECT_GE(b, 1.0);
    }
}

TEST(Bursts, QuantisedNoiseHasNone) {
  Eigen::VectorXd x = ar_noise(3000, 0.3, 12);
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] = 0.7 * std::round(x[k] / 0.7);  // a coarse lattice
  EXPECT_LT(burst_ratio(x), 1.05);
}

TEST(Bursts, ASwitchingMismatchInNoiseHasThem) {
  // Reversals every ~150 samples through a 2-sample lag, 30x the noise in height (a model error
  // of 15 noise levels RMS, as on random plant 5 004 294): a few samples per reversal carry more
  // energy than the noise in every difference.
  const Eigen::VectorXd noise = ar_noise(3000, 0.0, 13);
  EXPECT_GT(burst_ratio(noise + switching(3000, 30.0, 150, 2.0, 14)), kBurstRatioLimit);
  // 3x the noise in height: the reversals are inside the noise's body, too weak to be told.
  EXPECT_LT(burst_ratio(noise + switching(3000, 3.0, 150, 2.0, 14)), kBurstRatioLimit);
  // The strong mismatch smoothed (a lag of 60 samples): it moves slowly, no bursts.
  EXPECT_LT(burst_ratio(noise + switching(3000, 30.0, 150, 60.0, 14)), 1.1);
}

TEST(Bursts, ClippedRmsOfGaussianDataIsItsRms) {
  const Eigen::VectorXd x = 3.0 * ar_noise(20000, 0.0, 15);
  EXPECT_NEAR(clipped_rms(x), std::sqrt(x.squaredNorm() / 20000), 0.01 * 3.0);
}
