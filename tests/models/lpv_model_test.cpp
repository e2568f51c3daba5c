// The LPV model structure (Cerone–Regruto): basis functions and their ranges, the JSON structure,
// and the interval regression of the paper's structure against hand-computed intervals.

#include <gtest/gtest.h>

#include "sets/core/error.hpp"
#include "sets/examples/cerone_regruto.hpp"
#include "sets/models/lpv_model.hpp"

using sets::Interval;
using sets::LpvMeasurements;

TEST(LpvModel, RegressionOfThePaperStructureMatchesHandComputedIntervals) {
  const auto m = sets::cerone_regruto::structure();
  EXPECT_EQ(m.num_parameters(), 6);
  EXPECT_EQ(m.first_regression(), 2);
  LpvMeasurements d;
  d.u.resize(8);
  d.y.resize(8);
  d.r.resize(8, 1);
  d.u << 0.5, -1, 0.25, 2, 1, -1, 0.5, 0.25;
  d.y << 0, 1, -2, 0.5, 1, 0, -1, 0.5;
  d.r << 0.1, 0.1, 0.1, -0.75, 0.5, 0.25, 0, -0.5;
  d.delta_eta = Eigen::VectorXd::Constant(1, 0.5);
  d.delta_eps = Eigen::MatrixXd::Constant(1, 1, 0.25);
  const auto reg = sets::lpv_regression(m, d);
  ASSERT_EQ(reg.Phi.rows(), 6);
  // Row for t = 2 (0-based): lambda in [-0.15, 0.35], lambda^2 in [0, 0.1225];
  // w_{t-1} in [0.5, 1.5], w_{t-2} in [-0.5, 0.5]; u_{t-1} = -1, u_{t-2} = 0.5.
  const double expect[6][2] = {{-0.525, 0.225},     // -(w1 * lambda)
                               {-0.5, 0.5},         // -w0 * 1
                               {-0.06125, 0.06125}, // -(w0 * lambda^2)
                               {-1, -1},            // u1 * 1
                               {-0.075, 0.175},     // u0 * lambda
                               {0, 0.06125}};       // u0 * lambda^2
  for (int j = 0; j < 6; ++j) {
    EXPECT_NEAR(reg.Phi(0, j).lower(), expect[j][0], 1e-15) << j;
    EXPECT_NEAR(reg.Phi(0, j).upper(), expect[j][1], 1e-15) << j;
    EXPECT_LE(reg.Phi(0, j).lower(), expect[j][0]) << j;
    EXPECT_GE(reg.Phi(0, j).upper(), expect[j][1]) << j;
    EXPECT_NEAR(reg.central(0, j), (expect[j][0] + expect[j][1]) / 2, 1e-15);
    EXPECT_NEAR(reg.radius(0, j), (expect[j][1] - expect[j][0]) / 2, 1e-15);
  }
  EXPECT_EQ(reg.time[0], 2);
  EXPECT_NEAR(reg.Y[1].lower(), 0.0, 1e-15);
  EXPECT_NEAR(reg.Y[1].upper(), 1.0, 1e-15);
}

TEST(LpvModel, BasisParserAndJsonStructure) {
  const auto f = sets::parse_basis_function("2*l1^2*sin(l2)", 2);
  EXPECT_NEAR(f(Eigen::Vector2d(0.5, 1.0)), 2 * 0.25 * std::sin(1.0), 1e-15);
  sets::IntervalVector box(2);
  box << Interval(-0.5, 1), Interval(1, 2);
  const Interval r = f.range(box);
  EXPECT_NEAR(r.lower(), 0, 1e-12);
  EXPECT_NEAR(r.upper(), 2, 1e-9);  // max at l1 = 1, l2 = pi/2
  // l * l is merged into l^2, whose range over [-1, 1] starts at 0.
  const auto sq = sets::parse_basis_function("lambda*lambda", 1);
  sets::IntervalVector one(1);
  one << Interval(-1, 1);
  EXPECT_EQ(sq.range(one).lower(), 0.0);
  EXPECT_THROW(sets::parse_basis_function("l3", 2), sets::InputError);
  EXPECT_THROW(sets::parse_basis_function("lambda", 2), sets::InputError);
  EXPECT_THROW(sets::parse_basis_function("gamma(l1)", 1), sets::InputError);
  EXPECT_THROW(sets::parse_basis_function("l1^x", 1), sets::InputError);

  const auto m = sets::parse_lpv_structure_json(
      R"({"alpha": 1, "a": [["lambda"], ["1", "lambda^2"]], "b": [[], ["1"], ["lambda", "lambda^2"]]})");
  EXPECT_EQ(m.num_parameters(), 6);
  EXPECT_EQ(m.parameter_names()[2], "a2,2[lambda^2]");
  try {
    sets::parse_lpv_structure_json(R"({"a": [["lambda"]], "b": [["zeta"]]})", "model.json");
    FAIL();
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("b[0][0]"), std::string::npos);
  }
  EXPECT_THROW(sets::parse_lpv_structure_json(R"({"a": [["lambda"]]})"), sets::InputError);
  EXPECT_THROW(sets::parse_lpv_structure_json("{not json"), sets::InputError);
}
