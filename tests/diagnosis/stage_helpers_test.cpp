// Helpers shared by the diagnosis stages (src/diagnosis/stage_helpers.cpp): the misfit cost,
// parameter vectors, scales, the output Jacobian against the closed-form sensitivity of a
// first-order plant, and the linearised bounded-error intervals containing the truth.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "diagnosis/stages.hpp"
#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

TEST(StageHelpers, CostIsTheSumOfSquaredMisfits) {
  EXPECT_EQ(cost_of({100.0}), 0.0);
  EXPECT_NEAR(cost_of({90.0, 100.0}), 0.01, 1e-15);
  EXPECT_NEAR(cost_of({50.0, 0.0}), 0.25 + 1.0, 1e-15);
  EXPECT_NEAR(cost_of({-100.0}), 4.0, 1e-15);  // worse than the mean counts more
}

TEST(StageHelpers, ValuesAndScalesOfTheParameters) {
  ModelFile m = parse_model(R"json({"sample_time": 0.1, "parameters": {"a": -2.5, "Fc": 0.0, "c": 0.0},
    "states": {"x": 0.0}, "derivatives": {"x": "-a*x - Fc - c"}, "outputs": {"x": "y"}})json", "m.json");
  const Eigen::VectorXd p = values_of(m);
  ASSERT_EQ(p.size(), 3);
  EXPECT_EQ(p[0], -2.5);
  store_values(m, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(m.parameter("a")->value, 1.0);
  EXPECT_EQ(m.parameter("c")->value, 3.0);
  store_values(m, p);
  // |value|; a known scale by name wins; 1 when neither says anything.
  EXPECT_EQ(scales_for(m, {0, 1, 2}, {{"Fc", 0.3}}), (std::vector<double>{2.5, 0.3, 1.0}));
  EXPECT_EQ(scales_for(m, {0}, {{"a", 7.0}}), (std::vector<double>{7.0}));
}

TEST(StageHelpers, OutputJacobianIsTheSensitivityOfTheOutputs) {
  // x' = -a x + b, x(0) = 0: x(t) = b/a (1 - e^{-a t}); dx/db = (1 - e^{-a t})/a,
  // dx/da = -b/a^2 (1 - e^{-a t}) + b t e^{-a t} / a.
  const ModelFile m = parse_model(R"json({"sample_time": 0.05, "parameters": {"a": 2.0, "b": 3.0},
    "states": {"x": 0.0}, "derivatives": {"x": "-a*x + b"}, "outputs": {"x": "y"}})json", "m.json");
  Recording r;
  r.add("y", std::vector<double>(60, 0.0));
  const Simulator sim(m, r, {10});
  const Eigen::VectorXd p = sim.parameter_values();
  const Eigen::MatrixXd y0 = sim.simulate(p).outputs;
  const Eigen::MatrixXd J = output_jacobian(sim, p, {0, 1}, {2.0, 3.0}, y0);
  ASSERT_EQ(J.rows(), 60);
  ASSERT_EQ(J.cols(), 2);
  const double a = 2, b = 3;
  for (int k = 0; k < 60; ++k) {
    const double t = 0.05 * k, e = std::exp(-a * t);
    EXPECT_NEAR(J(k, 1), (1 - e) / a, 2e-4) << "t = " << t;
    EXPECT_NEAR(J(k, 0), -b / (a * a) * (1 - e) + b * t * e / a, 2e-4) << "t = " << t;
  }
}

// The threaded Jacobian (one column per worker job, a simulator per worker) is the serial one bit
// for bit on any number of threads, and its columns are not all equal (so a job that wrote the
// wrong column would show).
TEST(StageHelpers, ThreadedOutputJacobianIsTheSerialOneBitForBit) {
  const ModelFile m = parse_model(R"json({"sample_time": 0.05, "inputs": {"u": "u"},
    "parameters": {"a": 2.0, "b": 3.0, "c": 0.5}, "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "-a*x - c*v + b*u - c*x^3"}, "outputs": {"x": "y", "v": "w"}})json", "m.json");
  Recording r;
  std::vector<double> u(80);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = std::sin(0.3 * static_cast<double>(k)) + (k % 7 < 3 ? 0.5 : -0.5);
  r.add("u", u);
  r.add("y", std::vector<double>(80, 0.0));
  r.add("w", std::vector<double>(80, 0.0));
  const Simulator sim(m, r, {5});
  const Eigen::VectorXd p = sim.parameter_values();
  const Eigen::MatrixXd y0 = sim.simulate(p).outputs;
  const std::vector<int> free = {0, 1, 2};
  const std::vector<double> scale = {2.0, 3.0, 0.5};
  const Eigen::MatrixXd serial = output_jacobian(sim, p, free, scale, y0);
  ASSERT_EQ(serial.cols(), 3);
  EXPECT_NE(serial.col(0), serial.col(1));
  EXPECT_NE(serial.col(1), serial.col(2));
  for (int threads : {1, 2, 3, 5}) {
    const Eigen::MatrixXd threaded = output_jacobian(m, r, 5, threads, p, free, scale, y0);
    EXPECT_TRUE(threaded == serial) << threads << " threads";
  }
}

TEST(StageHelpers, OutputErrorIntervalsContainTheTruthOfALinearProblem) {
  // R = J (theta_true - estimate) + e with |e| <= 0.1: the strips hold theta_true when the
  // bound (1.5 x the largest |R|) covers the noise, which it does here.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  const int N = 400;
  Eigen::MatrixXd J(N, 2);
  for (int k = 0; k < N; ++k) J(k, 0) = std::sin(0.05 * k), J(k, 1) = 1.0 + 0.3 * std::cos(0.11 * k);
  const Eigen::Vector3d estimate(7.0, 2.0, -1.0);  // parameters 0 and 2 are free
  const Eigen::Vector2d truth(2.02, -0.99);
  Eigen::MatrixXd R(N, 1);
  for (int k = 0; k < N; ++k) R(k, 0) = J(k, 0) * (truth[0] - 2.0) + J(k, 1) * (truth[1] + 1.0) + 0.1 * U(rng);
  const OutputErrorIntervals oe = output_error_intervals(J, R, estimate, {1, 2}, {2.0, 1.0});
  ASSERT_TRUE(oe.built) << oe.note;
  ASSERT_EQ(oe.lo.size(), 2u);
  EXPECT_EQ(oe.stride, 1);
  ASSERT_EQ(oe.delta.size(), 1u);
  EXPECT_NEAR(oe.delta[0], 1.5 * R.cwiseAbs().maxCoeff(), 1e-12);
  for (int i = 0; i < 2; ++i) {
    EXPECT_LE(oe.lo[static_cast<std::size_t>(i)], truth[i]) << i;
    EXPECT_GE(oe.hi[static_cast<std::size_t>(i)], truth[i]) << i;
    EXPECT_LT(oe.hi[static_cast<std::size_t>(i)] - oe.lo[static_cast<std::size_t>(i)], 1.0) << i;  // informative
  }
  // Long records use every stride-th sample, about 1500 per output.
  const Eigen::MatrixXd Jl = J.replicate(10, 1), Rl = R.replicate(10, 1);
  EXPECT_EQ(output_error_intervals(Jl, Rl, estimate, {1, 2}, {2.0, 1.0}).stride, 2);
}

// A model whose residual has a part its parameters cannot produce (a square wave of amplitude 1
// beside a slow sine and a constant) is falsified by strips narrower than that part, and not by
// strips that hold it: the nested rule's question "does the special case fit within the richer
// law's bound".
TEST(StageHelpers, LinearisedStripsAreFalsifiedOnlyByABoundTheResidualCannotMeet) {
  const int N = 400;
  Eigen::MatrixXd J(N, 2), R(N, 1);
  for (int k = 0; k < N; ++k) {
    J(k, 0) = std::sin(0.05 * k), J(k, 1) = 1.0;
    R(k, 0) = 0.3 * J(k, 0) + 0.2 + ((k / 7) % 2 ? 1.0 : -1.0);
  }
  EXPECT_TRUE(linearised_strips_falsified(J, R, {1.0, 1.0}, {0.5}));
  EXPECT_FALSE(linearised_strips_falsified(J, R, {1.0, 1.0}, {1.05}));  // the square wave fits within it
  EXPECT_FALSE(linearised_strips_falsified(J, R, {2.0, 0.5}, {1.05}));  // scales change the units only
}

TEST(StageHelpers, NumbersForTheReport) {
  EXPECT_EQ(fmt(0.000123456), "0.000123");
  EXPECT_EQ(fmt(123456.0, 4), "1.235e+05");
  EXPECT_EQ(fixed1(99.96), "100.0");
  EXPECT_EQ(fixed1(-0.04), "-0.0");
  EXPECT_EQ(fixed1(-1.31002e44), "-1.31e+44");  // a fit of a model far off: three digits, not 45
  EXPECT_EQ(fixed1(999999.94), "999999.9");
}
