// Intersample behaviour of inputs: the model-file field, the interpolants and the simulator's
// RK4 stages.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sets/core/error.hpp"
#include "sets/data/intersample.hpp"
#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"

using namespace sets;

namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "<no exception>";
}

// x' = u: the state integrates the input, so x(t_k) shows exactly what the input did between samples.
const char* kIntegrator = R"json({"sample_time": 0.1, "inputs": {"u": "u"}, "states": {"x": 0.0},
  "derivatives": {"x": "u"}, "outputs": {"x": "y"}})json";

ModelFile integrator(const std::string& mode) {
  ModelFile m = parse_model(kIntegrator, "integrator.json");
  if (!mode.empty()) m.intersample = {{"u", mode}};
  return m;
}

Recording record(const std::vector<double>& u) {
  Recording r;
  r.source = "test";
  r.add("u", u);
  r.add("y", std::vector<double>(u.size(), 0.0));
  return r;
}

Eigen::VectorXd integrate(const std::string& mode, const std::vector<double>& u, int substeps = 10) {
  Simulator s(integrator(mode), record(u), {substeps});
  return s.simulate(s.parameter_values()).outputs.col(0);
}

}  // namespace

TEST(ModelFile, IntersampleIsReadCheckedAndWrittenBack) {
  const ModelFile m = parse_model(R"json({"sample_time": 1, "inputs": {"u": "U", "w": "W"},
    "intersample": {"u": "bl"}, "states": {"x": 0}, "derivatives": {"x": "u + w"}, "outputs": {"x": "y"}})json", "m.json");
  ASSERT_EQ(m.intersample.size(), 1u);
  EXPECT_EQ(declared_intersample(m, "u"), Intersample::bl);
  EXPECT_EQ(declared_intersample(m, "w"), Intersample::zoh);  // not declared: held
  EXPECT_EQ(parse_model(to_json_text(m), "back").intersample, m.intersample);
  // An old file (no field) means zoh for every input; made explicit, it records that.
  const ModelFile old = parse_model(kIntegrator, "old.json");
  EXPECT_TRUE(old.intersample.empty());
  EXPECT_EQ(to_json_text(old).find("intersample"), std::string::npos);
  const ModelFile explicit_ = with_intersample(old);
  ASSERT_EQ(explicit_.intersample.size(), 1u);
  EXPECT_EQ(explicit_.intersample[0].second, "zoh");
  EXPECT_EQ(with_intersample(m, Intersample::foh).intersample,
            (NamedTexts{{"u", "foh"}, {"w", "foh"}}));
  EXPECT_EQ(with_intersample(m, std::vector<std::string>{"w"}, Intersample::bl).intersample,
            (NamedTexts{{"u", "bl"}, {"w", "bl"}}));
}

TEST(ModelFile, BadIntersampleIsNamed) {
  auto msg = message_of([] {
    parse_model(R"json({"sample_time": 1, "inputs": {"u": "U"}, "intersample": {"u": "cubic"},
      "states": {"x": 0}, "derivatives": {"x": "u"}, "outputs": {"x": "y"}})json", "m.json");
  });
  EXPECT_NE(msg.find("m.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("intersample.u"), std::string::npos) << msg;
  msg = message_of([] {
    parse_model(R"json({"sample_time": 1, "inputs": {"u": "U"}, "intersample": {"v": "bl"},
      "states": {"x": 0}, "derivatives": {"x": "u"}, "outputs": {"x": "y"}})json", "m.json");
  });
  EXPECT_NE(msg.find("\"intersample.v\" is not an input"), std::string::npos) << msg;
  msg = message_of([] { parse_intersample("linear", "--intersample"); });
  EXPECT_NE(msg.find("--intersample"), std::string::npos) << msg;
  EXPECT_NE(msg.find("\"linear\""), std::string::npos) << msg;
}

TEST(Intersample, HeldAndLinearInputsIntegrateExactly) {
  // u_k = k: held, x_k = Ts (0 + 1 + ... + k-1); linear, x_k = Ts k^2 / 2 (RK4 is exact for both).
  std::vector<double> u(12);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = static_cast<double>(k);
  const Eigen::VectorXd zoh = integrate("zoh", u, 3), foh = integrate("foh", u, 3), none = integrate("", u, 3);
  for (int k = 0; k < 12; ++k) {
    EXPECT_NEAR(zoh[k], 0.1 * k * (k - 1) / 2.0, 1e-12) << k;
    EXPECT_NEAR(foh[k], 0.1 * k * k / 2.0, 1e-12) << k;
    EXPECT_EQ(none[k], zoh[k]) << k;  // an old file is held
  }
}

TEST(Intersample, BandLimitedInputIntegratesCubicsExactly) {
  // Each mode is exact on polynomials of its degree: zoh on constants, foh on lines (above), bl on
  // cubics, up to both ends of the record (the spline's end slopes are exact for cubics). RK4 is
  // Simpson's rule on x' = u(t), exact for cubics, so x(t_k) is the integral itself.
  auto cubic = [](double s) { return 0.5 - 2 * s + 0.3 * s * s - 0.01 * s * s * s; };
  auto integral = [](double s) { return 0.5 * s - s * s + 0.1 * s * s * s - 0.0025 * s * s * s * s; };
  std::vector<double> u(30);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = cubic(static_cast<double>(k));
  for (int substeps : {1, 3}) {
    const Eigen::VectorXd bl = integrate("bl", u, substeps), foh = integrate("foh", u, substeps);
    double foh_error = 0;
    for (int k = 0; k < 30; ++k) {
      EXPECT_NEAR(bl[k], 0.1 * integral(k), 1e-10 * 60) << k << " substeps " << substeps;  // Ts = 0.1
      foh_error = std::max(foh_error, std::abs(foh[k] - 0.1 * integral(k)));
    }
    EXPECT_GT(foh_error, 1e-3);  // a line is not a cubic: the test sees the difference
  }
  // Fewer than 5 samples: too short for the spline, linear between samples.
  EXPECT_EQ(integrate("bl", {0, 1, 4, 9}, 2), integrate("foh", {0, 1, 4, 9}, 2));
}

TEST(Intersample, BandLimitedInputFollowsTheSignalBetweenSamples) {
  // A sine sampled 8 times per period: holding it delays it by half a sample; the spline follows it.
  const double Ts = 0.1, w = 2 * M_PI / (8 * Ts);
  std::vector<double> u(200);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = std::sin(w * Ts * static_cast<double>(k));
  const Eigen::VectorXd zoh = integrate("zoh", u), foh = integrate("foh", u), bl = integrate("bl", u);
  double e_zoh = 0, e_foh = 0, e_bl = 0;
  for (int k = 20; k < 180; ++k) {  // away from the ends
    const double truth = (1 - std::cos(w * Ts * k)) / w;
    e_zoh = std::max(e_zoh, std::abs(zoh[k] - truth));
    e_foh = std::max(e_foh, std::abs(foh[k] - truth));
    e_bl = std::max(e_bl, std::abs(bl[k] - truth));
  }
  const double amplitude = 1 / w;
  EXPECT_GT(e_zoh, 0.2 * amplitude);   // half a sample of lag: about w Ts / 2 of the amplitude
  EXPECT_LT(e_foh, 0.15 * amplitude);
  EXPECT_LT(e_bl, 0.005 * amplitude);  // the spline's error is O((w Ts)^4)
  EXPECT_LT(e_bl, 0.2 * e_foh);
}

TEST(Intersample, SplinePassesThroughCubicsAndTheSamples) {
  std::vector<double> u(40);
  auto cubic = [](double x) { return 0.5 - 2 * x + 0.3 * x * x - 0.01 * x * x * x; };
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = cubic(static_cast<double>(k));
  const auto mid = input_between_samples(u, Intersample::bl, 0.5);
  for (std::size_t k = 0; k + 1 < u.size(); ++k) EXPECT_NEAR(mid[k], cubic(k + 0.5), 1e-9 * 640) << k;
  EXPECT_EQ(mid.back(), u.back());  // after the last sample: held
  const IntersampleInput in(u, Intersample::bl, 4);
  for (std::size_t k = 0; k + 1 < u.size(); ++k) {
    EXPECT_EQ(in.at(k, 0), u[k]);
    EXPECT_EQ(in.at(k, 8), u[k + 1]);
    EXPECT_NEAR(in.at(k, 3), cubic(k + 3.0 / 8), 1e-9 * 640);
  }
  // foh and zoh at the midpoint.
  EXPECT_DOUBLE_EQ(input_between_samples(u, Intersample::foh, 0.5)[3], 0.5 * (u[3] + u[4]));
  EXPECT_DOUBLE_EQ(input_between_samples(u, Intersample::zoh, 0.5)[3], u[3]);
}

TEST(Intersample, SampledSignalsStayHeldWhateverTheInput) {
  // `sampled` values are defined at the sample instants: a band-limited input does not change them.
  const char* text = R"json({"sample_time": 0.5, "inputs": {"u": "u"}, "intersample": {"u": "bl"},
    "states": {"x": 0.0}, "sampled": {"us": "u"}, "derivatives": {"x": "us"}, "outputs": {"x": "y"}})json";
  const ModelFile m = parse_model(text, "hold.json");
  EXPECT_TRUE(inputs_between_samples(m).empty());
  Simulator s(m, record({1, 3, -2, 0, 5, 1}));
  const Eigen::VectorXd x = s.simulate(s.parameter_values()).series("x");
  EXPECT_NEAR(x[1], 0.5, 1e-12);
  EXPECT_NEAR(x[2], 2.0, 1e-12);
  EXPECT_NEAR(x[3], 1.0, 1e-12);
  EXPECT_EQ(inputs_between_samples(integrator("bl")), std::vector<std::string>{"u"});
}

TEST(Intersample, PowerShareAboveSaysWhetherAnInputIsBandLimited) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  std::vector<double> smooth(4096), white(4096);
  for (std::size_t k = 0; k < smooth.size(); ++k) {
    smooth[k] = std::sin(0.3 * static_cast<double>(k)) + 0.5 * std::cos(0.71 * static_cast<double>(k));
    white[k] = g(rng);
  }
  EXPECT_LT(power_share_above(smooth), 1e-3);  // both lines below 0.12 cycles/sample
  EXPECT_NEAR(power_share_above(white), 0.25, 0.03);
  EXPECT_EQ(power_share_above(std::vector<double>(100, 2.0)), 1.0);  // no power: not band-limited
}
