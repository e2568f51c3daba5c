// Re-linearisation of the time-varying model around a perturbation trajectory and the sequential
// l-inf LP built on it (an extension of Salehpour & Johansson).

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sets/core/error.hpp"
#include "sets/methods/tv_bound/tv_relinearisation.hpp"
#include "support/tv_fixtures.hpp"

namespace {

using sets::testing::square_input;
sets::TimeVaryingModel model3() { return sets::testing::small_oscillator(true); }

Eigen::MatrixXd random_pi(int N, double size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-size, size);
  Eigen::MatrixXd pi(N, 3);
  for (int k = 0; k < N; ++k) pi.row(k) << U(rng), U(rng), U(rng);
  return pi;
}

// I_q (x) v written out.
Eigen::MatrixXd kron_i(int q, const Eigen::VectorXd& v) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(q * v.size(), q);
  for (int i = 0; i < q; ++i) K.block(i * v.size(), i, v.size(), 1) = v;
  return K;
}

}  // namespace

// With pi_bar = 0 the expansion is (2)-(3): Xi = Omega + Psi + Phi built literally from matrix
// powers, Upsilon = C zeta.
TEST(TvRelinearisation, AtZeroItIsEquation3) {
  const auto m = model3();
  const int N = 25, q = 3;
  const Eigen::MatrixXd u = square_input(N, 6);
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.3, -0.2);
  const auto r = sets::linearised_regression(m, x0, u, Eigen::MatrixXd::Zero(N, q));
  Eigen::MatrixXd zeta(N + 1, 2);
  zeta.row(0) = x0.transpose();
  for (int k = 0; k < N; ++k) zeta.row(k + 1) = (m.A * zeta.row(k).transpose() + m.B * u.row(k).transpose()).transpose();
  Eigen::MatrixXd Xi = Eigen::MatrixXd::Zero(N + 1, N * q);
  for (int k = 1; k <= N; ++k)
    for (int j = 0; j < k; ++j) {
      Eigen::MatrixXd Ap = Eigen::MatrixXd::Identity(2, 2);
      for (int e = 0; e < k - 1 - j; ++e) Ap = Ap * m.A;
      Xi.block(k, j * q, 1, q) = m.C * Ap * (m.D + m.P * kron_i(q, zeta.row(j).transpose()) +
                                             m.Q * kron_i(q, u.row(j).transpose()));
    }
  const double scale = Xi.cwiseAbs().maxCoeff();
  EXPECT_LT((r.xi - Xi).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_LT((r.upsilon - zeta * m.C.transpose()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((r.zeta - zeta).cwiseAbs().maxCoeff(), 1e-12);
  // biaffine_regression is the same expansion.
  const auto b = sets::biaffine_regression(m, x0, u);
  EXPECT_EQ((b.xi - r.xi).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((b.upsilon - r.upsilon).cwiseAbs().maxCoeff(), 0.0);
}

// Around a non-zero pi_bar: the constant term reproduces simulate(pi_bar) exactly, every column of
// Xi is the derivative of the simulated output (central differences), and the remainder is second
// order in pi - pi_bar.
TEST(TvRelinearisation, MatchesFiniteDifferencesOfSimulate) {
  const auto m = model3();
  const int N = 20, q = 3;
  const Eigen::MatrixXd u = square_input(N, 5);
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.1, 0.4);
  for (unsigned seed : {1u, 2u}) {
    const Eigen::MatrixXd pi_bar = random_pi(N, 0.8, seed);
    const auto r = sets::linearised_regression(m, x0, u, pi_bar);
    const Eigen::VectorXd y_bar = sets::stack_samples(sets::simulate(m, x0, u, pi_bar).y);
    EXPECT_LT((r.upsilon + r.xi * sets::stack_samples(pi_bar) - y_bar).cwiseAbs().maxCoeff(), 1e-12);
    const double d = 1e-6;
    double worst = 0;
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < q; ++i) {
        Eigen::MatrixXd plus = pi_bar, minus = pi_bar;
        plus(j, i) += d;
        minus(j, i) -= d;
        const Eigen::VectorXd fd = (sets::stack_samples(sets::simulate(m, x0, u, plus).y) -
                                    sets::stack_samples(sets::simulate(m, x0, u, minus).y)) / (2 * d);
        worst = std::max(worst, (fd - r.xi.col(j * q + i)).cwiseAbs().maxCoeff());
      }
    EXPECT_LT(worst, 1e-7) << "seed " << seed;
    // The nominal expansion (2) does not have these derivatives at pi_bar (the test is not vacuous).
    EXPECT_GT((sets::biaffine_regression(m, x0, u).xi - r.xi).cwiseAbs().maxCoeff(), 100 * worst);
    const Eigen::MatrixXd dir = random_pi(N, 1.0, seed + 10);
    double prev = 0;
    for (double a : {1e-2, 1e-3}) {
      const Eigen::MatrixXd p = pi_bar + a * dir;
      const double rem = (sets::stack_samples(sets::simulate(m, x0, u, p).y) - r.upsilon -
                          r.xi * sets::stack_samples(p)).cwiseAbs().maxCoeff();
      if (prev > 0) {
        EXPECT_NEAR(rem / prev, 0.01, 0.004);
      }
      prev = rem;
    }
  }
}

TEST(TvRelinearisation, ZeroIterationsIsTheLinfMethod) {
  const auto m = model3();
  const int N = 30;
  const Eigen::MatrixXd u = square_input(N, 7);
  const Eigen::VectorXd x0 = Eigen::Vector2d::Zero();
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(12, 0, N - 12, 1).setConstant(0.6);
  const auto w = sets::WindowNorm::pulse(6, 1.0 / 6);
  const Eigen::MatrixXd y = sets::simulate(m, x0, u, pi).y;
  const sets::TvBoundData data{sets::biaffine_regression(m, x0, u), y, {w}};
  const auto direct = sets::linf_bound(data);
  const auto r = sets::relinearised_linf_bound(m, x0, u, y, {w}, 0);
  ASSERT_EQ(r.steps.size(), 1u);
  EXPECT_LT((r.linf.pi - direct.pi).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(r.steps[0].objective, direct.objective, 1e-9);
  EXPECT_EQ(r.data.regression.pi_bar.cwiseAbs().maxCoeff(), 0.0);
}

// With a known noise bound (LinfBoundOptions::epsilon) the sequence must not add the paper's
// h-term (linf_bound rejects both at once); on data of the nominal model plus noise inside that
// bound every step then gives Pi-hat = 0. The paper's weight is linf_bound's default.
TEST(TvRelinearisation, KnownNoiseBoundIsPassedThrough) {
  const auto m = model3();
  const int N = 30;
  const Eigen::MatrixXd u = square_input(N, 7);
  const Eigen::VectorXd x0 = Eigen::Vector2d::Zero();
  const auto w = sets::WindowNorm::pulse(6, 1.0 / 6);
  Eigen::MatrixXd y = sets::simulate(m, x0, u, Eigen::MatrixXd::Zero(N, 3)).y;
  for (int k = 0; k <= N; ++k) y(k, 0) += 0.01 * std::sin(1.3 * k);
  const double noise = w(y.col(0) - sets::simulate(m, x0, u, Eigen::MatrixXd::Zero(N, 3)).y.col(0));
  sets::LinfBoundOptions o;
  o.epsilon = Eigen::VectorXd::Constant(1, noise * (1 + 1e-9));
  const auto r = sets::relinearised_linf_bound(m, x0, u, y, {w}, 2, o);
  ASSERT_EQ(r.steps.size(), 3u);
  EXPECT_LT(r.linf.pi.cwiseAbs().maxCoeff(), 1e-6);
  const sets::TvBoundData data{sets::biaffine_regression(m, x0, u), y, {w}};
  sets::LinfBoundOptions paper;
  paper.h = sets::paper_epsilon_weight(data);
  EXPECT_NEAR(sets::linf_bound(data, paper).objective, sets::linf_bound(data).objective, 1e-12);
}

// Noise-free data from a large step in a parameter that multiplies the state (P). With a heavy eps
// weight, (8) fits the data exactly *on its linearisation*; on (2) that leaves an exact-model residual
// (the linearisation error), and the sequential LP drives it to zero like Newton's method.
TEST(TvRelinearisation, NoiseFreeDataAreFittedExactlyByTheSequence) {
  const auto m = model3();
  const int N = 40;
  const Eigen::MatrixXd u = square_input(N, 7);
  const Eigen::VectorXd x0 = Eigen::Vector2d::Zero();
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(15, 0, N - 15, 1).setConstant(1.0);  // stiffness 2 -> 3
  const auto w = sets::WindowNorm::pulse(8, 1.0 / 8);
  const Eigen::MatrixXd y = sets::simulate(m, x0, u, pi).y;
  sets::LinfBoundOptions o;
  o.h = Eigen::VectorXd::Constant(1, 1e3);
  const auto r = sets::relinearised_linf_bound(m, x0, u, y, {w}, 4, o);
  ASSERT_EQ(r.steps.size(), 5u);
  const double first = r.steps.front().exact_residual[0], last = r.steps.back().exact_residual[0];
  RecordProperty("exact_residual", std::to_string(first) + " -> " + std::to_string(last));
  EXPECT_LT(r.steps.front().epsilon[0], 1e-9);  // exact on the linearisation ...
  EXPECT_GT(first, 1e-4);                       // ... but not with the model (1)
  EXPECT_LT(last, 1e-8);
  // The returned data are the linearisation the last LP used: its residual at the estimate is V-hat.
  const Eigen::VectorXd v = sets::stack_samples(y) - r.data.regression.upsilon -
                            r.data.regression.xi * sets::stack_samples(r.linf.pi);
  EXPECT_LT((v - sets::stack_samples(r.linf.residual)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(TvRelinearisation, BadInputIsRejected) {
  const auto m = model3();
  const int N = 10;
  const Eigen::MatrixXd u = square_input(N, 3);
  const Eigen::VectorXd x0 = Eigen::Vector2d::Zero();
  EXPECT_THROW(sets::linearised_regression(m, x0, u, Eigen::MatrixXd::Zero(N - 1, 3)), sets::InputError);
  EXPECT_THROW(sets::linearised_regression(m, x0, u, Eigen::MatrixXd::Zero(N, 2)), sets::InputError);
  Eigen::MatrixXd bad = Eigen::MatrixXd::Zero(N, 3);
  bad(3, 1) = NAN;
  EXPECT_THROW(sets::linearised_regression(m, x0, u, bad), sets::InputError);
  const Eigen::MatrixXd y = sets::simulate(m, x0, u, random_pi(N, 0.3, 4)).y;
  const auto w = sets::WindowNorm::pulse(3, 1.0 / 3);
  EXPECT_THROW(sets::relinearised_linf_bound(m, x0, u, y, {w}, -1), sets::InputError);
  EXPECT_THROW(sets::relinearised_linf_bound(m, x0, u, y.topRows(N), {w}, 1), sets::InputError);
}
