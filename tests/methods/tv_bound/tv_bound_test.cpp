// Time-varying parameter bounds: the biaffine regression, the l-inf LP and the sparse MILP
// (Salehpour & Johansson). Window norms: window_norm_test.cpp; the jump search: jump_search_test.cpp.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "sets/core/error.hpp"
#include "sets/methods/tv_bound/tv_bound.hpp"

#include "sets/examples/crane.hpp"
#include "support/tv_fixtures.hpp"

namespace {

using sets::testing::milp_options;
using sets::testing::small_data;
using sets::testing::square_input;
sets::TimeVaryingModel small_model() { return sets::testing::small_oscillator(); }

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

// The scale of GLPK's answers here: its primal and dual feasibility tolerances are 1e-7 (relative
// to 1 + |bound|, GLPK's defaults, kept by LinearProgram), the data are O(1) and the objectives
// below are O(1), so a value the exact LP makes 0 comes back below ~1e-7; 1e-6 leaves a factor 10.
constexpr double kLpTol = 1e-6;

// f(Pi) = ||(I (x) F) Pi||_inf + ||(I (x) G) Delta Pi||_inf of (8), Delta pi(0) = pi(0).
double perturbation_cost(const Eigen::MatrixXd& pi, const Eigen::VectorXd& F, const Eigen::VectorXd& G) {
  Eigen::MatrixXd d = pi;
  d.bottomRows(pi.rows() - 1) -= pi.topRows(pi.rows() - 1);
  return (pi * F.asDiagonal()).cwiseAbs().maxCoeff() + (d * G.asDiagonal()).cwiseAbs().maxCoeff();
}

// The crane of Section VII with pi == 0: nominal (lambda0, kappa0, b0) drawn within the ranges of
// Table II, a random piecewise-constant input, x(0) = 0 and the crane's window (1/35 on 0..35).
struct CraneNoiseCase {
  sets::TimeVaryingModel model;
  Eigen::Vector3d nominal;  // (b0, lambda0, kappa0): the order of pi
  Eigen::MatrixXd u;
  Eigen::VectorXd eta;      // white noise with ||eta||_w = 1
  sets::WindowNorm window = sets::WindowNorm::pulse(36, 1.0 / 35);

  // y_m = C zeta + scale * eta: pi == 0, so (4) holds with V = scale * eta exactly.
  sets::TvBoundData data(double scale) const {
    const Eigen::VectorXd x0 = Eigen::Vector3d::Zero();
    const auto reg = sets::biaffine_regression(model, x0, u);
    const Eigen::MatrixXd y = sets::simulate(model, x0, u, Eigen::MatrixXd::Zero(u.rows(), 3)).y + scale * eta;
    return {reg, y, {window}};
  }
};

CraneNoiseCase random_crane_case() {
  CraneNoiseCase c;
  const double lambda0 = *rc::gen::inRange(300, 371) / 100.0, kappa0 = *rc::gen::inRange(15, 26) / 100.0,
               b0 = *rc::gen::inRange(150, 251) / 100.0;
  c.model = sets::crane::model(lambda0, kappa0, b0);
  c.nominal = Eigen::Vector3d(b0, lambda0, kappa0);
  const int N = *rc::gen::inRange(40, 61);
  std::mt19937 rng(*rc::gen::arbitrary<unsigned>());
  std::uniform_real_distribution<double> U(-1, 1);
  std::uniform_int_distribution<int> hold(5, 20);
  c.u.resize(N, 1);
  for (int k = 0; k < N;) {
    const double level = U(rng);
    for (int e = std::min(N, k + hold(rng)); k < e; ++k) c.u(k, 0) = level;
  }
  c.eta.resize(N + 1);
  for (int k = 0; k <= N; ++k) c.eta[k] = U(rng);
  c.eta /= c.window(c.eta);
  return c;
}

}  // namespace

// The "pi == 0 and noise within the window-norm bound gives a bound ~ 0", with the bound
// eps KNOWN (assumption (6); the paper allows eps from another method): Pi = 0 is feasible and
// costs 0, so (8) with eps fixed has optimum 0 and every pi-hat_i(k) is 0 up to the LP tolerance.
RC_GTEST_PROP(TvBound, KnownNoiseBoundAndZeroPerturbationGiveZeroBound, ()) {
  const CraneNoiseCase c = random_crane_case();
  const double eps = *rc::gen::inRange(1, 31) / 100.0;  // 0.01-0.3 (Table III: 0.05-0.3)
  const double inside = *rc::gen::element(1.0, 0.999, 0.5, 0.1, 0.0);     // ||eta||_w / eps
  const auto data = c.data(inside * eps);
  sets::LinfBoundOptions o;
  o.F = o.G = c.nominal.cwiseInverse();
  o.epsilon = Eigen::VectorXd::Constant(1, eps);
  const auto r = sets::linf_bound(data, o);
  RC_ASSERT(r.pi.rows() == c.u.rows());
  RC_ASSERT(r.epsilon[0] == eps);
  RC_ASSERT(r.bound.cwiseProduct(o.F).maxCoeff() <= kLpTol);                     // F-weighted l-inf bound
  for (int i = 0; i < 3; ++i)  // every component: |pi-hat_i(k)| <= tol * nominal_i
    RC_ASSERT(r.pi.col(i).cwiseAbs().maxCoeff() <= kLpTol * c.nominal[i]);
  RC_ASSERT(perturbation_cost(r.pi, o.F, o.G) <= 2 * kLpTol);                  // the objective of (8)
}

// The paper's free-eps form (8), h = 1/||y_m - C zeta||_w, derived in docs/methods/tv-bound.md:
// with pi == 0 and noise s*eta, Pi-hat(s eta) = s Pi'(s) where Pi'(s) minimises
// s f(Pi') + g(Pi'), g(Pi') = ||eta - Xi Pi'||_w / ||eta||_w. It follows that
//   (a) f(Pi-hat) <= 1 (Pi = 0 costs 1);
//   (b) f(Pi-hat(s eta)) / s is non-increasing in s (never falls faster than the noise);
//   (c) eps-hat(s eta) / (s ||eta||_w) is non-decreasing in s;
//   (d) f(Pi-hat(s eta)) <= s C*, C* = min f over the best fits argmin g: the bound -> 0 linearly;
//   (e) the optimal value min (s f + g) is non-decreasing in s (so once Pi = 0 is optimal,
//       objective 1, it stays optimal for every larger noise).
// With delta-optimal LP solutions (delta = kLpTol) (b) and (c) hold up to 2 delta / (s2 - s1) and
// (d) up to delta (C* is computed at eps* (1 + 1e-9), which adds <= 1e-9).
// Seeded random crane cases, s = 1, 0.1, 0.01, 0.001 (a plain loop: 6 LPs per case).
TEST(TvBound, PaperWeightBoundFollowsTheScalingLaw) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const auto window = sets::WindowNorm::pulse(36, 1.0 / 35);
  const double scales[] = {1.0, 0.1, 0.01, 0.001};
  for (int run = 0; run < 3; ++run) {
    const Eigen::Vector3d nominal(2.0 + 0.5 * U(rng), 3.35 + 0.35 * U(rng), 0.2 + 0.05 * U(rng));  // Table II
    const auto model = sets::crane::model(nominal[1], nominal[2], nominal[0]);
    const int N = 40;
    Eigen::MatrixXd u(N, 1);
    for (int k = 0; k < N;) {
      const double level = U(rng);
      for (int e = std::min(N, k + 5 + static_cast<int>(8 * (U(rng) + 1))); k < e; ++k) u(k, 0) = level;
    }
    Eigen::VectorXd eta(N + 1);
    for (int k = 0; k <= N; ++k) eta[k] = U(rng);
    eta *= 0.3 / window(eta);  // s = 1 is Table III's largest noise, 0.3
    const Eigen::VectorXd x0 = Eigen::Vector3d::Zero();
    const auto reg = sets::biaffine_regression(model, x0, u);
    const Eigen::MatrixXd y0 = sets::simulate(model, x0, u, Eigen::MatrixXd::Zero(N, 3)).y;
    sets::LinfBoundOptions o;
    o.F = o.G = nominal.cwiseInverse();
    // C*: the best fit (F = G = 0, so (8) minimises eps alone), then the least f at that eps.
    sets::LinfBoundOptions fit;
    fit.F = fit.G = Eigen::Vector3d::Zero();
    const sets::TvBoundData unit{reg, y0 + eta, {window}};
    sets::LinfBoundOptions at_best = o;
    at_best.epsilon = sets::linf_bound(unit, fit).epsilon * (1 + 1e-9);
    const double c_star = perturbation_cost(sets::linf_bound(unit, at_best).pi, o.F, o.G);

    double prev_s = 0, prev_ratio = 0, prev_share = 0, prev_objective = 0;
    std::string trace;
    for (const double s : scales) {  // decreasing s
      const sets::TvBoundData data{reg, y0 + s * eta, {window}};
      const auto r = sets::linf_bound(data, o);
      const double f = perturbation_cost(r.pi, o.F, o.G), share = r.epsilon[0] / (0.3 * s);
      trace += " s=" + std::to_string(s) + ": f=" + std::to_string(f) + " eps/|e|=" + std::to_string(share) + ";";
      EXPECT_LE(f, 1 + kLpTol) << trace;                                           // (a)
      EXPECT_LE(f, s * c_star + kLpTol) << "C* = " << c_star << trace;             // (d)
      EXPECT_NEAR(r.objective, f + share, kLpTol) << trace;
      if (prev_s > 0) {
        const double slack = 2 * kLpTol / (prev_s - s);
        EXPECT_GE(f / s, prev_ratio - slack) << trace;                              // (b)
        EXPECT_LE(share, prev_share + kLpTol + slack) << trace;                     // (c)
        EXPECT_LE(r.objective, prev_objective + 2 * kLpTol) << trace;               // (e)
      }
      prev_s = s, prev_ratio = f / s, prev_share = share, prev_objective = r.objective;
    }
    RecordProperty("run" + std::to_string(run), "C* = " + std::to_string(c_star) + trace);
    std::printf("run %d: C* = %.4g;%s\n", run, c_star, trace.c_str());
  }
}

TEST(TvBound, SparseBoundPlacesASingleStep) {
  // The paper's pipeline: eps from (8) with the paper's h, then (14) with the l-inf trajectory as
  // warm start. A unit step in the gain (pi2, through Q) or the offset (pi3, through D) at a
  // random sample; the largest jump of the MILP estimate in that parameter must lie within 3
  // samples of the true one in at least 2/3 of the runs. Every MILP must be PROVEN optimal within
  // a node limit (a run that hits it counts as a miss). GLPK's branch-and-bound is deterministic
  // and the limit counts nodes, not seconds, so the count does not depend on the machine's speed;
  // the time limit is only a guard against a hang.
  std::mt19937 rng(11);
  const int runs = 9, N = 20;
  int hits = 0;
  for (int run = 0; run < runs; ++run) {
    const int param = 1 + run % 2, at = std::uniform_int_distribution<int>(N / 5, N - N / 4)(rng);
    Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
    pi.block(at, param, N - at, 1).setConstant(1.0);
    const auto data = small_data(pi, 0.01, 100 + run, 8, 10);
    const auto lin = sets::linf_bound(data);
    auto o = milp_options(lin.epsilon, 20000, 2.0);
    o.start = lin.pi;
    const auto r = sets::sparse_bound(data, o);
    int best_k = -1;
    double best = 0;
    for (const auto& c : r.changes)
      if (c.parameter == param && std::abs(c.size) > best) best = std::abs(c.size), best_k = c.sample;
    const bool optimal = r.status == sets::MilpStatus::optimal;
    if (optimal && std::abs(best_k - at) <= 3) ++hits;
    char line[200];
    std::snprintf(line, sizeof line,
                  "pi%d step at %d -> largest jump at %d (%.2f), %zu jumps, eps %.4g, %s, %ld nodes, %.2f s", param + 1,
                  at, best_k, best, r.changes.size(), lin.epsilon[0], sets::to_string(r.status), r.nodes, r.seconds);
    RecordProperty("run" + std::to_string(run), line);
    std::printf("run %d: %s\n", run, line);
  }
  EXPECT_GE(3 * hits, 2 * runs) << hits << " of " << runs;
}

TEST(TvBound, PaperAndSingleBinaryFormulationsAgree) {
  // One binary per jump drops the sign symmetry of (12) but keeps the optimum.
  const int N = 16;
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(6, 2, N - 6, 1).setConstant(0.4);
  pi.block(10, 1, N - 10, 1).setConstant(-0.3);
  const auto data = small_data(pi, 0.01, 5, 4);
  const auto lin = sets::linf_bound(data);
  auto o = milp_options(lin.epsilon, 50000);
  o.solver = sets::SparseSolver::glpk_big_m;
  const auto single = sets::sparse_bound(data, o);
  o.formulation = sets::SparseFormulation::paper;
  const auto paper = sets::sparse_bound(data, o);
  ASSERT_TRUE(single.status == sets::MilpStatus::optimal) << sets::to_string(single.status);
  ASSERT_TRUE(paper.status == sets::MilpStatus::optimal) << sets::to_string(paper.status);
  EXPECT_NEAR(single.objective, paper.objective, 1e-3 * (1 + std::abs(paper.objective)));
  // Both satisfy the window-norm constraint with the given eps.
  EXPECT_LE(data.ball().norms(sets::stack_samples(single.residual))[0], lin.epsilon[0] * (1 + 1e-6) + 1e-9);
}

TEST(TvBound, CoarserJumpGridIsARestriction) {
  // The quantized approximation: jumps only where k is a multiple of the grid. Its optimum is
  // feasible for (14), so it is no better than (14)'s; every jump lies on the grid.
  const int N = 18;
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(7, 1, N - 7, 1).setConstant(0.5);  // off the grid of 3
  const auto data = small_data(pi, 0.01, 41, 4);
  const auto lin = sets::linf_bound(data);
  auto o = milp_options(lin.epsilon, 50000);
  const auto fine = sets::sparse_bound(data, o);
  for (auto solver : {sets::SparseSolver::jump_search, sets::SparseSolver::glpk_big_m}) {
    o.solver = solver;
    o.grid = 3;
    const auto coarse = sets::sparse_bound(data, o);
    ASSERT_TRUE(coarse.status == sets::MilpStatus::optimal);
    EXPECT_GE(coarse.objective, fine.objective - 1e-4 * (1 + fine.objective));
    for (const auto& c : coarse.changes) EXPECT_EQ(c.sample % 3, 0) << "jump at " << c.sample;
  }
  o.grid = 0;
  EXPECT_THROW(sets::sparse_bound(data, o), sets::InputError);
}

namespace {

// Runs f, expects an exception of type E whose message contains `names`.
template <class E = sets::InputError, class Fn>
void expect_error_naming(Fn&& f, const std::string& names) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one naming \"" << names << "\"";
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << "\"" << e.what() << "\" lacks \"" << names << "\"";
  }
}

}  // namespace

TEST(TvBound, BadInputIsRejectedWithClearErrors) {
  auto m = small_model();
  const Eigen::MatrixXd u = square_input(10, 3);
  const Eigen::VectorXd x0 = Eigen::Vector2d::Zero();
  // Dimensions that do not match.
  auto bad = m;
  bad.P = Eigen::MatrixXd::Zero(2, 5);  // should be n x nq = 2 x 6
  expect_error_naming([&] { sets::biaffine_regression(bad, x0, u); }, "P (n x nq)");
  expect_error_naming([&] { sets::biaffine_regression(m, Eigen::Vector3d::Zero(), u); }, "x0 has 3 entries");
  expect_error_naming([&] { sets::biaffine_regression(m, x0, Eigen::MatrixXd(10, 2)); }, "the input has 2");
  expect_error_naming([&] { sets::biaffine_regression(m, x0, Eigen::MatrixXd(0, 1)); }, "no samples");
  expect_error_naming([&] { sets::simulate(m, x0, u, Eigen::MatrixXd::Zero(9, 3)); }, "perturbation is 9 x 3");
  const auto reg = sets::biaffine_regression(m, x0, u);
  const auto w = sets::WindowNorm::pulse(3, 1.0 / 3);
  // y needs N + 1 = 11 samples and one column per output.
  expect_error_naming([&] { sets::linf_bound({reg, Eigen::MatrixXd::Zero(10, 1), {w}}); }, "10 samples, the model 11");
  expect_error_naming([&] { sets::linf_bound({reg, Eigen::MatrixXd::Zero(11, 2), {w}}); }, "2 columns");
  expect_error_naming([&] { sets::linf_bound({reg, Eigen::MatrixXd::Zero(11, 1), {}}); }, "0 windows given for 1");
  expect_error_naming([&] { sets::linf_bound({reg, Eigen::MatrixXd::Zero(11, 1), {w, w}}); }, "2 windows given");
  // An empty window and a window that is not monotone decreasing.
  expect_error_naming([] { (void)sets::WindowNorm(Eigen::VectorXd()); }, "window is empty");
  expect_error_naming([] { sets::WindowNorm::pulse(0, 1.0); }, "length 0");
  expect_error_naming([] { sets::WindowNorm(Eigen::Vector3d(0.5, 0.4, 0.45)); }, "increases at sample 2");
  // Options of the l-inf method.
  const Eigen::MatrixXd y = Eigen::MatrixXd::Ones(11, 1);
  const sets::TvBoundData data{reg, y, {w}};
  sets::LinfBoundOptions lo;
  lo.F = Eigen::Vector2d::Ones();  // q = 3
  expect_error_naming([&] { sets::linf_bound(data, lo); }, "F has 2 entries, expected 3");
  lo = {};
  lo.h = Eigen::Vector2d::Ones();  // l = 1
  expect_error_naming([&] { sets::linf_bound(data, lo); }, "h needs one");
  lo = {};
  lo.epsilon = Eigen::Vector2d::Constant(0.1);  // l = 1
  expect_error_naming([&] { sets::linf_bound(data, lo); }, "epsilon needs one finite non-negative");
  lo.epsilon = Eigen::VectorXd::Constant(1, -0.1);
  expect_error_naming([&] { sets::linf_bound(data, lo); }, "epsilon needs one finite non-negative");
  lo.epsilon = Eigen::VectorXd::Constant(1, NAN);
  expect_error_naming([&] { sets::linf_bound(data, lo); }, "epsilon needs one finite non-negative");
  lo.epsilon = Eigen::VectorXd::Constant(1, 0.5);
  lo.h = Eigen::VectorXd::Ones(1);
  expect_error_naming([&] { sets::linf_bound(data, lo); }, "not both");
  // A known eps the data violate: y(0) - C x0 = 1 is beyond any perturbation (Xi's first row is 0)
  // and w(0) * 1 = 1/3 > 0.1.
  lo.h.resize(0);
  lo.epsilon = Eigen::VectorXd::Constant(1, 0.1);
  const auto falsified = sets::linf_bound(data, lo);
  EXPECT_TRUE(falsified.falsified());
  EXPECT_EQ(falsified.pi.size(), 0);
  EXPECT_NE(falsified.consistency.message().find("falsify"), std::string::npos);
  lo.epsilon = Eigen::VectorXd::Constant(1, 0.34);
  const auto within = sets::linf_bound(data, lo);
  EXPECT_EQ(within.consistency.falsified, sets::Falsified::unknown);  // a floating-point trajectory, not verified
  EXPECT_GT(within.pi.size(), 0);
  lo.epsilon.resize(0);
  EXPECT_EQ(sets::linf_bound(data, lo).consistency.falsified, sets::Falsified::no);  // eps free: always explained
  // Options of the sparse method.
  sets::SparseBoundOptions so;  // mu, max_abs and epsilon missing
  expect_error_naming([&] { sets::sparse_bound(data, so); }, "mu needs one positive threshold");
  so.mu = Eigen::Vector3d::Constant(0.01);
  expect_error_naming([&] { sets::sparse_bound(data, so); }, "max_abs needs one positive finite");
  so.max_abs = Eigen::Vector3d::Constant(1);
  expect_error_naming([&] { sets::sparse_bound(data, so); }, "epsilon needs one non-negative");
  so.epsilon = Eigen::VectorXd::Constant(1, 0.1);
  so.start = Eigen::MatrixXd::Zero(9, 3);  // N = 10
  expect_error_naming([&] { sets::sparse_bound(data, so); }, "start trajectory is 9 x 3, expected 10 x 3");
  so.max_abs[1] = sets::inf;
  so.start.resize(0, 0);
  expect_error_naming([&] { sets::sparse_bound(data, so); }, "max_abs");
}

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
