// The data hypothesis (src/diagnosis/data_hypothesis.cpp): is the mismatch the inputs' intersample
// behaviour rather than missing physics? Synthetic records where the truth is known, then the
// Silverbox benchmark (issue 18's "must show").

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sets/data/intersample.hpp"
#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/models/model_file.hpp"
#include "support/shared_data.hpp"

using namespace sets;

namespace {

// A lightly damped oscillator sampled 8 times per period of its resonance (12.5 Hz at 100 Hz).
const char* kOscillator = R"json({"sample_time": 0.01, "inputs": {"u": "u"},
  "parameters": {"g": 6000, "c": 6, "k": 6000}, "states": {"y": 0.0, "v": 0.0},
  "derivatives": {"y": "v", "v": "g*u - c*v - k*y"}, "outputs": {"y": "y"}})json";

// The engineer's nominal: the same structure, values 20-30 % off.
ModelFile nominal(const std::string& intersample) {
  ModelFile m = parse_model(kOscillator, "oscillator.json");
  for (auto& p : m.parameters) p.value *= p.name == "c" ? 1.3 : 0.8;
  if (!intersample.empty()) m.intersample = {{"u", intersample}};
  return m;
}

// Smooth: a multisine below 0.3 fs. Stepped: levels held 5-20 samples (what a controller applies).
std::vector<double> input(bool smooth, unsigned seed, std::size_t n = 4000) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> phase(0, 2 * M_PI), level(-1, 1);
  std::vector<double> u(n, 0.0);
  if (smooth) {
    std::vector<double> ph(60);
    for (auto& p : ph) p = phase(rng);
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t l = 0; l < ph.size(); ++l)
        u[k] += 0.2 * std::sin(2 * M_PI * 0.005 * static_cast<double>(l + 1) * static_cast<double>(k) + ph[l]);
    return u;
  }
  std::uniform_int_distribution<int> hold(5, 20);
  for (std::size_t k = 0; k < n;) {
    const double v = level(rng);
    for (int j = hold(rng); j > 0 && k < n; --j) u[k++] = v;
  }
  return u;
}

// The true system driven by `u` as it really is between samples, its output with 1 % noise.
Recording record(const std::vector<double>& u, Intersample truth, unsigned seed) {
  Recording r;
  r.source = "synthetic";
  r.add("u", u);
  r.add("y", std::vector<double>(u.size(), 0.0));
  ModelFile m = parse_model(kOscillator, "truth.json");
  m.intersample = {{"u", intersample_name(truth)}};
  Simulator s(m, r, {20});
  const Eigen::VectorXd y = s.simulate(s.parameter_values()).outputs.col(0);
  const double rms = std::sqrt(y.squaredNorm() / static_cast<double>(y.size()));
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 0.01 * rms);
  std::vector<double> measured(u.size());
  for (std::size_t k = 0; k < u.size(); ++k) measured[k] = y[static_cast<Eigen::Index>(k)] + noise(rng);
  Recording out;
  out.source = "synthetic";
  out.add("u", u);
  out.add("y", measured);
  return out;
}

DiagnosisOptions calibration_only() {
  DiagnosisOptions o;
  o.max_effects = 0;  // the data hypothesis is tested before any physics
  o.threads = 1;
  // Calibrated with the full RK4 substeps: at 8 samples per period the coarse screening step's
  // error would move the nominal's values (k by 0.5 %, validation fit 94 % instead of 99 %) and
  // blur what these tests are about.
  o.screening_substeps = o.final_substeps;
  return o;
}

}  // namespace

TEST(DataHypothesis, SmoothInputDeclaredHeldIsFoundBandLimited) {
  const Recording est = record(input(true, 1), Intersample::bl, 11), val = record(input(true, 2), Intersample::bl, 12);
  const Diagnosis d = diagnose(nominal(""), est, &val, calibration_only());  // an old file: held
  const DataHypothesis& h = d.data_hypothesis;
  ASSERT_TRUE(h.tested) << h.note;
  EXPECT_TRUE(h.found) << h.note;
  EXPECT_EQ(h.declared, "zoh");
  EXPECT_EQ(h.alternative, "bl");
  EXPECT_EQ(h.inputs, std::vector<std::string>{"u"});
  EXPECT_GE(h.ratio, 2.0) << h.note;
  EXPECT_GT(h.fit_alternative_validation.at(0), h.fit_declared_validation.at(0) + 5) << h.note;
  EXPECT_NE(h.finding.find("band-limited, not held"), std::string::npos) << h.finding;
  // Reported apart from physics: never a catalogue effect.
  EXPECT_TRUE(d.effects.empty());
  // The model the fits were made under records the assumption (an old file meant zoh).
  ASSERT_EQ(d.augmented.intersample.size(), 1u);
  EXPECT_EQ(d.augmented.intersample[0].second, "zoh");
}

TEST(DataHypothesis, SmoothInputDeclaredBandLimitedIsNotAFinding) {
  const Recording est = record(input(true, 3), Intersample::bl, 13), val = record(input(true, 4), Intersample::bl, 14);
  const Diagnosis d = diagnose(nominal("bl"), est, &val, calibration_only());
  const DataHypothesis& h = d.data_hypothesis;
  ASSERT_TRUE(h.tested) << h.note;
  EXPECT_FALSE(h.found) << h.note;
  EXPECT_EQ(h.alternative, "zoh");
  EXPECT_LT(h.ratio, 1.0) << h.note;  // held explains the data worse
  EXPECT_GT(d.fit_nominal_validation.at(0), 95.0) << diagnosis_text(d);  // the declared behaviour is the truth
  EXPECT_EQ(d.augmented.intersample, (NamedTexts{{"u", "bl"}}));
  // The override of the app (--intersample) wins over the file.
  DiagnosisOptions o = calibration_only();
  o.intersample = Intersample::zoh;
  const Diagnosis held = diagnose(nominal("bl"), est, &val, o);
  EXPECT_EQ(held.augmented.intersample, (NamedTexts{{"u", "zoh"}}));
  EXPECT_TRUE(held.data_hypothesis.found) << held.data_hypothesis.note;
}

TEST(DataHypothesis, SteppedInputIsNotTestedBandLimited) {
  // A held input has power up to Nyquist: no interpolation is "the" signal, so no data finding.
  const Recording est = record(input(false, 5), Intersample::zoh, 15), val = record(input(false, 6), Intersample::zoh, 16);
  const Diagnosis d = diagnose(nominal(""), est, &val, calibration_only());
  EXPECT_FALSE(d.data_hypothesis.tested);
  EXPECT_FALSE(d.data_hypothesis.found);
  EXPECT_NE(d.data_hypothesis.note.find("no input is band-limited"), std::string::npos) << d.data_hypothesis.note;
}

// ---- Silverbox (../shared/data/silverbox): a real Duffing oscillator, input V1 a band-limited
// voltage sampled with the output. Each test runs the full diagnosis on 86 845 + 40 475 samples
// (20-40 s on the shared 2-core machine): they are the issue's acceptance on real data, and the
// only tests that see a cubic stiffness under real noise and a real input timing.

namespace {

struct Silverbox {
  Recording estimation, validation;
  std::filesystem::path nominal;
};

std::optional<Silverbox> silverbox() {
  const auto nominal = test::shared_data("silverbox/nominal.json");
  const auto est = test::shared_data("silverbox/estimation.csv");
  const auto val = test::shared_data("silverbox/validation.csv");
  if (nominal.empty() || est.empty() || val.empty()) return std::nullopt;
  return Silverbox{read_recording(est.string()), read_recording(val.string()), nominal};
}

const EffectParameter& parameter(const DiagnosedEffect& e, const std::string& name) {
  for (const auto& p : e.parameters)
    if (p.name == name) return p;
  throw std::runtime_error("no parameter " + name + " in " + e.name);
}

}  // namespace

TEST(DataHypothesis, SilverboxHeldNamesCubicStiffnessAndTheInputTiming) {
  const auto s = silverbox();
  if (!s) GTEST_SKIP() << "silverbox data not found under ../shared/data (set SETS_SHARED_DIR)";
  DiagnosisOptions o;
  o.max_effects = 1;  // the first effect is the question; the offset (second) costs another 20 s
  const Diagnosis d = diagnose(load_model_file(s->nominal.string()), s->estimation, &s->validation, o);
  ASSERT_FALSE(d.effects.empty()) << d.verdict;
  EXPECT_EQ(d.effects[0].name, "cubic_stiffness");
  EXPECT_EQ(d.effects[0].equation, "v");
  // check.py rows A -> B (held input): validation 62.8 -> 73.1 %.
  EXPECT_LE(d.fit_nominal_validation.at(0), 65.0);
  EXPECT_GE(d.fit_augmented_validation.at(0), 72.0);
  // The noise of V2 is 0.25-0.3 mV (README: the repeat of the record); within a factor 2.
  ASSERT_EQ(d.noise.size(), 1u);
  EXPECT_GT(d.noise[0].estimate.sigma, 0.3e-3 / 2);
  EXPECT_LT(d.noise[0].estimate.sigma, 0.25e-3 * 2);
  // The input timing is named as a finding about the data.
  EXPECT_TRUE(d.data_hypothesis.found) << d.data_hypothesis.note;
  EXPECT_EQ(d.data_hypothesis.alternative, "bl");
  EXPECT_EQ(d.augmented.intersample, (NamedTexts{{"u", "zoh"}}));
}

TEST(DataHypothesis, SilverboxBandLimitedFitsTheArrowHeadToNearTheNoise) {
  const auto s = silverbox();
  if (!s) GTEST_SKIP() << "silverbox data not found under ../shared/data (set SETS_SHARED_DIR)";
  ModelFile m = load_model_file(s->nominal.string());
  m.intersample = {{"u", "bl"}};  // as examples/models/silverbox_bl.json declares it
  const Diagnosis d = diagnose(m, s->estimation, &s->validation);
  ASSERT_FALSE(d.effects.empty()) << d.verdict;
  EXPECT_EQ(d.effects[0].name, "cubic_stiffness");
  EXPECT_EQ(d.effects[0].equation, "v");
  EXPECT_LE(d.fit_nominal_validation.at(0), 80.0);    // linear, same input
  EXPECT_GE(d.fit_augmented_validation.at(0), 95.0);  // check.py row F: 98.7 %
  // k3: check.py row F (mid-interval input) 7.30e5; inside the reported interval.
  const EffectParameter& k3 = parameter(d.effects[0], "k3");
  EXPECT_NEAR(k3.estimate, 7.3e5, 0.5e5);
  EXPECT_LE(k3.lo, k3.estimate);
  EXPECT_GE(k3.hi, k3.estimate);
  EXPECT_FALSE(d.data_hypothesis.found) << d.data_hypothesis.note;
  EXPECT_EQ(d.augmented.intersample, (NamedTexts{{"u", "bl"}}));
}
