// The Cerone-Regruto example: the data respect the stated error bounds, and the true theta lies
// in the PUIs of the paper's method on them.

#include <gtest/gtest.h>

#include "sets/examples/cerone_regruto.hpp"
#include "sets/methods/lpv_pui/lpv_pui.hpp"

TEST(CeroneRegrutoExample, ErrorsStayWithinTheirBoundsAndThetaIsCovered) {
  std::mt19937_64 rng(3);
  const double delta = 4.8e-3;
  const auto e = sets::cerone_regruto::simulate(200, true, delta, rng);
  ASSERT_EQ(e.data.y.size(), 202);
  EXPECT_LE((e.data.y - e.w).cwiseAbs().maxCoeff(), delta);
  EXPECT_LE((e.data.r - e.lambda).cwiseAbs().maxCoeff(), delta);
  EXPECT_GT((e.data.y - e.w).cwiseAbs().maxCoeff(), 0.5 * delta);  // the errors are really drawn
  const auto res = sets::lpv_pui(sets::cerone_regruto::structure(), e.data);
  ASSERT_FALSE(res.pui.empty());
  EXPECT_TRUE(sets::contains(res.pui.box, sets::cerone_regruto::true_theta()));
}

TEST(CeroneRegrutoExample, SinusoidalSchedulingAndLaggedReading) {
  std::mt19937_64 rng(1);
  const auto e = sets::cerone_regruto::simulate(50, false, 1e-3, rng, true);
  EXPECT_DOUBLE_EQ(e.lambda(9, 0), std::sin(1.0));  // lambda_t = sin(0.1 t), t from 1
  ASSERT_EQ(e.data.r.cols(), 2);                     // [lambda_{t-1}, lambda_{t-2}]
  EXPECT_DOUBLE_EQ(e.data.r(5, 1), e.lambda(3, 0) + e.eps(3, 0));
  const auto res = sets::lpv_pui(sets::cerone_regruto::lagged_structure(), e.data);
  ASSERT_FALSE(res.pui.empty());
  EXPECT_TRUE(sets::contains(res.pui.box, sets::cerone_regruto::true_theta()));
}

TEST(CeroneRegrutoExample, PaperTablesAsPrinted) {
  const auto& t = sets::cerone_regruto::paper_tables();
  EXPECT_STREQ(t[1].name, "II");
  EXPECT_EQ(t[1].N, 1000);
  EXPECT_DOUBLE_EQ(t[3].paper[3].delta_theta[5], 5.6e-2);
}
