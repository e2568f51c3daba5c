// Equation-error PUIs of one derivative (sets/diagnosis/equation_error.hpp).

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "sets/diagnosis/equation_error.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "sets/models/model_file.hpp"

using namespace sets;

// Equation-error PUIs of the Coulomb plant's force balance, measured at values a little off the
// truth (as an estimate would be): every true parameter must lie in its interval, and the
// parameters that enter nonlinearly or through prev() are refused with a reason.
TEST(EquationError, PuiContainsTheTrueParametersOfTheCoulombPlant) {
  const SyntheticPlant p = synthetic_plant("coulomb_friction");
  ModelFile m = p.nominal;
  *m.derivative("v") = "(K*u - k*x - c*v - Fc*sign(v))/m";
  ModelParameter fc;
  fc.name = "Fc";
  m.parameters.push_back(fc);
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
  ModelFile delayed = m;
  *delayed.derivative("v") = "(K*prev(u, 3) - k*x - c*v)/m";
  const EquationErrorResult rd = equation_error_pui(delayed, p.estimation, "v");
  EXPECT_FALSE(rd.built);
  EXPECT_NE(rd.note.find("prev"), std::string::npos) << rd.note;
}
