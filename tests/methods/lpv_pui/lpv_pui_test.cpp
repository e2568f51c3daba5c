// Cerone–Regruto's PUIs of LPV models with errors in the variables: the regressor boxes contain
// the true regressors, the true theta lies in every PUI over 500 random LPV systems, bad input
// fails with a message that names the sample and the field, and falsifying data name their samples.

#include <gtest/gtest.h>

#include <random>

#include "sets/core/error.hpp"
#include "sets/examples/cerone_regruto.hpp"
#include "sets/methods/lpv_pui/lpv_pui.hpp"

namespace {

using sets::BasisFunction;
using sets::Interval;
using sets::LpvMeasurements;
using sets::LpvModelStructure;

struct Experiment {
  LpvModelStructure model;
  Eigen::VectorXd theta;
  Eigen::MatrixXd lambda;  // true scheduling
  Eigen::VectorXd w;       // true output
  LpvMeasurements data;
};

// A random stable LPV system: random orders, scheduling dimension, bases and noise bounds.
Experiment random_experiment(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1), P(0, 1);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  Experiment e;
  LpvModelStructure& m = e.model;
  m.alpha = pick(1, 2);
  // Pools without near-collinear pairs (sin l ~ l on [-1, 1] would make the set unbounded).
  const std::vector<std::string> pool1 = {"1", "lambda", "lambda^2", "exp(lambda)", "cos(lambda)", "tanh(lambda)^3"};
  const std::vector<std::string> pool2 = {"1", "l1", "l2", "l1*l2", "l1^2", "exp(l2)", "tanh(l1)*l2^2", "cos(l1)"};
  const auto& pool = m.alpha == 1 ? pool1 : pool2;
  auto basis = [&](int max_terms) {
    std::vector<BasisFunction> b;
    std::vector<std::string> chosen = pool;
    std::shuffle(chosen.begin(), chosen.end(), rng);
    const int n = pick(0, max_terms);
    for (int k = 0; k < n; ++k) b.push_back(sets::parse_basis_function(chosen[static_cast<std::size_t>(k)], m.alpha));
    return b;
  };
  const int na = pick(1, 2), nb = pick(0, 2);
  for (int i = 0; i < na; ++i) m.a.push_back(basis(2));
  for (int j = 0; j <= nb; ++j) m.b.push_back(basis(2));
  if (m.num_parameters() == 0) m.b[0].push_back(BasisFunction());
  while (m.num_parameters() > 5) {
    for (auto& v : m.a) if (!v.empty() && m.num_parameters() > 5) v.pop_back();
    for (auto& v : m.b) if (!v.empty() && m.num_parameters() > 5) v.pop_back();
  }
  // Without an input term the output stays 0 from zero initial conditions: nothing to identify.
  int b_terms = 0;
  for (const auto& v : m.b) b_terms += static_cast<int>(v.size());
  if (b_terms == 0) {
    if (m.num_parameters() == 5)
      for (auto& v : m.a) if (!v.empty() && m.num_parameters() == 5) v.pop_back();
    m.b.back().push_back(BasisFunction());
  }
  const int p = m.num_parameters();
  const int T = pick(4 * p + m.first_regression() + 10, 60);
  // Scheduling in [-1, 1] (uniform or sinusoidal), noise bounds per signal.
  const double deps = P(rng) < 0.2 ? 0.0 : 0.001 + 0.02 * P(rng);
  const double deta = 0.001 + 0.02 * P(rng);
  e.lambda.resize(T, m.alpha);
  const bool sinus = P(rng) < 0.5;
  for (int t = 0; t < T; ++t)
    for (int s = 0; s < m.alpha; ++s) e.lambda(t, s) = sinus ? std::sin(0.1 * (t + 1) + s) : U(rng);
  // theta: entries of magnitude 0.1..1, random signs; the a-part scaled so that
  // sum |a_ik| max|f_ik| <= 0.8 keeps the recursion stable.
  e.theta.resize(p);
  for (int l = 0; l < p; ++l) e.theta[l] = (0.1 + 0.9 * P(rng)) * (U(rng) < 0 ? -1 : 1);
  sets::IntervalVector big(m.alpha);
  for (int s = 0; s < m.alpha; ++s) big[s] = Interval(-1 - deps, 1 + deps);
  double gain = 0;
  int l = 0;
  for (const auto& v : m.a)
    for (const auto& f : v) gain += std::abs(e.theta[l++]) * boost::numeric::norm(f.range(big));
  if (gain > 0.8)
    for (int k = 0; k < l; ++k) e.theta[k] *= 0.8 / gain;
  Eigen::VectorXd u(T);
  for (int t = 0; t < T; ++t) u[t] = U(rng);
  e.w = sets::simulate_lpv(m, e.theta, u, e.lambda);
  e.data.u = u;
  e.data.y.resize(T);
  e.data.r.resize(T, m.alpha);
  for (int t = 0; t < T; ++t) {
    e.data.y[t] = e.w[t] + deta * U(rng);
    for (int s = 0; s < m.alpha; ++s) e.data.r(t, s) = e.lambda(t, s) + deps * U(rng);
  }
  e.data.delta_eta = Eigen::VectorXd::Constant(1, deta);
  e.data.delta_eps = Eigen::MatrixXd::Constant(1, m.alpha, deps);
  return e;
}

// The true regressor of row `row` (eqs. 15–17 with the true w and lambda).
Eigen::VectorXd true_regressor(const Experiment& e, int t) {
  const auto& m = e.model;
  Eigen::VectorXd phi(m.num_parameters());
  const Eigen::VectorXd lam = e.lambda.row(t).transpose();
  int l = 0;
  for (int i = 1; i <= m.na(); ++i)
    for (const auto& f : m.a[static_cast<std::size_t>(i - 1)]) phi[l++] = -e.w[t - i] * f(lam);
  for (int j = 0; j <= m.nb(); ++j)
    for (const auto& g : m.b[static_cast<std::size_t>(j)]) phi[l++] = e.data.u[t - j] * g(lam);
  return phi;
}

}  // namespace

TEST(LpvPui, TrueThetaInsideEveryPuiOver500RandomLpvSystems) {
  int covered = 0, with_all_orthants = 0, unbounded = 0;
  for (std::uint64_t seed = 1; seed <= 500; ++seed) {
    const Experiment e = random_experiment(seed);
    const auto r = sets::lpv_pui(e.model, e.data);
    // Eqs. 18–26: each true regressor lies in its box (up to the simulation's own rounding).
    for (Eigen::Index row = 0; row < r.regression.Phi.rows(); ++row) {
      const Eigen::VectorXd phi = true_regressor(e, r.regression.time[static_cast<std::size_t>(row)]);
      for (Eigen::Index j = 0; j < phi.size(); ++j) {
        ASSERT_GE(phi[j], r.regression.Phi(row, j).lower() - 1e-14) << "seed " << seed << " row " << row;
        ASSERT_LE(phi[j], r.regression.Phi(row, j).upper() + 1e-14) << "seed " << seed << " row " << row;
      }
    }
    ASSERT_EQ(r.pui.consistency.falsified, sets::Falsified::no) << "seed " << seed;
    ASSERT_TRUE(sets::contains(r.pui.box, e.theta)) << "seed " << seed;
    // A badly excited random system can have an unbounded feasible set; pui() then reports ends
    // it cannot certify. Every bounded answer must be fully certified.
    bool bounded = true;
    for (Eigen::Index j = 0; j < r.pui.box.size(); ++j)
      bounded = bounded && std::abs(r.pui.box[j].lower()) < 1e6 && std::abs(r.pui.box[j].upper()) < 1e6;
    if (bounded)
      ASSERT_TRUE(r.pui.guaranteed) << "seed " << seed;
    else {
      ++unbounded;
    }
    ++covered;
    if (seed % 25 == 0 && e.model.num_parameters() <= 4) {
      // All orthants: a superset of the Remark-2 orthants, so a box at least as large.
      const auto all = sets::lpv_pui(e.model, e.data, {.orthants = sets::OrthantSelection::all});
      ASSERT_TRUE(sets::contains(all.pui.box, e.theta));
      for (Eigen::Index j = 0; j < e.theta.size(); ++j) {
        EXPECT_LE(all.pui.box[j].lower(), r.pui.box[j].lower() + 1e-9);
        EXPECT_GE(all.pui.box[j].upper(), r.pui.box[j].upper() - 1e-9);
      }
      ++with_all_orthants;
    }
  }
  EXPECT_EQ(covered, 500);
  EXPECT_GT(with_all_orthants, 0);
  EXPECT_LT(unbounded, 25);  // the generator aims at identifiable systems
  std::cout << "    " << covered << " systems, true theta inside every PUI; " << unbounded
            << " with an unbounded feasible set\n";
}

TEST(LpvPui, BadInputIsReportedWithSampleAndField) {
  const Experiment e = random_experiment(7);
  auto expect_error = [&](const LpvMeasurements& d, const std::vector<std::string>& words) {
    try {
      sets::lpv_pui(e.model, d);
      FAIL() << "no error";
    } catch (const sets::InputError& err) {
      for (const auto& w : words) EXPECT_NE(std::string(err.what()).find(w), std::string::npos) << err.what();
    }
  };
  LpvMeasurements d = e.data;
  d.y[5] = NAN;
  expect_error(d, {"sample 5", "output y"});
  d = e.data;
  d.r(3, 0) = NAN;
  expect_error(d, {"sample 3", "scheduling"});
  d = e.data;
  d.u[4] = INFINITY;
  expect_error(d, {"sample 4", "input u"});
  d = e.data;
  d.delta_eta[0] = -0.1;
  expect_error(d, {"delta_eta", ">= 0"});
  d = e.data;
  d.delta_eps(0, 0) = -1;
  expect_error(d, {"delta_eps", ">= 0"});
  // More parameters than regressions.
  d = e.data;
  const int keep = e.model.first_regression() + e.model.num_parameters() - 1;
  d.u = d.u.head(keep).eval();
  d.y = d.y.head(keep).eval();
  d.r = d.r.topRows(keep).eval();
  expect_error(d, {"regressions", "parameters"});
}

TEST(LpvPui, DataThatNoThetaExplainsAreReportedWithTheirSamples) {
  // Section IV's system, 30 samples, bounds 1e-3; sample 15's output is off by 0.5.
  const auto m = sets::cerone_regruto::structure();
  const Eigen::VectorXd theta = sets::cerone_regruto::true_theta();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  const int T = 30;
  Eigen::VectorXd u(T);
  Eigen::MatrixXd lambda(T, 1);
  for (int t = 0; t < T; ++t) {
    u[t] = U(rng);
    lambda(t, 0) = U(rng);
  }
  const Eigen::VectorXd w = sets::simulate_lpv(m, theta, u, lambda);
  LpvMeasurements d;
  d.u = u;
  d.y = w + 1e-3 * Eigen::VectorXd::NullaryExpr(T, [&] { return U(rng); });
  d.r = lambda + 1e-3 * Eigen::MatrixXd::NullaryExpr(T, 1, [&] { return U(rng); });
  d.delta_eta = Eigen::VectorXd::Constant(1, 1e-3);
  d.delta_eps = Eigen::MatrixXd::Constant(1, 1, 1e-3);
  ASSERT_EQ(sets::lpv_pui(m, d).pui.consistency.falsified, sets::Falsified::no);  // consistent before the fault
  d.y[15] += 0.5;
  const auto r = sets::lpv_pui(m, d);
  ASSERT_TRUE(r.pui.empty());
  ASSERT_FALSE(r.falsifying_times.empty());
  // y_15 is the output of regression 15 and a regressor of 16 and 17.
  bool named = false;
  for (int t : r.falsifying_times) named = named || (t >= 15 && t <= 17);
  EXPECT_TRUE(named);
  EXPECT_NE(r.pui.consistency.conflict.message().find("falsify"), std::string::npos);
}

TEST(LpvPui, WorkingSetLpsGiveTheSamePuisAsTheFullLps) {
  // pui()'s constraint generation must not change the answer, only the time.
  const auto m = sets::cerone_regruto::structure();
  const Eigen::VectorXd theta = sets::cerone_regruto::true_theta();
  for (double delta : {1e-3, 3e-2}) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(delta * 1e6));
    std::uniform_real_distribution<double> U(-1, 1);
    const int T = 1500;
    Eigen::VectorXd u(T);
    Eigen::MatrixXd lambda(T, 1);
    for (int t = 0; t < T; ++t) {
      u[t] = U(rng);
      lambda(t, 0) = U(rng);
    }
    LpvMeasurements d;
    d.u = u;
    d.y = sets::simulate_lpv(m, theta, u, lambda) + delta * Eigen::VectorXd::NullaryExpr(T, [&] { return U(rng); });
    d.r = lambda + delta * Eigen::MatrixXd::NullaryExpr(T, 1, [&] { return U(rng); });
    d.delta_eta = Eigen::VectorXd::Constant(1, delta);
    d.delta_eps = Eigen::MatrixXd::Constant(1, 1, delta);
    const auto ws = sets::lpv_pui(m, d);
    const auto full = sets::lpv_pui(m, d, {.working_set = false});
    ASSERT_TRUE(ws.pui.guaranteed && full.pui.guaranteed);
    ASSERT_TRUE(sets::contains(ws.pui.box, theta));
    for (int l = 0; l < 6; ++l) {
      const double w = full.pui.box[l].upper() - full.pui.box[l].lower();
      EXPECT_NEAR(ws.pui.box[l].lower(), full.pui.box[l].lower(), 1e-7 * w) << l;
      EXPECT_NEAR(ws.pui.box[l].upper(), full.pui.box[l].upper(), 1e-7 * w) << l;
    }
  }
}
