// Equation-error PUIs of one derivative (sets/diagnosis/equation_error.hpp).

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "sets/diagnosis/equation_error.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "sets/models/model_file.hpp"
#include "support/plant_fixtures.hpp"

using namespace sets;

namespace {

// The Coulomb plant's nominal with the friction term and its free parameter Fc added.
ModelFile with_coulomb_friction(ModelFile m) {
  *m.derivative("v") = "(K*u - k*x - c*v - Fc*sign(v))/m";
  ModelParameter fc;
  fc.name = "Fc";
  m.parameters.push_back(fc);
  return m;
}

}  // namespace

// Equation-error PUIs of the Coulomb plant's force balance, measured at values a little off the
// truth (as an estimate would be): every true parameter must lie in its interval, and the
// parameters that enter nonlinearly or through the past of an unmeasured state are refused with a
// reason.
TEST(EquationError, PuiContainsTheTrueParametersOfTheCoulombPlant) {
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  ModelFile m = with_coulomb_friction(p.nominal);
  const std::vector<std::pair<std::string, double>> truth{{"m", 1.0}, {"k", 4.0}, {"c", 0.8}, {"Fc", 0.3}};
  const std::vector<double> off{1.03, 3.9, 0.84, 0.28};
  for (std::size_t i = 0; i < truth.size(); ++i) m.parameter(truth[i].first)->value = off[i];
  const EquationErrorResult r = equation_error_pui(m, p.estimation, "v");
  ASSERT_TRUE(r.built) << r.note;
  EXPECT_EQ(r.order, 2);
  ASSERT_EQ(r.parameters.size(), 4u);
  EXPECT_EQ(r.parameters.front(), "m");  // the inertia: m * v' is affine in k, c, Fc
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    double tv = 0;
    for (const auto& [n, v] : truth)
      if (n == r.parameters[i]) tv = v;
    EXPECT_LE(r.box[static_cast<Eigen::Index>(i)].lower(), tv) << r.parameters[i];
    EXPECT_GE(r.box[static_cast<Eigen::Index>(i)].upper(), tv) << r.parameters[i];
  }
  ModelFile nonlinear = m;
  *nonlinear.derivative("v") = "(K*u - k*x - c*v - Fc*sign(v)*exp(-(v/m)^2))/m";
  EXPECT_FALSE(equation_error_pui(nonlinear, p.estimation, "v").built);
  ModelFile delayed = m;  // the past of an unmeasured (differentiated) state is not known
  *delayed.derivative("v") = "(K*u - k*x - c*prev(v, 3))/m";
  const EquationErrorResult rd = equation_error_pui(delayed, p.estimation, "v");
  EXPECT_FALSE(rd.built);
  EXPECT_NE(rd.note.find("prev"), std::string::npos) << rd.note;
}

// The noise of the differentiated column estimated once by the caller (measured_noise) gives the
// same regression as estimating it inside; a caller's value is used (a tenfold noise changes the
// interval regressors), so the cache can neither be ignored nor disagree unnoticed.
TEST(EquationError, NoiseOfTheColumnsPassedInGivesTheSameRegression) {
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  ModelFile m = with_coulomb_friction(p.nominal);
  const int w = 20;
  const ColumnNoise noise = measured_noise(m, p.estimation);
  ASSERT_EQ(noise.size(), m.outputs.size());
  const EquationErrorRegression inside = equation_error_regressions(m, p.estimation, "v", {w}).front();
  const EquationErrorRegression passed = equation_error_regressions(m, p.estimation, "v", {w}, noise).front();
  ASSERT_TRUE(inside.built) << inside.note;
  ASSERT_TRUE(passed.built) << passed.note;
  ASSERT_EQ(inside.Phi.rows(), passed.Phi.rows());
  ASSERT_EQ(inside.Phi.cols(), passed.Phi.cols());
  int differ = 0;
  ColumnNoise louder = noise;
  for (auto& [column, sigma] : louder) sigma *= 10;
  const EquationErrorRegression loud = equation_error_regressions(m, p.estimation, "v", {w}, louder).front();
  ASSERT_TRUE(loud.built) << loud.note;
  for (Eigen::Index i = 0; i < inside.Phi.rows(); ++i)
    for (Eigen::Index j = 0; j < inside.Phi.cols(); ++j) {
      ASSERT_EQ(inside.Phi(i, j).lower(), passed.Phi(i, j).lower());
      ASSERT_EQ(inside.Phi(i, j).upper(), passed.Phi(i, j).upper());
      differ += loud.Phi(i, j).lower() != inside.Phi(i, j).lower() || loud.Phi(i, j).upper() != inside.Phi(i, j).upper();
    }
  EXPECT_GT(differ, 0);
  const EquationErrorFit a = equation_error_fit(m, p.estimation, "v"), b = equation_error_fit(m, p.estimation, "v", 0, noise);
  ASSERT_TRUE(a.built && b.built);
  EXPECT_EQ(a.estimate, b.estimate);
  EXPECT_EQ(a.relative_residual, b.relative_residual);
}

namespace {

// A position loop: a sampled PD controller h (with the past of the measured position) drives the
// mass through a play b (a backlash written with its own past), truth M = 2, c = 3.
std::string position_loop(const std::string& M, const std::string& c, const std::string& b) {
  return R"J({"time": "t", "inputs": {"r": "r"},
    "parameters": {"M": )J" + M + R"J(, "c": )J" + c + R"J(, "b": )J" + b + R"J(,
                   "P": {"value": 200, "fixed": true}, "D": {"value": 25, "fixed": true}},
    "states": {"q": 0.0, "v": 0.0},
    "sampled": {"h": "P*(r - q) - D*(q - prev(q, 1))/Ts", "h_bl": "max(h - b, min(h + b, prev(h_bl, 1)))"},
    "derivatives": {"q": "v", "v": "(h_bl - c*v)/M"},
    "outputs": {"q": "q_meas"}})J";
}

}  // namespace

// The sampled controller and the play are evaluated from the measured position sample by sample
// (as the simulator does, the play's own past included): the regression of v recovers the truth's
// M and c from values far off, and its PUI holds them. A play left free is refused: the play's
// history would depend on it.
TEST(EquationError, SampledControllerAndPlayAreEvaluatedFromTheMeasurements) {
  const SyntheticPlant p = test::simulated_plant(position_loop("2.0", "3.0", "{\"value\": 4.0, \"fixed\": true}"),
                                                 position_loop("2.0", "3.0", "{\"value\": 4.0, \"fixed\": true}"), 4000,
                                                 0.005, {"r", -1, 1, 0.3, 1.5}, 1e-4, 7);
  ModelFile m = p.truth;
  m.parameter("M")->value = 1.2;
  m.parameter("c")->value = 6.0;
  const EquationErrorFit f = equation_error_fit(m, p.estimation, "v");
  ASSERT_TRUE(f.built) << f.note;
  ASSERT_EQ(f.parameters.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const double truth = f.parameters[i] == "M" ? 2.0 : 3.0;
    EXPECT_NEAR(f.estimate[i], truth, 0.02 * truth) << f.parameters[i];
  }
  const EquationErrorResult r = equation_error_pui(m, p.estimation, "v");
  ASSERT_TRUE(r.built) << r.note;
  for (std::size_t i = 0; i < r.parameters.size(); ++i) {
    const double truth = r.parameters[i] == "M" ? 2.0 : 3.0;
    EXPECT_LE(r.box[static_cast<Eigen::Index>(i)].lower(), truth) << r.parameters[i];
    EXPECT_GE(r.box[static_cast<Eigen::Index>(i)].upper(), truth) << r.parameters[i];
  }
  EXPECT_NE(r.note.find("h_bl"), std::string::npos) << r.note;
  m.parameter("b")->fixed = false;
  const EquationErrorFit free_play = equation_error_fit(m, p.estimation, "v");
  EXPECT_FALSE(free_play.built);
  EXPECT_NE(free_play.note.find("free parameter \"b\""), std::string::npos) << free_play.note;
}
