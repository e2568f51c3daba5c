// Calibration by output error (src/diagnosis/calibration.cpp): fits in percent, Levenberg-Marquardt
// recovering the parameters of a noise-free first-order plant from a wrong start, whether it stopped
// on its tolerances or its budget, bounds kept by clamping, and a blow-up reported as ok = false
// rather than thrown, and a Jacobian whose columns run side by side that is Eigen's NumericalDiff's
// bit for bit.

#include "sets/diagnosis/calibration.hpp"

#include <gtest/gtest.h>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include <algorithm>
#include <cmath>
#include <vector>

#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"

using namespace sets;

namespace {

// x' = -a x + b u, y = x, a = 2, b = 1.5, on steps of u (noise-free), 4 s at 20 ms.
const char* kFirstOrder = R"json({"sample_time": 0.02, "inputs": {"u": "u"}, "parameters": {"a": 2.0, "b": 1.5},
  "states": {"x": 0.0}, "derivatives": {"x": "-a*x + b*u"}, "outputs": {"x": "y"}})json";

Recording first_order_record() {
  const ModelFile truth = parse_model(kFirstOrder, "truth");
  Recording r;
  std::vector<double> u(200);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = (k / 40) % 2 == 0 ? 1.0 : -0.5;
  r.add("u", u);
  r.add("y", std::vector<double>(u.size(), 0.0));
  Simulator sim(truth, r);
  const Eigen::VectorXd y = sim.simulate(sim.parameter_values()).outputs.col(0);
  r.add("y", std::vector<double>(y.data(), y.data() + y.size()));
  return r;
}

}  // namespace

TEST(Calibration, FitIsOneHundredForAPerfectModelAndZeroForTheMean) {
  Eigen::MatrixXd y(4, 2);
  y << 1, 10, 2, 20, 3, 10, 4, 20;
  EXPECT_EQ(fits(y, y), (std::vector<double>{100.0, 100.0}));
  Eigen::MatrixXd mean(4, 2);
  mean.col(0).setConstant(2.5);
  mean.col(1).setConstant(15);
  const auto f = fits(y, mean);
  EXPECT_NEAR(f[0], 0.0, 1e-12);
  EXPECT_NEAR(f[1], 0.0, 1e-12);
  EXPECT_LT(fits(y, 2 * mean)[0], 0.0);  // worse than the mean
}

TEST(Calibration, RecoversTheParametersOfANoiseFreeFirstOrderPlant) {
  const Recording r = first_order_record();
  ModelFile m = parse_model(kFirstOrder, "nominal");
  m.parameter("a")->value = 1.0;  // wrong start
  m.parameter("b")->value = 1.0;
  const Simulator sim(m, r);
  const CalibrationResult before = evaluate(sim, sim.parameter_values());
  ASSERT_TRUE(before.ok);
  EXPECT_LT(before.fit[0], 90.0);
  const CalibrationResult c = calibrate(sim, sim.parameter_values(), {0, 1});
  ASSERT_TRUE(c.ok);
  EXPECT_NEAR(c.parameters[0], 2.0, 1e-4);
  EXPECT_NEAR(c.parameters[1], 1.5, 1e-4);
  EXPECT_GT(c.fit[0], 99.99);
  EXPECT_NEAR(c.cost, (1 - c.fit[0] / 100) * (1 - c.fit[0] / 100), 1e-15);
  EXPECT_EQ(c.free, (std::vector<int>{0, 1}));
  EXPECT_GT(c.evaluations, 2);
  // Only b free: a stays where it is, b compensates as well as it can.
  const CalibrationResult only_b = calibrate(sim, sim.parameter_values(), {1});
  EXPECT_EQ(only_b.parameters[0], 1.0);
  EXPECT_LT(only_b.fit[0], c.fit[0]);
}

TEST(Calibration, SaysWhetherItStoppedOnItsTolerancesOrOnItsBudget) {
  const Recording r = first_order_record();
  ModelFile m = parse_model(kFirstOrder, "nominal");
  m.parameter("a")->value = 1.0;
  m.parameter("b")->value = 1.0;
  const Simulator sim(m, r);
  const CalibrationResult full = calibrate(sim, sim.parameter_values(), {0, 1});
  ASSERT_TRUE(full.ok);
  EXPECT_TRUE(full.converged);
  // Eigen counts the Jacobian's simulations in its budget: max_evaluations / (n + 1) = 4 in all,
  // one Jacobian and one step, far from the optimum.
  CalibrationOptions o;
  o.max_evaluations = 12;
  const CalibrationResult cut = calibrate(sim, sim.parameter_values(), {0, 1}, o);
  ASSERT_TRUE(cut.ok);
  EXPECT_FALSE(cut.converged);
  EXPECT_LE(cut.evaluations, 5);
  EXPECT_LT(cut.fit[0], full.fit[0]);
  // Continued from where it stopped, it reaches the same optimum.
  const CalibrationResult more = calibrate(sim, cut.parameters, {0, 1});
  EXPECT_TRUE(more.converged);
  EXPECT_NEAR(more.parameters[0], 2.0, 1e-4);
  EXPECT_TRUE(calibrate(sim, sim.parameter_values(), {}).converged);  // nothing free: nothing to do
}

TEST(Calibration, BoundsOfTheModelFileAreKept) {
  const Recording r = first_order_record();
  ModelFile m = parse_model(kFirstOrder, "nominal");
  m.parameter("a")->value = 1.0;
  m.parameter("a")->max = 1.6;  // the truth (2) lies outside
  const Simulator sim(m, r);
  const CalibrationResult c = calibrate(sim, sim.parameter_values(), {0, 1});
  ASSERT_TRUE(c.ok);
  EXPECT_LE(c.parameters[0], 1.6);
  EXPECT_GT(c.parameters[0], 1.5);  // pressed against the bound
}

TEST(Calibration, AStartThatBlowsUpIsNotOk) {
  const ModelFile m = parse_model(R"json({"sample_time": 0.1, "parameters": {"k": 1.0}, "states": {"x": 1.0},
    "derivatives": {"x": "k*x*x"}, "outputs": {"x": "y"}})json", "blow.json");
  Recording r;
  r.add("y", std::vector<double>(30, 1.0));
  const Simulator sim(m, r);
  EXPECT_FALSE(evaluate(sim, sim.parameter_values()).ok);  // x' = x^2 escapes at t = 1
  EXPECT_FALSE(calibrate(sim, sim.parameter_values(), {0}).ok);
}

namespace {

// The output error calibrate() minimises, one simulation per call: Eigen's NumericalDiff over it
// is the reference for calibrate()'s own forward differences.
struct One_at_a_time {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  const Simulator* sim = nullptr;
  Eigen::VectorXd scale;
  int inputs() const { return static_cast<int>(scale.size()); }
  int values() const { return static_cast<int>(sim->measured().rows()); }
  Eigen::VectorXd parameters(const Eigen::VectorXd& z) const {
    Eigen::VectorXd p(z.size());
    for (Eigen::Index i = 0; i < z.size(); ++i) p[i] = std::clamp(scale[i] * z[i], -1e300, 1e300);
    return p;
  }
  int operator()(const Eigen::VectorXd& z, Eigen::VectorXd& f) const {
    const Eigen::VectorXd& y = sim->measured().col(0);
    Eigen::MatrixXd yhat;
    if (!sim->simulate_outputs(parameters(z), yhat)) {  // a trial step that blows up
      f = Eigen::VectorXd::Constant(values(), 1e3 / std::sqrt(static_cast<double>(values())));
      return 0;
    }
    f = (y - yhat.col(0)) * (1.0 / (y.array() - y.mean()).matrix().norm());
    return 0;
  }
};

}  // namespace

TEST(Calibration, ItsJacobianIsEigensForwardDifferenceBitForBit) {
  // Three free parameters, so that the Jacobian's three columns run side by side
  // (Simulator::simulate_outputs_each), on a plant with a cubic term.
  const char* cubic = R"json({"sample_time": 0.02, "inputs": {"u": "u"},
    "parameters": {"a": 2.0, "b": 1.5, "c": 0.8}, "states": {"x": 0.0},
    "derivatives": {"x": "-a*x + b*u - c*x*x*x"}, "outputs": {"x": "y"}})json";
  Recording r = first_order_record();
  {
    const Simulator truth(parse_model(cubic, "truth"), r);
    const Eigen::VectorXd y = truth.simulate(truth.parameter_values()).outputs.col(0);
    r.add("y", std::vector<double>(y.data(), y.data() + y.size()));
  }
  ModelFile m = parse_model(cubic, "nominal");
  m.parameter("a")->value = 1.3;
  m.parameter("b")->value = 0.7;
  m.parameter("c")->value = 0.1;
  const Simulator sim(m, r);
  const Eigen::VectorXd start = sim.parameter_values();
  const CalibrationResult c = calibrate(sim, start, {0, 1, 2});
  ASSERT_TRUE(c.ok);
  One_at_a_time reference;
  reference.sim = &sim;
  reference.scale = start.cwiseAbs();
  Eigen::NumericalDiff<One_at_a_time> diff(reference, 1e-6);
  Eigen::LevenbergMarquardt<Eigen::NumericalDiff<One_at_a_time>> lm(diff);
  lm.parameters.maxfev = 300 / 4;
  lm.parameters.ftol = 1e-7;
  lm.parameters.xtol = 1e-7;
  lm.parameters.factor = 10;
  Eigen::VectorXd z = Eigen::VectorXd::Ones(3);
  lm.minimize(z);
  const Eigen::VectorXd expected = reference.parameters(z);
  for (Eigen::Index i = 0; i < 3; ++i) EXPECT_EQ(c.parameters[i], expected[i]) << "parameter " << i;
  EXPECT_GT(lm.njev + lm.nfev, 10);  // LM took several steps: the comparison is not of the start
  EXPECT_NEAR(c.parameters[2], 0.8, 1e-3);
}
