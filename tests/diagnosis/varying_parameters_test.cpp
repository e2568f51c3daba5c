// The varying-parameter stage of the diagnosis (src/diagnosis/varying_parameters.cpp), run through
// diagnose() with no effects searched.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/models/model_file.hpp"

using namespace sets;

// A plant whose stiffness steps from 4 to 7 at t = 23.7 s, diagnosed from the constant-parameter
// model: the time-varying estimates must name k and a window holding the step.
TEST(Diagnosis, VaryingParameterNamesTheSteppingParameterAndWhen) {
  const char* nominal = R"({"name": "axis", "time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.2, "k": 3.5, "c": 1.0}, "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})";
  ModelFile truth = parse_model(nominal);
  *truth.derivative("v") = "(u - (4 + 3*(t >= 23.7))*x - 0.8*v)/1.0";
  const int n = 4000;
  const double Ts = 0.01;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> level(-2, 2), hold(0.5, 3.0);
  std::vector<double> t(n), u(n);
  double next = 0, value = 0;
  for (int k = 0; k < n; ++k) {
    t[static_cast<std::size_t>(k)] = k * Ts;
    if (k * Ts >= next) value = level(rng), next = k * Ts + hold(rng);
    u[static_cast<std::size_t>(k)] = value;
  }
  Recording r;
  r.add("t", t);
  r.add("u", u);
  r.add("x_meas", std::vector<double>(n, 0.0));
  Simulator sim(truth, r);
  const Eigen::VectorXd x = sim.simulate(sim.parameter_values()).outputs.col(0);
  const double sd = std::sqrt((x.array() - x.mean()).square().mean());
  std::normal_distribution<double> noise(0.0, 0.01 * sd);
  std::vector<double> meas(n);
  for (int k = 0; k < n; ++k) meas[static_cast<std::size_t>(k)] = x[k] + noise(rng);
  r.add("x_meas", meas);

  DiagnosisOptions opt;
  opt.max_effects = 0;  // only the mismatch location is tested here
  const Diagnosis d = diagnose(parse_model(nominal), r, nullptr, opt);
  ASSERT_EQ(d.varying.size(), 3u);
  const VaryingParameter& v = d.varying.front();
  std::ostringstream trace;  // the estimates, shown when an expectation fails
  for (const auto& p : d.varying) {
    trace << p.name << " (" << p.method << ", explained " << p.explained << ", squared " << p.explained_squared << "):";
    for (const auto& s : p.trajectory) trace << " " << s.value;
    trace << "; when:";
    for (const auto& w : p.when) trace << " [" << w.first << ", " << w.second << "]";
    trace << "\n";
  }
  if (std::getenv("SETS_VERBOSE")) std::cout << trace.str();
  SCOPED_TRACE(trace.str());
  EXPECT_EQ(v.name, "k");
  ASSERT_FALSE(v.when.empty());
  EXPECT_LE(v.when.front().first, 23.7);
  EXPECT_GE(v.when.front().second, 23.7);
  // The estimated trajectory is lower before the step than after it.
  ASSERT_FALSE(v.trajectory.empty());
  EXPECT_LT(v.trajectory.front().value, v.trajectory.back().value);
  EXPECT_GT(v.explained, d.varying[1].explained);
}
