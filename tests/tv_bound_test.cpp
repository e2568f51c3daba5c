// Time-varying parameter bounds: the biaffine regression, window norms, the l-inf LP and the
// sparse MILP (Salehpour & Johansson).

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <random>

#include "sets/error.hpp"
#include "sets/tv_bound.hpp"

namespace {

// A damped oscillator (the crane's pendulum, scaled down) with one parameter in A (through P),
// one in B (through Q) and one additive (through D).
sets::TimeVaryingModel small_model() {
  const double h = 0.1;
  sets::TimeVaryingModel m;
  m.A.resize(2, 2);
  m.A << 1, h, -h * 2.0, 1 - h * 0.5;
  m.B = Eigen::Vector2d(0, h);
  m.C = Eigen::RowVector2d(1, 0);
  m.P = Eigen::MatrixXd::Zero(2, 6);
  m.P(1, 0) = -h;  // pi1 * (-h x1): stiffness
  m.Q = Eigen::MatrixXd::Zero(2, 3);
  m.Q(1, 1) = h;   // pi2 * h u: gain
  m.D = Eigen::MatrixXd::Zero(2, 3);
  m.D(0, 2) = h;   // pi3: additive offset
  return m;
}

Eigen::MatrixXd square_input(int N, int half_period) {
  Eigen::MatrixXd u(N, 1);
  for (int k = 0; k < N; ++k) u(k, 0) = (k / half_period) % 2 == 0 ? 1.0 : -1.0;
  return u;
}

}  // namespace

TEST(TvBound, BiaffineRegressionIsExactForAdditiveAndFirstOrderOtherwise) {
  const auto m = small_model();
  const int N = 60;
  const Eigen::MatrixXd u = square_input(N, 10);
  const Eigen::VectorXd x0 = Eigen::Vector2d(0.3, -0.1);
  const auto reg = sets::biaffine_regression(m, x0, u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::MatrixXd pi(N, 3);
  for (int k = 0; k < N; ++k) pi.row(k) << U(rng), U(rng), U(rng);
  // Only the D-term: the model is affine in pi, so (4) holds with V = 0.
  Eigen::MatrixXd pd = Eigen::MatrixXd::Zero(N, 3);
  pd.col(2) = pi.col(2);
  const auto sd = sets::simulate(m, x0, u, pd);
  EXPECT_LT((sets::stack_samples(sd.y) - reg.upsilon - reg.xi * sets::stack_samples(pd)).cwiseAbs().maxCoeff(), 1e-12);
  // All terms: the remainder is second order in the size of pi.
  double prev = 0;
  for (double a : {1e-2, 1e-3}) {
    const auto s = sets::simulate(m, x0, u, a * pi);
    const double r = (sets::stack_samples(s.y) - reg.upsilon - a * reg.xi * sets::stack_samples(pi)).cwiseAbs().maxCoeff();
    if (prev > 0) {
      EXPECT_NEAR(r / prev, 0.01, 0.004);
    }
    prev = r;
  }
  EXPECT_TRUE(reg.xi.topRows(1).isZero());
}

namespace {

// Data of a small problem: the model above simulated with the perturbation pi and output noise
// of window norm noise_norm.
sets::TvBoundData small_data(const Eigen::MatrixXd& pi, double noise_norm, unsigned seed, int window = 8) {
  const auto m = small_model();
  const int N = static_cast<int>(pi.rows());
  const Eigen::MatrixXd u = square_input(N, 7);
  const Eigen::VectorXd x0 = Eigen::Vector2d::Zero();
  const auto w = sets::WindowNorm::pulse(window, 1.0 / window);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd eta(N + 1);
  for (int k = 0; k <= N; ++k) eta[k] = U(rng);
  if (noise_norm > 0) eta *= noise_norm / w(eta);
  else eta.setZero();
  return {sets::biaffine_regression(m, x0, u), sets::simulate(m, x0, u, pi).y + eta, {w}};
}

}  // namespace

TEST(TvBound, WindowNormOfKnownSignals) {
  const auto w = sets::WindowNorm::pulse(36, 1.0 / 35);
  EXPECT_NEAR(w(Eigen::VectorXd::Ones(100)), 36.0 / 35, 1e-12);  // full window of ones
  EXPECT_NEAR(w(Eigen::VectorXd::Ones(10)), 10.0 / 35, 1e-12);   // signal shorter than the window
  Eigen::VectorXd pulse = Eigen::VectorXd::Zero(50);
  pulse[20] = -7;
  EXPECT_NEAR(w(pulse), 7.0 / 35, 1e-12);  // a single spike: the sign does not matter
  // The unit pulse window gives the l-inf norm.
  EXPECT_NEAR(sets::WindowNorm::pulse(1, 1.0)(Eigen::Vector3d(1, -4, 2)), 4.0, 0);
}

TEST(TvBound, BadWindowsAreRejected) {
  EXPECT_THROW(sets::WindowNorm(Eigen::VectorXd()), sets::InputError);
  EXPECT_THROW(sets::WindowNorm::pulse(0, 1.0), sets::InputError);
  EXPECT_THROW(sets::WindowNorm(Eigen::Vector3d(0.5, 0.6, 0.1)), sets::InputError);  // increases at 1
  EXPECT_THROW(sets::WindowNorm(Eigen::Vector2d(0, 0)), sets::InputError);           // identically zero
  EXPECT_THROW(sets::WindowNorm(Eigen::Vector2d(1, -0.1)), sets::InputError);
  EXPECT_THROW(sets::WindowNorm(Eigen::Vector2d(1, NAN)), sets::InputError);
  try {
    sets::WindowNorm(Eigen::Vector3d(0.5, 0.4, 0.45));
    FAIL();
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sample 2"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(sets::WindowNorm(Eigen::Vector3d(0.5, 0.5, 0.0)));  // non-increasing is enough
}

// The lifted polytope (7) holds (V, |V|) exactly when every output's window norm is <= eps.
RC_GTEST_PROP(TvBound, LiftedWindowPolytopeIsTheWindowNormBall, ()) {
  const int samples = *rc::gen::inRange(1, 12), l = *rc::gen::inRange(1, 3);
  std::vector<sets::WindowNorm> ws;
  for (int j = 0; j < l; ++j) {
    const int L = *rc::gen::inRange(1, 6);
    Eigen::VectorXd w(L);
    double prev = 1;
    for (int d = 0; d < L; ++d) w[d] = prev = prev * (*rc::gen::inRange(1, 101)) / 100.0;
    ws.emplace_back(w);
  }
  const sets::WindowNormBall ball(ws, samples);
  Eigen::VectorXd V(samples * l);
  for (Eigen::Index i = 0; i < V.size(); ++i) V[i] = *rc::gen::inRange(-1000, 1001) / 100.0;
  const Eigen::VectorXd n = ball.norms(V);
  const double scale = *rc::gen::element(0.9, 1.0, 1.1);
  const Eigen::VectorXd eps = scale * n;
  const auto poly = ball.lifted_polytope(eps);
  Eigen::VectorXd z(2 * V.size());
  z << V, V.cwiseAbs();
  const bool inside = ((poly.A() * z - poly.b()).array() <= 1e-9 * (1 + n.maxCoeff())).all();
  const bool expected = scale >= 1.0 || n.maxCoeff() == 0;
  RC_ASSERT(inside == expected);
  RC_ASSERT(ball.contains(V, eps, 1e-12) == expected);
}

TEST(TvBound, ZeroPerturbationWithBoundedNoiseGivesZeroBound) {
  // With the paper's weight h = 1/||y_m - C zeta||_w, (8) may trade a little noise for a small
  // perturbation; with a lighter h the noise is cheaper than any perturbation and pi-hat = 0.
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const int N = 40;
    const auto data = small_data(Eigen::MatrixXd::Zero(N, 3), 0.05, seed);
    const auto paper_h = sets::linf_bound(data);
    ASSERT_EQ(paper_h.pi.rows(), N);
    EXPECT_LT(paper_h.bound.maxCoeff(), 0.1) << "seed " << seed;
    EXPECT_LE(paper_h.epsilon[0], 0.05 + 1e-9);
    sets::LinfBoundOptions o;
    o.h = Eigen::VectorXd::Constant(1, 0.01 / 0.05);
    const auto r = sets::linf_bound(data, o);
    EXPECT_LT(r.bound.maxCoeff(), 1e-6) << "seed " << seed << ": " << r.bound.transpose();
    EXPECT_NEAR(r.epsilon[0], 0.05, 1e-6);  // the noise alone explains the data
    EXPECT_TRUE(r.changes.empty());
  }
}

TEST(TvBound, SparseBoundPlacesASingleStep) {
  // A step in one parameter at a random sample: the largest jump of the MILP estimate in that
  // parameter lies within a few samples of the true one in most runs. The parameters here enter
  // through Q and D, so (4) is exact and eps = the noise's window norm keeps the truth feasible
  // (one jump); the paper's eps from (8) is used by the app.
  std::mt19937 rng(11);
  int hits = 0, runs = 6;
  for (int run = 0; run < runs; ++run) {
    const int N = 30, param = 1 + run % 2, at = std::uniform_int_distribution<int>(6, 22)(rng);
    Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
    pi.block(at, param, N - at, 1).setConstant(0.5);
    const auto data = small_data(pi, 0.01, 100 + run);
    const auto lin = sets::linf_bound(data);
    sets::SparseBoundOptions o;
    o.mu = Eigen::Vector3d::Constant(1e-3);
    o.max_abs = Eigen::Vector3d::Constant(2.0);
    o.epsilon = Eigen::VectorXd::Constant(1, 0.01);
    o.milp.time_limit_s = 1.5;
    o.start = lin.pi;
    const auto r = sets::sparse_bound(data, o);
    int best_k = -1;
    double best = 0;
    for (const auto& c : r.changes)
      if (c.parameter == param && std::abs(c.size) > best) best = std::abs(c.size), best_k = c.sample;
    RecordProperty("run" + std::to_string(run), std::to_string(at) + " -> " + std::to_string(best_k) + ", " +
                                                    std::to_string(r.changes.size()) + " jumps, gap " +
                                                    std::to_string(r.gap));
    if (std::abs(best_k - at) <= 3) ++hits;
  }
  EXPECT_GE(hits, runs - 2);
}

TEST(TvBound, PaperAndSingleBinaryFormulationsAgree) {
  // One binary per jump drops the sign symmetry of (12) but keeps the optimum.
  const int N = 16;
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(6, 2, N - 6, 1).setConstant(0.4);
  pi.block(10, 1, N - 10, 1).setConstant(-0.3);
  const auto data = small_data(pi, 0.01, 5, 4);
  const auto lin = sets::linf_bound(data);
  sets::SparseBoundOptions o;
  o.mu = Eigen::Vector3d::Constant(1e-3);
  o.max_abs = Eigen::Vector3d::Constant(1.0);
  o.epsilon = lin.epsilon;
  o.milp.time_limit_s = 10;
  const auto single = sets::sparse_bound(data, o);
  o.formulation = sets::SparseFormulation::paper;
  const auto paper = sets::sparse_bound(data, o);
  ASSERT_TRUE(single.status == sets::MilpStatus::optimal) << sets::to_string(single.status);
  ASSERT_TRUE(paper.status == sets::MilpStatus::optimal) << sets::to_string(paper.status);
  EXPECT_NEAR(single.objective, paper.objective, 1e-3 * (1 + std::abs(paper.objective)));
  // Both satisfy the window-norm constraint with the given eps.
  EXPECT_LE(data.ball().norms(sets::stack_samples(single.residual))[0], lin.epsilon[0] * (1 + 1e-6) + 1e-9);
}

TEST(TvBound, BadInputIsRejectedWithClearErrors) {
  auto m = small_model();
  const Eigen::MatrixXd u = square_input(10, 3);
  const Eigen::VectorXd x0 = Eigen::Vector2d::Zero();
  auto bad = m;
  bad.P = Eigen::MatrixXd::Zero(2, 5);  // should be n x nq = 2 x 6
  try {
    sets::biaffine_regression(bad, x0, u);
    FAIL();
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("P (n x nq)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sets::biaffine_regression(m, Eigen::Vector3d::Zero(), u), sets::InputError);    // x0
  EXPECT_THROW(sets::biaffine_regression(m, x0, Eigen::MatrixXd(10, 2)), sets::InputError);   // inputs
  EXPECT_THROW(sets::biaffine_regression(m, x0, Eigen::MatrixXd(0, 1)), sets::InputError);    // empty
  EXPECT_THROW(sets::simulate(m, x0, u, Eigen::MatrixXd::Zero(9, 3)), sets::InputError);      // pi rows
  const auto reg = sets::biaffine_regression(m, x0, u);
  const auto w = sets::WindowNorm::pulse(3, 1.0 / 3);
  sets::TvBoundData short_y{reg, Eigen::MatrixXd::Zero(10, 1), {w}};  // needs N + 1 = 11 samples
  try {
    sets::linf_bound(short_y);
    FAIL();
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("11"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sets::linf_bound({reg, Eigen::MatrixXd::Zero(11, 2), {w}}), sets::InputError);  // outputs
  EXPECT_THROW(sets::linf_bound({reg, Eigen::MatrixXd::Zero(11, 1), {}}), sets::InputError);   // no window
  Eigen::MatrixXd y = Eigen::MatrixXd::Ones(11, 1);
  sets::LinfBoundOptions lo;
  lo.F = Eigen::Vector2d::Ones();  // q = 3
  EXPECT_THROW(sets::linf_bound({reg, y, {w}}, lo), sets::InputError);
  sets::SparseBoundOptions so;  // mu, max_abs and epsilon missing
  EXPECT_THROW(sets::sparse_bound({reg, y, {w}}, so), sets::InputError);
  so.mu = Eigen::Vector3d::Constant(0.01);
  so.max_abs = Eigen::Vector3d::Constant(1);
  so.epsilon = Eigen::VectorXd::Constant(1, 0.1);
  so.start = Eigen::MatrixXd::Zero(9, 3);  // N = 10
  EXPECT_THROW(sets::sparse_bound({reg, y, {w}}, so), sets::InputError);
  so.max_abs[1] = sets::inf;
  so.start.resize(0, 0);
  EXPECT_THROW(sets::sparse_bound({reg, y, {w}}, so), sets::InputError);
}

#include "../apps/sets-tv-bound/crane.hpp"

TEST(TvBound, CraneModelMatchesEquation15) {
  // simulate() of the (A, B, C, P, D, Q) form equals the Euler recursion (15) with
  // b = b0 + pi1, lambda = lambda0 + pi2, kappa = kappa0 + pi3.
  const double l0 = 3.3, k0 = 0.25, b0 = 2, h = sets::crane::kStep;
  const auto m = sets::crane::model(l0, k0, b0);
  const int N = 50;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::MatrixXd u(N, 1), pi(N, 3);
  for (int k = 0; k < N; ++k) u(k, 0) = U(rng), pi.row(k) << 0.2 * U(rng), U(rng), 0.5 * U(rng);
  const Eigen::Vector3d x0(0.1, -0.2, 0.3);
  const auto s = sets::simulate(m, x0, u, pi);
  Eigen::Vector3d x = x0;
  for (int k = 0; k < N; ++k) {
    const double b = b0 + pi(k, 0), lam = l0 + pi(k, 1), kap = k0 + pi(k, 2);
    Eigen::Matrix3d A;
    A << 1, h, 0, -h * lam, 1 - h * kap, h * lam, 0, 0, 1;
    x = A * x + Eigen::Vector3d(0, 0, h * b) * u(k, 0);
    EXPECT_LT((s.x.row(k + 1).transpose() - x).cwiseAbs().maxCoeff(), 1e-12) << "sample " << k + 1;
  }
}
