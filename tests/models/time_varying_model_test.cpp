// Time-varying models (Salehpour & Johansson, eq. 1) and their biaffine regressions (eqs. 2-4),
// checked against the simulator on random models: the regression is exact when the model is
// affine in pi (P = Q = 0), its error is second order in the deviation from the linearisation
// point otherwise, its recursion gives the same Xi Pi, and bad sizes are named.

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "sets/core/error.hpp"
#include "sets/models/time_varying_model.hpp"
#include "support/random_matrices.hpp"

namespace {

using sets::test::Rng;

// A random stable model with n states, p inputs, l outputs and q parameters.
sets::TimeVaryingModel random_model(Rng& rng, int n, int p, int l, int q, bool bilinear) {
  sets::TimeVaryingModel m;
  m.A = rng.mat(n, n);
  m.A *= 0.6 / m.A.cwiseAbs().rowwise().sum().maxCoeff();  // ||A||_inf = 0.6
  m.B = rng.mat(n, p);
  m.C = rng.mat(l, n);
  m.D = rng.mat(n, q);
  m.P = bilinear ? Eigen::MatrixXd(0.2 * rng.mat(n, n * q)) : Eigen::MatrixXd::Zero(n, n * q);
  m.Q = bilinear ? Eigen::MatrixXd(0.2 * rng.mat(n, q * p)) : Eigen::MatrixXd::Zero(n, q * p);
  return m;
}

// max |y(pi) - (Upsilon + Xi Pi)| over every sample and output.
double regression_error(const sets::TimeVaryingModel& m, const sets::BiaffineRegression& r,
                        const Eigen::VectorXd& x0, const Eigen::MatrixXd& u, const Eigen::MatrixXd& pi) {
  const Eigen::VectorXd y = sets::stack_samples(sets::simulate(m, x0, u, pi).y);
  return (y - r.upsilon - r.xi * sets::stack_samples(pi)).cwiseAbs().maxCoeff();
}

}  // namespace

TEST(TimeVaryingModel, BiaffineRegressionIsExactForModelsAffineInThePerturbation) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Rng rng(seed);
    const int n = 1 + static_cast<int>(seed % 3), p = 1 + static_cast<int>(seed % 2), q = 1 + static_cast<int>(seed % 2);
    const auto m = random_model(rng, n, p, 2, q, false);
    const int N = 15;
    const Eigen::VectorXd x0 = rng.mat(n, 1).col(0);
    const Eigen::MatrixXd u = rng.mat(N, p), pi = 0.3 * rng.mat(N, q);
    const auto r = sets::biaffine_regression(m, x0, u);
    ASSERT_EQ(r.samples(), N);
    ASSERT_EQ(r.xi.rows(), (N + 1) * 2);
    ASSERT_EQ(r.xi.cols(), N * q);
    EXPECT_LT(regression_error(m, r, x0, u, pi), 1e-12) << "seed " << seed;
    // The first block row is zero: y(0) does not depend on pi.
    EXPECT_EQ(r.xi.topRows(2).cwiseAbs().maxCoeff(), 0.0);
  }
}

TEST(TimeVaryingModel, LinearisedRegressionErrorIsSecondOrderInTheDeviation) {
  Rng rng(7);
  const int n = 3, p = 2, q = 2, N = 12;
  const auto m = random_model(rng, n, p, 1, q, true);
  const Eigen::VectorXd x0 = rng.mat(n, 1).col(0);
  const Eigen::MatrixXd u = rng.mat(N, p), pi_bar = 0.2 * rng.mat(N, q), step = rng.mat(N, q);
  const auto r = sets::linearised_regression(m, x0, u, pi_bar);
  EXPECT_LT(regression_error(m, r, x0, u, pi_bar), 1e-12);  // exact at the linearisation point
  const double e1 = regression_error(m, r, x0, u, pi_bar + 0.02 * step);
  const double e2 = regression_error(m, r, x0, u, pi_bar + 0.01 * step);
  EXPECT_GT(e1, 1e-10);  // the model is bilinear: the expansion is not exact
  EXPECT_NEAR(e1 / e2, 4.0, 0.5);
  // Around pi_bar = 0 it is the biaffine regression of the paper.
  const auto lin0 = sets::linearised_regression(m, x0, u, Eigen::MatrixXd::Zero(N, q));
  const auto paper = sets::biaffine_regression(m, x0, u);
  EXPECT_LT((lin0.xi - paper.xi).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((lin0.upsilon - paper.upsilon).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(TimeVaryingModel, RecursionGivesTheSameXiPi) {
  Rng rng(3);
  const int n = 2, p = 1, q = 2, N = 10;
  const auto m = random_model(rng, n, p, 2, q, true);
  const Eigen::MatrixXd u = rng.mat(N, p), pi = rng.mat(N, q);
  const auto r = sets::linearised_regression(m, rng.mat(n, 1).col(0), u, 0.1 * rng.mat(N, q));
  ASSERT_EQ(static_cast<int>(r.transition.size()), N);
  ASSERT_EQ(static_cast<int>(r.input_map.size()), N);
  const Eigen::VectorXd dense = r.xi * sets::stack_samples(pi);
  Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
  for (int k = 0; k <= N; ++k) {
    EXPECT_LT((r.output_map * s - dense.segment(k * 2, 2)).cwiseAbs().maxCoeff(), 1e-12) << "sample " << k;
    if (k < N) s = r.transition[k] * s + r.input_map[k] * pi.row(k).transpose();
  }
}

TEST(TimeVaryingModel, StackingRoundTripsAndBadSizesAreNamed) {
  Rng rng(1);
  const Eigen::MatrixXd signal = rng.mat(5, 3);
  const Eigen::VectorXd stacked = sets::stack_samples(signal);
  EXPECT_EQ(stacked[3], signal(1, 0));  // [s(0); s(1); ...]
  EXPECT_EQ(sets::unstack_samples(stacked, 3), signal);

  auto m = random_model(rng, 2, 1, 1, 1, true);
  m.D = rng.mat(3, 1);  // 3 rows against n = 2
  try {
    m.validate();
    FAIL() << "no error";
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("D"), std::string::npos) << e.what();
  }
  const auto ok = random_model(rng, 2, 1, 1, 1, true);
  EXPECT_THROW(sets::simulate(ok, Eigen::VectorXd::Zero(2), rng.mat(4, 1), rng.mat(3, 1)), sets::InputError);
  EXPECT_THROW(sets::biaffine_regression(ok, Eigen::VectorXd::Zero(3), rng.mat(4, 1)), sets::InputError);
}
