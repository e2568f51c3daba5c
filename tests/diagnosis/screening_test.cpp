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

namespace {

// A position loop whose sampled PD controller h drives the mass (truth M = 2, c = 3), in the
// truth through a play of 20 (a backlash written with its own past), in the nominal directly.
std::string position_loop(bool play) {
  return std::string(R"J({"time": "t", "inputs": {"r": "r"},
    "parameters": {"M": 2.0, "c": 3.0, "P": {"value": 200, "fixed": true}, "D": {"value": 25, "fixed": true}},
    "states": {"q": 0.0, "v": 0.0},
    "sampled": {"h": "P*(r - q) - D*(q - prev(q, 1))/Ts")J") +
         (play ? R"J(, "h_bl": "max(h - 20, min(h + 20, prev(h_bl, 1)))"}, "derivatives": {"q": "v", "v": "(h_bl - c*v)/M"},)J"
               : R"J(}, "derivatives": {"q": "v", "v": "(h - c*v)/M"},)J") +
         R"J( "outputs": {"q": "q_meas"}})J";
}

}  // namespace

// An actuator candidate (the play on the sampled controller signal h) gets the equation-error
// start of the state equation its signal drives, with the play at its best grid point: the mass
// and the damping fitted jointly from the measurements (the nominal's values are off), and a gain
// over the nominal's equation error.
TEST(Screening, AnActuatorCandidateGetsTheEquationErrorStartOfTheEquationItDrives) {
  const SyntheticPlant p = test::simulated_plant(position_loop(true), position_loop(false), 4000, 0.005, {"r", -1, 1, 0.3, 1.5}, 1e-4, 11);
  ModelFile off = p.nominal;  // off the truth, as a calibration against the wrong structure may leave it
  off.parameter("M")->value = 1.4;
  off.parameter("c")->value = 5.0;
  Simulator s(off, p.estimation, {2});
  const auto sim = s.simulate(s.parameter_values());
  const Screening sc = screen_hypotheses(off, p.estimation, generate_candidates(off, sim, p.estimation));
  const ScreenedHypothesis* bl = nullptr;
  for (const auto& h : sc.ranked)
    if (h.candidate.effect == "backlash" && h.candidate.equation == "h" && h.candidate.parts.empty()) bl = &h;
  ASSERT_NE(bl, nullptr);
  ASSERT_TRUE(std::isfinite(bl->ee_gain));
  EXPECT_GT(bl->ee_gain, 0.1);
  const ModelFile& m = bl->candidate.model;
  const Eigen::VectorXd& ee = bl->starts.back();
  std::size_t iM = 0, ic = 0;
  for (std::size_t i = 0; i < m.parameters.size(); ++i) {
    if (m.parameters[i].name == "M") iM = i;
    if (m.parameters[i].name == "c") ic = i;
  }
  // The mass from the equation error at the play's grid point (the screening's own start keeps the
  // nominal's 1.4); the damping is weakly seen inside a stiff loop (the controller's D dominates),
  // so only its being fitted is asserted. The play stays at the best grid point.
  const Eigen::VectorXd& front = bl->starts.front();
  const auto b = static_cast<Eigen::Index>(m.parameters.size() - 1);
  EXPECT_EQ(m.parameters.back().name, bl->candidate.parameters.front());
  EXPECT_NEAR(ee[static_cast<Eigen::Index>(iM)], 2.0, 0.2);
  EXPECT_NE(ee[static_cast<Eigen::Index>(ic)], front[static_cast<Eigen::Index>(ic)]);
  EXPECT_EQ(ee[b], front[b]);
}
