#include <gtest/gtest.h>

#include <random>

#include "sets/core/error.hpp"
#include "sets/examples/farah.hpp"
#include "sets/methods/ss_uncertainty/ss_uncertainty.hpp"

namespace {

// Data of the paper's example at 20 dB (white Gaussian output noise), binary input.
void example_data(unsigned seed, Eigen::MatrixXd& u, Eigen::MatrixXd& y) {
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution coin(0.5);
  std::normal_distribution<double> g;
  u.resize(1000, 2);
  for (int t = 0; t < u.rows(); ++t) u.row(t) << (coin(rng) ? 1.0 : -1.0), (coin(rng) ? 1.0 : -1.0);
  y = sets::simulate(sets::farah::system(), u);
  for (int j = 0; j < 2; ++j) {
    const double sd = std::sqrt((y.col(j).array() - y.col(j).mean()).square().mean() / 100.0);
    for (int t = 0; t < y.rows(); ++t) y(t, j) += sd * g(rng);
  }
}

// The entry point is the three steps in a row: the same estimate, ellipsoid and FPS as calling
// them one by one; and the FPS with l = max |eps| contains the least-squares estimate itself.
TEST(SsUncertainty, EntryPointChainsTheSteps) {
  Eigen::MatrixXd u, y;
  example_data(5, u, y);
  sets::SsUncertaintyOptions o;
  o.identification.order = 3;
  const auto r = sets::ss_uncertainty(u, y, o);
  const auto id = sets::identify_propagator(u, y, o.identification);
  const auto dom = sets::level_set_domain(id.regression, o.level);
  EXPECT_EQ(r.identification.theta, id.theta);
  EXPECT_EQ(r.estimate_level_set.theta, dom.theta);
  EXPECT_EQ(r.estimate_level_set.ell, dom.ell);
  EXPECT_EQ(r.estimate_fps.size(), sets::regression_fps(id.regression, dom.ell).size());
  EXPECT_NE(r.estimate_fps.contains(dom.theta), sets::BoolInterval::no);
  ASSERT_TRUE(r.estimate_fps_pui.has_value());
  ASSERT_EQ(r.estimate_fps_pui->consistency.falsified, sets::Falsified::no);
  EXPECT_TRUE(sets::contains(r.estimate_fps_pui->box, dom.theta));
  o.estimate_fps_pui = false;
  EXPECT_FALSE(sets::ss_uncertainty(u, y, o).estimate_fps_pui.has_value());
  o.identification.past = 2;
  EXPECT_THROW(sets::ss_uncertainty(u, y, o), sets::InputError);
}

}  // namespace
