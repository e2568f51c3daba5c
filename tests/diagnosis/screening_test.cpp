// Screening by least squares: scale-free (the same plant at a scale 10^6 larger is screened the
// same), and the true effect is among the best screened.

#include <gtest/gtest.h>

#include "sets/data/simulation.hpp"
#include "sets/diagnosis/calibration.hpp"
#include "sets/diagnosis/screening.hpp"
#include "support/plant_fixtures.hpp"

using namespace sets;

namespace {

// A hardening spring whose cubic term matters at a large scale: k3 = 12 * s^-2 for positions
// scaled by s (x = s * x_unit), with the linear parts scaled alike.
SyntheticPlant hardening_spring(double s) {
  const std::string k3 = std::to_string(12.0 / (s * s));
  const std::string truth = R"({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.0, "k": 4.0, "c": 0.8, "g": {"value": )" + std::to_string(s) + R"(, "fixed": true}},
    "states": {"x": 0.0, "v": 0.0}, "derivatives": {"x": "v", "v": "(g*u - k*x - c*v - )" + k3 + R"(*x^3)/m"},
    "outputs": {"x": "x_meas"}})";
  const std::string nominal = R"({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.0, "k": 4.0, "c": 0.8, "g": {"value": )" + std::to_string(s) + R"(, "fixed": true}},
    "states": {"x": 0.0, "v": 0.0}, "derivatives": {"x": "v", "v": "(g*u - k*x - c*v)/m"},
    "outputs": {"x": "x_meas"}})";
  return test::simulated_plant(truth, nominal, 3000, 0.01, {}, 0.01, 3);
}

Screening screened(const SyntheticPlant& p) {
  Simulator s(p.nominal, p.estimation, {2});
  ModelFile cal = p.nominal;
  const auto r = calibrate(s, s.parameter_values(), s.free_parameters());
  for (std::size_t i = 0; i < cal.parameters.size(); ++i) cal.parameters[i].value = r.parameters[static_cast<Eigen::Index>(i)];
  Simulator sc(cal, p.estimation, {2});
  const auto sim = sc.simulate(sc.parameter_values());
  ScreeningOptions o;
  o.noise_bound = {5 * p.noise_sigma.at(0)};
  return screen_hypotheses(cal, p.estimation, generate_candidates(cal, sim, p.estimation), o);
}

}  // namespace

TEST(Screening, BoundedLeastSquaresRespectsBounds) {
  Eigen::MatrixXd A(3, 2);
  A << 1, 0, 0, 1, 1, 1;
  const Eigen::Vector3d b(1, -2, -1);
  const Eigen::VectorXd free = bounded_least_squares(A, b, Eigen::Vector2d(-1e300, -1e300), Eigen::Vector2d(1e300, 1e300));
  EXPECT_NEAR(free[1], -2, 1e-9);
  const Eigen::VectorXd x = bounded_least_squares(A, b, Eigen::Vector2d(-1e300, 0), Eigen::Vector2d(1e300, 1e300));
  EXPECT_EQ(x[1], 0.0);
  EXPECT_NEAR(x[0], 0.0, 1e-9);  // the least squares of the rest with x1 at its bound: x0 = 1 and x0 = -1
}

TEST(Screening, CubicStiffnessIsScreenedFirstAtAnyScale) {
  for (double s : {1.0, 1e-3, 1e3}) {
    const Screening sc = screened(hardening_spring(s));
    ASSERT_FALSE(sc.ranked.empty());
    EXPECT_EQ(sc.ranked.front().candidate.effect, "cubic_stiffness") << "scale " << s;
    EXPECT_GT(sc.ranked.front().gain, 0.5) << "scale " << s;
    // Its start is the least-squares k3: near the truth in the data's own units.
    const auto& c = sc.ranked.front().candidate;
    const double k3 = c.model.parameter(c.parameters.front())->value;
    EXPECT_NEAR(k3 * s * s, 12.0, 6.0) << "scale " << s;
  }
}
