// The noise-level estimate: each method on a case where it must be right, scale-freedom, and the
// real recordings (Silverbox, EMPS) where a truth is known.

#include <gtest/gtest.h>

#include <unsupported/Eigen/FFT>

#include <cmath>
#include <complex>
#include <random>

#include "sets/data/intersample.hpp"
#include "sets/data/noise_level.hpp"
#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"
#include "support/shared_data.hpp"

using namespace sets;

namespace {

using Eigen::VectorXd;

// A random multisine with lines between f_lo and f_hi cycles/sample, repeated `periods` times.
VectorXd multisine(int N, double f_lo, double f_hi, int periods, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> phase(0, 2 * M_PI);
  const int P = N / periods;
  std::vector<std::complex<double>> spectrum(static_cast<std::size_t>(P), 0.0);
  for (int line = static_cast<int>(std::ceil(f_lo * P)); line <= static_cast<int>(f_hi * P); ++line) {
    const double ph = phase(rng);
    spectrum[static_cast<std::size_t>(line)] = std::polar(1.0, ph);
    spectrum[static_cast<std::size_t>(P - line)] = std::polar(1.0, -ph);
  }
  std::vector<double> one;
  Eigen::FFT<double> fft;
  fft.inv(one, spectrum);
  VectorXd u(N);
  for (int k = 0; k < N; ++k) u[k] = one[static_cast<std::size_t>(k % P)];
  return u / std::sqrt(u.squaredNorm() / N);
}

// A lightly damped resonance at f0 cycles/sample driven by u (a second-order recursion).
VectorXd resonance(const VectorXd& u, double f0, double zeta) {
  const double r = std::exp(-zeta * 2 * M_PI * f0), c = 2 * r * std::cos(2 * M_PI * f0 * std::sqrt(1 - zeta * zeta));
  VectorXd y = VectorXd::Zero(u.size());
  for (Eigen::Index k = 2; k < u.size(); ++k) y[k] = c * y[k - 1] - r * r * y[k - 2] + (1 - c + r * r) * u[k - 1];
  return y;
}

VectorXd white(int N, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  VectorXd e(N);
  for (auto& v : e) v = g(rng);
  return e;
}

double rms(const VectorXd& x) { return std::sqrt((x.array() - x.mean()).square().mean()); }

// A sine of 15.3 samples per period through a resonance, with white noise of 0.4 % of the output:
// the input nearly repeats at a lag of 46 samples (3 periods, 0.04 rad of phase short).
struct NearlyPeriodic {
  VectorXd u, clean, noise;
};
NearlyPeriodic nearly_periodic(int N) {
  NearlyPeriodic c;
  c.u.resize(N);
  for (int k = 0; k < N; ++k) c.u[k] = std::sin(2 * M_PI * k / 15.3);
  c.clean = resonance(c.u, 0.02, 0.3);
  c.noise = white(N, 4e-3 * rms(c.clean), 11);
  return c;
}

}  // namespace

TEST(NoiseLevel, WhiteNoiseOnAFastSampledSignalFromTheOutputAlone) {
  const int N = 8192;
  const VectorXd y = 10 * multisine(N, 0.001, 0.02, 1, 1) + white(N, 0.01, 2);
  const NoiseLevelEstimate e = estimate_noise(y);
  EXPECT_EQ(e.method, NoiseMethod::output_spectrum);
  EXPECT_NEAR(e.sigma / 0.01, 1.0, 0.15) << e.reason;
}

TEST(NoiseLevel, CoarseSamplingDoesNotTurnSignalIntoNoise) {
  // ~9 samples per period of the resonance (the Silverbox's case): the second difference is signal.
  const int N = 16384;
  const VectorXd u = multisine(N, 0.002, 0.2, 1, 3);
  const VectorXd clean = resonance(u, 0.11, 0.05);
  const VectorXd noise = white(N, 1e-3 * rms(clean), 4);
  const VectorXd y = clean + noise;
  // The model is close but not exact: 3 % gain and a small lag.
  VectorXd model = 1.03 * clean;
  for (int k = N - 1; k > 0; --k) model[k] = 0.9 * model[k] + 0.1 * model[k - 1];
  VectorXd d2(N - 2);
  for (int k = 2; k < N; ++k) d2[k - 2] = y[k] - 2 * y[k - 1] + y[k - 2];
  EXPECT_GT(rms(d2) / std::sqrt(6.0), 20 * rms(noise));  // what the old estimate read as noise
  const NoiseLevelEstimate e = estimate_noise(y, model, u);
  EXPECT_NE(e.method, NoiseMethod::repeats);
  EXPECT_NEAR(e.sigma / rms(noise), 1.0, 0.3) << e.reason;
}

TEST(NoiseLevel, ColouredNoiseIsExtrapolatedUnderTheSignal) {
  const int N = 16384;
  const VectorXd u = multisine(N, 0.001, 0.05, 1, 5);
  const VectorXd clean = resonance(u, 0.02, 0.1);
  VectorXd noise = white(N, 1.0, 6);
  for (int k = 1; k < N; ++k) noise[k] += 0.8 * noise[k - 1];  // AR(1), pole 0.8
  noise *= 1e-2 * rms(clean) / rms(noise);
  const NoiseLevelEstimate e = estimate_noise(clean + noise, 0.98 * clean, u);
  EXPECT_EQ(e.method, NoiseMethod::residual_coloured) << e.reason;
  EXPECT_NEAR(e.sigma / rms(noise), 1.0, 0.3) << e.reason;
  // The white floor alone would read the noise's top band only: sqrt((1 - a) / (1 + a)) = 1/3.
  // The pole is said (the residual tests whiten by it).
  EXPECT_NEAR(e.ar_pole, 0.8, 0.03) << e.reason;
}

TEST(NoiseLevel, WhiteNoiseHasNoPoleToWhitenBy) {
  const int N = 16384;
  const VectorXd u = multisine(N, 0.001, 0.05, 1, 5);
  const VectorXd clean = resonance(u, 0.02, 0.1);
  const VectorXd noise = 1e-2 * rms(clean) * white(N, 1.0, 6);
  const NoiseLevelEstimate e = estimate_noise(clean + noise, 0.98 * clean, u);
  EXPECT_LT(std::abs(e.ar_pole), 0.03) << e.reason;  // white: 0, or the a = 0 shape verified
}

TEST(NoiseLevel, ColouredNoiseIsExtrapolatedPastAnOctaveOfModelError) {
  // AR(1) noise (pole 0.9) plus what the model misses in one octave, [1/16, 1/8] cycles/sample
  // (a resonance at 0.09 driven by a disturbance the inputs do not carry, so no projection removes
  // it): above that octave the residual is the noise's shape, below it the noise again. Random
  // plant 5 001 426 (Stribeck friction, AR noise 0.91) read 0.22x from the white floor.
  const int N = 4096;
  const VectorXd u = multisine(N, 0.001, 0.03, 1, 13);
  const VectorXd clean = resonance(u, 0.01, 0.3);
  VectorXd noise = white(N, 1.0, 14);
  for (int k = 1; k < N; ++k) noise[k] += 0.9 * noise[k - 1];
  noise *= 1e-2 * rms(clean) / rms(noise);
  const VectorXd missed = resonance(white(N, 1.0, 15), 0.09, 0.05);
  const VectorXd y = clean + noise + 0.5 * rms(noise) / rms(missed) * missed;
  const NoiseLevelEstimate e = estimate_noise(y, clean, u);
  EXPECT_EQ(e.method, NoiseMethod::residual_coloured) << e.reason;
  EXPECT_NEAR(e.sigma / rms(noise), 1.0, 0.3) << e.reason;
  // The white floor would read sqrt((1 - a) / (1 + a)) = 0.23 of it.
  // The pole is the noise's, read around the octave of model error, not bent by it.
  EXPECT_NEAR(e.ar_pole, 0.9, 0.03) << e.reason;
}

TEST(NoiseLevel, ColouredNoiseIsExtrapolatedFromThreeOctavesAboveModelErrorBelowThem) {
  // AR(1) noise (pole 0.9) plus what the model misses at low frequencies (a disturbance the inputs
  // do not carry, low-passed at 0.006 cycles/sample, 10x the noise RMS): the residual is the
  // noise's shape from 1/16 to 1/2 and holds more than it in every octave below, so the band never
  // reaches 1/32. The white floor reads sqrt((1 - a) / (1 + a)) = 0.23 of the noise (random plant
  // 5 004 769, a = 0.75 under a named Stribeck law's low-frequency error: 0.36x).
  const int N = 4096;
  const VectorXd u = multisine(N, 0.001, 0.03, 1, 41);
  const VectorXd clean = resonance(u, 0.01, 0.3);
  const VectorXd missed = resonance(white(N, 1.0, 43), 0.006, 0.7);
  VectorXd noise = white(N, 1.0, 42);
  for (int k = 1; k < N; ++k) noise[k] += 0.9 * noise[k - 1];
  noise *= 1e-2 * rms(clean) / rms(noise);
  for (double scale : {1e-6, 1.0}) {
    const VectorXd y = scale * (clean + noise + 10 * rms(noise) / rms(missed) * missed);
    const NoiseLevelEstimate e = estimate_noise(y, scale * clean, u);
    EXPECT_EQ(e.method, NoiseMethod::residual_coloured) << e.reason;
    EXPECT_NEAR(e.sigma / (scale * rms(noise)), 1.0, 0.3) << e.reason;
    EXPECT_GT(e.ar_pole, 0.85) << e.reason;
  }
  // White noise under 3x stronger model error, whose tail rises into the third octave: the refit
  // over three octaves bends towards a = 0.23 and read 1.19x; the third octave must match the shape
  // of the two above it, so the white floor reads the noise.
  const VectorXd w = white(N, 1e-2 * rms(clean), 42);
  const NoiseLevelEstimate e = estimate_noise(clean + w + 30 * rms(w) / rms(missed) * missed, clean, u);
  EXPECT_NEAR(e.sigma / rms(w), 1.0, 0.1) << e.reason;
  EXPECT_LT(e.ar_pole, 0.1) << e.reason;
}

TEST(NoiseLevel, ModelErrorShapedLikeColouredNoiseAboveABandIsNotExtrapolated) {
  // White noise plus what the model misses above f = 1/32 only, shaped so that the residual's
  // density is exactly AR(1)'s (pole 0.8) from 1/32 to 1/2 and the noise's own below 1/32. The shape
  // holds over the four octaves colour asks for; extrapolated it claims sqrt((1 + a) / (1 - a)) =
  // 3x the noise, most of it below 1/32, where the residual holds a ninth of the shape. Noise cannot
  // hold more than the residual, so the shape is the model error's: the white floor reads the noise
  // (random plant 5 004 576, Stribeck friction and a dead zone named: 2.59x, now 1.00x).
  const int N = 8192;
  const VectorXd u = multisine(N, 0.001, 0.02, 1, 31);
  const VectorXd clean = resonance(u, 0.005, 0.3);
  const VectorXd noise = white(N, 1e-2 * rms(clean), 32);
  const VectorXd w = white(N, 1.0, 33);
  std::vector<std::complex<double>> W;
  Eigen::FFT<double> fft;
  fft.fwd(W, std::vector<double>(w.data(), w.data() + N));
  const double a = 0.8;
  auto ar = [&](double f) { return 1 / (1 + a * a - 2 * a * std::cos(2 * M_PI * f)); };
  for (int k = 0; k < N; ++k) {
    const double f = std::min(k, N - k) / static_cast<double>(N);
    W[static_cast<std::size_t>(k)] *= f >= 1.0 / 32 ? std::sqrt(std::max(0.0, ar(f) / ar(0.5) - 1)) : 0.0;
  }
  std::vector<double> m;
  fft.inv(m, W);
  const VectorXd missed = rms(noise) * Eigen::Map<const VectorXd>(m.data(), N);
  for (double scale : {1e-6, 1.0}) {
    const NoiseLevelEstimate e = estimate_noise(scale * (clean + noise + missed), scale * clean, u);
    EXPECT_NE(e.method, NoiseMethod::residual_coloured) << e.reason;
    EXPECT_NEAR(e.sigma / (scale * rms(noise)), 1.0, 0.2) << e.reason;
    EXPECT_EQ(e.ar_pole, 0.0);
  }
}

TEST(NoiseLevel, QuantisedOutputGivesTheQuantisationFloor) {
  const int N = 8192;
  const VectorXd clean = 1e-3 * resonance(multisine(N, 0.001, 0.03, 1, 7), 0.01, 0.3);
  const double q = rms(clean) / 300;
  VectorXd y(N);
  for (int k = 0; k < N; ++k) y[k] = q * std::round(clean[k] / q);
  EXPECT_NEAR(lattice_step(y) / q, 1.0, 1e-6);
  const NoiseLevelEstimate e = estimate_noise(y, clean);
  EXPECT_NEAR(e.quantisation_step / q, 1.0, 1e-6);
  EXPECT_NEAR(e.sigma / rms(y - clean), 1.0, 0.5) << e.reason;  // within a factor 2
  EXPECT_GE(e.sigma, q / std::sqrt(12.0) * (1 - 1e-12));
}

TEST(NoiseLevel, AnOutputThatCrossesSeveralLevelsPerSampleIsStillQuantised) {
  // Sampled 7 times per period, a sine of 100 levels never moves by one level between samples: its
  // smallest step is a multiple of q (random plant 5 006 649's level moved the same way).
  const int N = 4096;
  const double q = 3e-5;
  VectorXd y(N);
  for (int k = 0; k < N; ++k) y[k] = q * std::round(100 * std::sin(2 * M_PI * k / 7.0 + 0.1));
  double smallest = INFINITY;
  for (int k = 1; k < N; ++k)
    if (y[k] != y[k - 1]) smallest = std::min(smallest, std::abs(y[k] - y[k - 1]));
  ASSERT_GT(smallest, 1.5 * q);  // the case: no step of one level
  ASSERT_LT(smallest, 64.5 * q);
  EXPECT_NEAR(lattice_step(y) / q, 1.0, 1e-9);
}

TEST(NoiseLevel, AQuantisedOutputThatStepsRarelyIsReadAtItsQuantiser) {
  // A staircase on a lattice of step q that changes 6 times in 3000 samples, and a model that
  // reproduces it exactly (random plant 5 007 815: a position loop's few steps seen through a
  // sensor play, quantised): the residual is zero, and was read as a noise of 1e-14 of the truth.
  // Nothing below q / sqrt(12) can be read from values that only sit on the lattice.
  const double q = 2e-3;
  const int levels[] = {3, 7, 0, -4, 9, 2, 5};
  VectorXd y(3000);
  for (int k = 0; k < y.size(); ++k) y[k] = q * levels[k / 430];
  EXPECT_NEAR(lattice_step(y) / q, 1.0, 1e-9);
  for (double scale : {1e-6, 1.0}) {
    const NoiseLevelEstimate e = estimate_noise(scale * y, scale * y);
    EXPECT_NEAR(e.sigma / (scale * q / std::sqrt(12.0)), 1.0, 1e-9) << e.reason;
  }
}

TEST(NoiseLevel, FewLevelsOffAnyLatticeAreNotTakenForAQuantiser) {
  // The same staircase with levels drawn from a continuum: values that merely repeat are no
  // quantiser, whichever fraction of the smallest step is tried. Three or four distinct values fall
  // on one of 64 lattices to 1e-3 about once in 8 or 2 000 draws, so they are never enough.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> level(-1, 1);
  for (int distinct : {3, 4, 7})
    for (int trial = 0; trial < 200; ++trial) {
      std::vector<double> levels(static_cast<std::size_t>(distinct));
      for (double& v : levels) v = level(rng);
      VectorXd y(3000);
      for (int k = 0; k < y.size(); ++k) y[k] = levels[static_cast<std::size_t>(k / 430 % distinct)];
      EXPECT_EQ(lattice_step(y), 0.0) << distinct << " levels, trial " << trial;
    }
}

TEST(NoiseLevel, ColouredNoiseBeforeAQuantiserIsStillReadAsColour) {
  // AR(1) noise (pole 0.9, RMS 2q) before a quantiser of step q: it dithers the quantiser, whose
  // error is then white (q^2 / 12) beside it, and the noise puts (1 - a) / (1 + a) of its own white
  // density into the top band, above the quantiser's. Colour is read and extrapolated; a quantised
  // output whose top band holds no more than the quantiser's error is read at q / sqrt(12)
  // (NoiseFloor.AQuantisedOutputsModelErrorIsNotReadAsNoiseBeyondTheQuantiser).
  const int N = 8192;
  const VectorXd clean = resonance(multisine(N, 0.001, 0.03, 1, 7), 0.01, 0.3);
  const double q = rms(clean) / 200;
  VectorXd noise = white(N, 1.0, 11);
  for (int k = 1; k < N; ++k) noise[k] = 0.9 * noise[k - 1] + std::sqrt(1 - 0.81) * noise[k];
  noise *= 2 * q / rms(noise);
  for (double scale : {1e-6, 1.0}) {
    VectorXd y(N);
    for (int k = 0; k < N; ++k) y[k] = scale * q * std::round((clean[k] + noise[k]) / q);
    const NoiseLevelEstimate e = estimate_noise(y, scale * clean);
    ASSERT_GT(e.quantisation_step, 0);
    EXPECT_EQ(e.method, NoiseMethod::residual_coloured) << e.reason;
    EXPECT_NEAR(e.sigma / rms(y - scale * clean), 1.0, 0.2) << e.reason;
  }
}

TEST(NoiseLevel, RepeatedInputGivesTheNoiseFromTheRepeats) {
  // Four periods of a multisine; a model that is plainly wrong does not matter to the repeats.
  const int N = 16384;
  const VectorXd u = multisine(N, 0.002, 0.2, 4, 8);
  const VectorXd clean = resonance(u, 0.11, 0.05);
  const VectorXd noise = white(N, 2e-3 * rms(clean), 9);
  const NoiseLevelEstimate e = estimate_noise(clean + noise, 0.7 * clean, u);
  EXPECT_EQ(e.method, NoiseMethod::repeats) << e.reason;
  EXPECT_NE(e.reason.find("lag of 4096"), std::string::npos) << e.reason;
  EXPECT_NEAR(e.sigma / rms(noise), 1.0, 0.1) << e.reason;
  // A random (not repeating) input of the same spectrum: no repeats are invented.
  EXPECT_EQ(detect_repeats(multisine(N, 0.002, 0.2, 1, 10)).matched, 0);
}

TEST(NoiseLevel, ANearlyPeriodicInputDoesNotTurnItsDriftIntoNoise) {
  // The repeat difference of the output is mostly signal. The input's own repeat difference is
  // its derivative times the phase short (the derivative's share of it, R^2, is near 1): the
  // repeats are not read at all, the residual is (randomised suite, random-800013: 24x when they
  // were).
  const auto [u, clean, noise] = nearly_periodic(4096);
  const InputRepeats rep = detect_repeats(u);
  ASSERT_GT(rep.matched, 0);  // the premise: the repeats are found
  EXPECT_GT(sigma_from_repeats(clean + noise, rep), 2 * rms(noise));  // what the repeats alone read
  const NoiseLevelEstimate e = estimate_noise(clean + noise, clean, u);
  EXPECT_NE(e.method, NoiseMethod::repeats) << e.reason;
  EXPECT_NE(e.reason.find("phase drift"), std::string::npos) << e.reason;
  EXPECT_NEAR(e.sigma / rms(noise), 1.0, 0.1) << e.reason;
}

// The same nearly periodic input beside a model that misses a slow part of the output (an effect
// not yet in the model): the model's projected residual is then the noise plus that model error,
// an upper bound, and taking it when the repeats hold even more read the model error as noise
// (random plant 700 069: 10x the truth, and a strong Stribeck law failed the noise rule against
// that floor). The residual's spectrum above the model error gives the noise.
TEST(NoiseLevel, ANearlyPeriodicInputBesideModelErrorIsReadFromTheResidualNotItsRms) {
  const int N = 4096;
  const auto [u, clean, noise] = nearly_periodic(N);
  VectorXd slow = white(N, 1.0, 12);  // model error: slow, independent of the input
  for (int k = 1; k < N; ++k) slow[k] = 0.995 * slow[k - 1] + 0.1 * slow[k];
  slow *= 5 * rms(noise) / rms(slow);
  const VectorXd y = clean + slow + noise;
  ASSERT_GT(sigma_from_repeats(y, detect_repeats(u)), rms(slow));  // the premise: the repeats read more than the model error
  const NoiseLevelEstimate e = estimate_noise(y, clean, u);
  EXPECT_NEAR(e.sigma / rms(noise), 1.0, 0.2) << e.reason;
}

// An input that repeats exactly but carries a dither the plant responds to (an actuator's own
// noise, recorded): the output's repeat difference holds the response to the dither's difference,
// which the model simulates from the recorded input. Read on the model's residual, it drops out.
// The dither is white, so the repeat difference is no phase drift (R^2 near 0) and the repeats are
// kept.
TEST(NoiseLevel, RepeatsWithAnInputDitherAreReadOnTheResidual) {
  const int N = 16384;
  const VectorXd u = multisine(N, 0.002, 0.2, 4, 8) + white(N, 0.05, 13);
  const VectorXd clean = resonance(u, 0.11, 0.05);
  const VectorXd noise = white(N, 2e-3 * rms(clean), 14);
  const VectorXd y = clean + noise;
  const InputRepeats rep = detect_repeats(u);
  ASSERT_GT(rep.matched, 0);                                       // the premise: the dither hides no repeat
  ASSERT_GT(sigma_from_repeats(y, rep), 2 * rms(noise));           // and y's repeats read more than noise
  const NoiseLevelEstimate e = estimate_noise(y, clean, u);
  EXPECT_EQ(e.method, NoiseMethod::repeats) << e.reason;
  EXPECT_NE(e.reason.find("on the model's residual"), std::string::npos) << e.reason;
  EXPECT_NEAR(e.sigma / rms(noise), 1.0, 0.1) << e.reason;
}

TEST(NoiseLevel, IsFreeOfUnits) {
  const int N = 8192;
  const VectorXd u = multisine(N, 0.001, 0.1, 1, 11);
  const VectorXd clean = resonance(u, 0.05, 0.1);
  const VectorXd y = clean + white(N, 1e-2 * rms(clean), 12);
  const NoiseLevelEstimate a = estimate_noise(y, 1.01 * clean, u);
  const NoiseLevelEstimate b = estimate_noise(1e6 * y, 1.01e6 * clean, 1e-3 * u);
  EXPECT_EQ(a.method, b.method);
  EXPECT_NEAR(b.sigma / (1e6 * a.sigma), 1.0, 1e-9);
}

TEST(NoiseLevel, MostReliableMethodWins) {
  std::vector<NoiseLevelEstimate> e(3);
  e[0].method = NoiseMethod::residual_floor;
  e[1].method = NoiseMethod::repeats;
  e[2].method = NoiseMethod::repeats;
  EXPECT_EQ(most_reliable(e), 1u);
  e[1].method = NoiseMethod::output_spectrum;
  EXPECT_EQ(most_reliable(e), 2u);
}

TEST(NoiseLevel, SilverboxRepeatsGiveTheNoiseOfV2) {
  // Truth: 0.25-0.3 mV on V2 (README: the repeated stretches of the record).
  const auto dir = test::shared_data("silverbox");
  if (dir.empty()) GTEST_SKIP() << "silverbox data not found under ../shared/data (set SETS_SHARED_DIR)";
  ModelFile m = load_model_file((dir / "nominal.json").string());
  const Recording est = read_recording((dir / "estimation.csv").string());
  // The linear model of the README (row A), input held.
  m.parameter("g")->value = 1.8823e5;
  m.parameter("c")->value = 43.34;
  m.parameter("k")->value = 1.9766e5;
  Simulator s(m, est, {10});
  const VectorXd yhat = s.simulate(s.parameter_values()).outputs.col(0);
  const VectorXd y = s.measured().col(0);
  const VectorXd u = Eigen::Map<const VectorXd>(est.column("V1").data(), est.rows());
  const NoiseLevelEstimate e = estimate_noise(y, yhat, u);
  EXPECT_EQ(e.method, NoiseMethod::repeats) << e.reason;
  EXPECT_GT(e.sigma, 0.25e-3 / 2) << e.reason;
  EXPECT_LT(e.sigma, 0.30e-3 * 2) << e.reason;
}

TEST(NoiseLevel, EmpsPositionIsQuantisedAtTheEncoderStep) {
  // q_meas is on a 5e-8 m lattice: its noise is q / sqrt(12) = 14.4 nm.
  const auto file = test::shared_data("emps/estimation.csv");
  if (file.empty()) GTEST_SKIP() << "emps data not found under ../shared/data (set SETS_SHARED_DIR)";
  const Recording est = read_recording(file.string());
  const VectorXd q = Eigen::Map<const VectorXd>(est.column("q_meas").data(), est.rows());
  EXPECT_NEAR(lattice_step(q) / 5e-8, 1.0, 1e-6);
  const NoiseLevelEstimate e = estimate_noise(q);
  EXPECT_GT(e.sigma, 14.4e-9 / 2) << e.reason;
  EXPECT_LT(e.sigma, 14.4e-9 * 2) << e.reason;
}

TEST(NoiseLevel, ASwitchingModelErrorIsNotReadAsColouredNoise) {
  // What the model misses switches between two levels (a relay, a hysteresis' or backlash's
  // reversal seen at coarse sampling) at random, on average every 20 samples: a random telegraph
  // signal, whose spectrum is exactly that of AR(1) noise of pole 1 - 2/20 = 0.9. Beside white
  // noise of a tenth of its height the residual's spectrum is AR(1)-shaped from 1/32 to 1/2, and
  // was read as that noise (random plant 5 004 294, 7.5x). Its differences hold the reversals in a
  // few samples each, bursts the clipped differences drop: the noise is read from them.
  const int N = 4096;
  const VectorXd u = multisine(N, 0.001, 0.03, 1, 21);
  const VectorXd clean = resonance(u, 0.01, 0.3);
  const VectorXd noise = white(N, 1e-3 * rms(clean), 22);
  std::mt19937 rng(23);
  std::bernoulli_distribution reverse(1.0 / 20);
  VectorXd missed(N);
  double level = 10 * rms(noise);
  for (int k = 0; k < N; ++k) missed[k] = level = reverse(rng) ? -level : level;
  for (double scale : {1e-6, 1.0}) {
    const NoiseLevelEstimate e = estimate_noise(scale * (clean + noise + missed), scale * clean, u);
    EXPECT_NE(e.method, NoiseMethod::residual_coloured) << e.reason;
    EXPECT_NEAR(e.sigma / (scale * rms(noise)), 1.0, 0.2) << e.reason;
    EXPECT_EQ(e.ar_pole, 0.0);
  }
}
