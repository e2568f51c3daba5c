// simulate(StateSpaceModel): the response is the convolution with the Markov parameters plus the
// free response of x0, and mismatched dimensions are refused.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sets/core/error.hpp"
#include "sets/models/state_space_model.hpp"

namespace {

sets::StateSpaceModel two_state_system() {
  sets::StateSpaceModel s;
  s.A.resize(2, 2);
  s.A << 0.5, 0.2, -0.1, 0.3;
  s.B.resize(2, 2);
  s.B << 1, 0, 0.5, -1;
  s.C.resize(1, 2);
  s.C << 2, -1;
  s.D.resize(1, 2);
  s.D << 0.25, 0;
  return s;
}

TEST(StateSpaceModel, ResponseIsMarkovConvolutionPlusFreeResponse) {
  const auto s = two_state_system();
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g;
  const int N = 30;
  const Eigen::MatrixXd u = Eigen::MatrixXd::NullaryExpr(N, 2, [&] { return g(rng); });
  const Eigen::Vector2d x0(1.5, -2.0);
  const Eigen::MatrixXd y = sets::simulate(s, u, x0);
  ASSERT_EQ(y.rows(), N);
  ASSERT_EQ(y.cols(), 1);
  for (int t = 0; t < N; ++t) {
    Eigen::MatrixXd At = Eigen::MatrixXd::Identity(2, 2);
    for (int k = 0; k < t; ++k) At = At * s.A;
    double expected = (s.C * At * x0)(0) + (s.D * u.row(t).transpose())(0);
    Eigen::MatrixXd Aj = Eigen::MatrixXd::Identity(2, 2);
    for (int j = 0; j < t; ++j) {  // C A^j B u(t-1-j)
      expected += (s.C * Aj * s.B * u.row(t - 1 - j).transpose())(0);
      Aj = Aj * s.A;
    }
    EXPECT_NEAR(y(t, 0), expected, 1e-12 * (1 + std::abs(expected))) << "t = " << t;
  }
  // Without x0 the model starts at rest.
  const Eigen::MatrixXd y0 = sets::simulate(s, u);
  EXPECT_NEAR(y0(0, 0), 0.25 * u(0, 0), 1e-15);
}

TEST(StateSpaceModel, MismatchedDimensionsAreRefused) {
  const auto s = two_state_system();
  const Eigen::MatrixXd u = Eigen::MatrixXd::Ones(5, 2);
  EXPECT_THROW(sets::simulate(s, Eigen::MatrixXd::Ones(5, 3)), sets::InputError);
  EXPECT_THROW(sets::simulate(s, u, Eigen::VectorXd::Ones(3)), sets::InputError);
  auto bad = s;
  bad.D = Eigen::MatrixXd::Zero(2, 2);
  EXPECT_THROW(sets::simulate(bad, u), sets::InputError);
}

}  // namespace
