// The simulator of model files (sets/data/simulation.hpp): errors naming the symbol, column, row or
// time; RK4 against the closed form; prev() and sampled (held) signals.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "sets/core/error.hpp"
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

const char* kDecay = R"json({"name": "decay", "sample_time": 0.1, "inputs": {"u": "u"},
  "parameters": {"a": 2.0}, "states": {"x": 1.0},
  "sampled": {"us": "u + 0*prev(x, 1)", "lag": "prev(x, 2)"},
  "derivatives": {"x": "-a*x + us"}, "outputs": {"x": "y", "lag": "y"}})json";

Recording columns(int n, double u) {
  Recording r;
  r.source = "test";
  r.add("u", std::vector<double>(static_cast<std::size_t>(n), u));
  r.add("y", std::vector<double>(static_cast<std::size_t>(n), 0.0));
  return r;
}

}  // namespace

TEST(ModelFile, UnknownSymbolIsNamed) {
  ModelFile m = parse_model(kDecay, "decay.json");
  *m.derivative("x") = "-a*x + us*gain";
  const auto msg = message_of([&] { Simulator s(m, columns(10, 0)); });
  EXPECT_NE(msg.find("unknown symbol \"gain\""), std::string::npos) << msg;
  EXPECT_NE(msg.find("derivatives.x"), std::string::npos) << msg;
}

TEST(Recording, MissingColumnIsNamed) {
  ModelFile m = parse_model(kDecay, "decay.json");
  m.inputs = {{"u", "force"}};
  const auto msg = message_of([&] { Simulator s(m, columns(10, 0)); });
  EXPECT_NE(msg.find("missing column \"force\""), std::string::npos) << msg;
}

TEST(Simulation, TimeMustIncrease) {
  ModelFile m = parse_model(kDecay, "decay.json");
  m.sample_time.reset();
  m.time_column = "t";
  Recording r = parse_csv("t,u,y\n0,0,0\n0.1,0,0\n0.1,0,0\n0.3,0,0\n", "r.csv");
  const auto msg = message_of([&] { Simulator s(m, r); });
  EXPECT_NE(msg.find("does not increase at data row 3"), std::string::npos) << msg;
}

TEST(Simulation, BlowUpNamesTheTime) {
  ModelFile m = parse_model(R"json({"sample_time": 0.1, "states": {"x": 1.0},
    "derivatives": {"x": "x*x"}, "outputs": {"x": "y"}})json", "blow.json");
  Simulator s(m, columns(30, 0));
  const auto msg = message_of([&] { s.simulate(s.parameter_values()); });
  // x' = x^2, x(0) = 1 escapes at t = 1.
  EXPECT_NE(msg.find("blew up at t = "), std::string::npos) << msg;
  const double t = std::stod(msg.substr(msg.find("t = ") + 4));
  EXPECT_NEAR(t, 1.0, 0.05);
}

TEST(Simulation, Rk4MatchesExponentialAndPrevHoldsPastSamples) {
  const ModelFile m = parse_model(kDecay, "decay.json");
  Simulator s(m, columns(21, 0.0));
  const auto r = s.simulate(s.parameter_values());
  const Eigen::VectorXd x = r.series("x"), lag = r.series("lag");
  for (int k = 0; k <= 20; ++k) EXPECT_NEAR(x[k], std::exp(-2.0 * 0.1 * k), 1e-9);
  EXPECT_DOUBLE_EQ(lag[0], x[0]);  // no earlier sample: the first one
  EXPECT_DOUBLE_EQ(lag[1], x[0]);
  for (int k = 2; k <= 20; ++k) EXPECT_DOUBLE_EQ(lag[k], x[k - 2]);
}

TEST(Simulation, SampledInputIsHeldOverTheSample) {
  // x' = us with us held: x grows by us*Ts per sample exactly.
  const ModelFile m = parse_model(R"json({"sample_time": 0.5, "inputs": {"u": "u"}, "states": {"x": 0.0},
    "sampled": {"us": "u"}, "derivatives": {"x": "us"}, "outputs": {"x": "y"}})json", "hold.json");
  Recording r;
  r.add("u", {1, 3, -2, 0});
  r.add("y", {0, 0, 0, 0});
  Simulator s(m, r);
  const Eigen::VectorXd x = s.simulate(s.parameter_values()).series("x");
  EXPECT_NEAR(x[1], 0.5, 1e-12);
  EXPECT_NEAR(x[2], 2.0, 1e-12);
  EXPECT_NEAR(x[3], 1.0, 1e-12);
}

TEST(Simulation, AnExpressionThatIsOneSymbolIsThatSymbolsValue) {
  // Such expressions are read from the symbol's slot, not evaluated (a position's derivative `v`):
  // a state, a parameter, the time and a signal, on polynomials of degree <= 2 that RK4 integrates
  // exactly.
  const ModelFile m = parse_model(R"json({"sample_time": 0.25, "parameters": {"a": 3.0},
    "states": {"x": 0.0, "v": 1.0, "w": 0.0}, "signals": {"z": "v"},
    "derivatives": {"x": "v", "v": "a", "w": "t"}, "outputs": {"x": "y"}})json", "one_symbol.json");
  const Simulator s(m, columns(9, 0.0));
  const SimulationResult r = s.simulate(s.parameter_values());
  for (int k = 0; k < 9; ++k) {
    const double t = 0.25 * k;
    EXPECT_NEAR(r.series("x")[k], t + 1.5 * t * t, 1e-12) << k;
    EXPECT_NEAR(r.series("v")[k], 1 + 3 * t, 1e-12) << k;
    EXPECT_NEAR(r.series("w")[k], t * t / 2, 1e-12) << k;
    EXPECT_EQ(r.series("z")[k], r.series("v")[k]) << k;
  }
  Eigen::VectorXd p(1);
  p << -1.0;  // the parameter's slot is read at each call
  EXPECT_NEAR(s.simulate(p).series("v")[8], 1 - 2.0, 1e-12);
}

// A model with signals, a sampled signal with prev() of a state and of itself, an input between
// samples (foh), a friction-like sign and a condition runs can take differently; g*v^3 blows up
// for a large g.
ModelFile side_by_side_model() {
  return parse_model(R"json({"sample_time": 0.05, "inputs": {"u": "u"},
    "intersample": {"u": "foh"},
    "parameters": {"k": 2.0, "c": 0.3, "Fc": 0.2, "g": 0.0},
    "states": {"x": 0.1, "v": 0.0}, "signals": {"F": "Fc*sign(v) + (x > 0.05 ? c*v : 0.5*c*v)"},
    "sampled": {"us": "u - 0.1*x - 0.05*(x - prev(x, 2))/(2*Ts) + 0.01*prev(us, 1)"}, "derivatives": {"x": "v", "v": "us - k*x - F + g*v^3"},
    "outputs": {"x": "y", "F": "y"}})json", "side_by_side.json");
}

Recording side_by_side_recording() {
  Recording r;
  std::vector<double> u(400), y(400, 0.0);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = std::sin(0.07 * static_cast<double>(k)) + (k % 37 < 5 ? 1.0 : 0.0);
  r.add("u", u);
  r.add("y", y);
  return r;
}

TEST(Simulation, RunsSideBySideGiveEachRunsOutputsBitForBit) {
  // simulate_outputs_each against simulate_outputs column by column, one run blowing up while the
  // others go on.
  const ModelFile m = side_by_side_model();
  const Recording r = side_by_side_recording();
  const Simulator s(m, r, {2});
  Eigen::MatrixXd p(4, 5);
  p.col(0) << 2.0, 0.3, 0.2, 0.0;
  p.col(1) << 2.0 * (1 + 1e-3), 0.3, 0.2, 0.0;
  p.col(2) << 0.5, 0.8, 0.0, 0.0;
  p.col(3) << 2.0, 0.3, 0.2, 5e3;  // v^3 with a large gain: blows up
  p.col(4) << 9.0, 0.01, 1.0, 0.0;
  std::vector<Eigen::MatrixXd> each;
  std::vector<bool> ok;
  s.simulate_outputs_each(p, each, ok);
  ASSERT_EQ(each.size(), 5u);
  for (Eigen::Index j = 0; j < p.cols(); ++j) {
    Eigen::MatrixXd alone;
    const bool alone_ok = s.simulate_outputs(p.col(j), alone);
    EXPECT_EQ(ok[static_cast<std::size_t>(j)], alone_ok) << "run " << j;
    if (alone_ok) EXPECT_TRUE(each[static_cast<std::size_t>(j)] == alone) << "run " << j;  // exact equality
  }
  EXPECT_FALSE(ok[3]);
  EXPECT_TRUE(ok[0] && ok[1] && ok[2] && ok[4]);
  EXPECT_FALSE(each[0] == each[1]);  // the runs are not one run copied
}

TEST(Simulation, ScheduledRunsSideBySideGiveEachRunsOutputsBitForBit) {
  // simulate_outputs_scheduled_each against simulate_outputs_scheduled schedule by schedule:
  // parameters that step, ramp and alternate, each run its own way, one blowing up late.
  const ModelFile m = side_by_side_model();
  const Recording r = side_by_side_recording();
  const Simulator s(m, r, {2});
  const Eigen::Index N = s.samples();
  Eigen::RowVector4d p0(2.0, 0.3, 0.2, 0.0);
  std::vector<Eigen::MatrixXd> schedules(4, p0.replicate(N, 1));
  schedules[1].col(0).segment(100, 100).array() += 0.02;                               // k steps up, then back
  schedules[2].col(1) = Eigen::VectorXd::LinSpaced(N, 0.3, 0.9);                       // c ramps
  for (Eigen::Index k = 0; k < N; k += 2) schedules[3](k, 2) = 0.6;                    // Fc alternates
  schedules.push_back(schedules[0]);
  schedules[4].col(3).tail(N - 200).setConstant(5e3);                                 // g: blows up late
  std::vector<Eigen::MatrixXd> each;
  std::vector<bool> ok;
  s.simulate_outputs_scheduled_each(schedules, each, ok);
  ASSERT_EQ(each.size(), schedules.size());
  for (std::size_t j = 0; j < schedules.size(); ++j) {
    Eigen::MatrixXd alone;
    const bool alone_ok = s.simulate_outputs_scheduled(schedules[j], alone);
    EXPECT_EQ(ok[j], alone_ok) << "run " << j;
    if (alone_ok) EXPECT_TRUE(each[j] == alone) << "run " << j;  // exact equality
  }
  EXPECT_TRUE(ok[0] && ok[1] && ok[2] && ok[3]);
  EXPECT_FALSE(ok[4]);
  for (std::size_t j = 1; j < 4; ++j) EXPECT_FALSE(each[0] == each[j]) << "run " << j;  // each schedule counts
  EXPECT_THROW(s.simulate_outputs_scheduled_each({Eigen::MatrixXd::Zero(N - 1, 4)}, each, ok), InputError);
}
