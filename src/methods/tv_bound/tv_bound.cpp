#include "sets/methods/tv_bound/tv_bound.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "sets/core/error.hpp"
#include "sets/numeric/lp_certificate.hpp"
#include "methods/tv_bound/jump_search.hpp"

namespace sets {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

Eigen::VectorXd diagonal_or_ones(const Eigen::VectorXd& d, int q, const char* what) {
  if (d.size() == 0) return Eigen::VectorXd::Ones(q);
  if (d.size() != q)
    throw InputError(std::string(what) + " has " + std::to_string(d.size()) + " entries, expected " +
                     std::to_string(q) + " (one per parameter)");
  if (!d.allFinite() || (d.array() < 0).any()) throw InputError(std::string(what) + " must be finite and non-negative");
  return d;
}

// Rows  -t <= w_i * expr <= t  for every parameter i at every sample k (expr = pi or Delta pi).
void add_peak_rows(LinearProgram& lp, int N, int q, const Eigen::VectorXd& w, int t_col, bool difference,
                   bool initial_difference) {
  for (int k = 0; k < N; ++k) {
    if (difference && k == 0 && !initial_difference) continue;
    for (int i = 0; i < q; ++i) {
      std::vector<std::pair<int, double>> row{{k * q + i, w[i]}};
      if (difference && k > 0) row.emplace_back((k - 1) * q + i, -w[i]);
      row.emplace_back(t_col, -1.0);
      lp.add_row(row, -inf, 0.0);
      row.back().second = 1.0;
      lp.add_row(row, 0.0, inf);
    }
  }
}

void fill_result(const TvBoundData& data, const Eigen::VectorXd& pi_stacked, const Eigen::VectorXd& mu,
                 TvBoundResult& r) {
  const int q = data.parameters();
  r.pi = unstack_samples(pi_stacked, q);
  r.bound = r.pi.cwiseAbs().colwise().maxCoeff().transpose();
  const Eigen::VectorXd V =
      stack_samples(data.y) - data.regression.upsilon - data.regression.xi * pi_stacked;
  r.residual = unstack_samples(V, data.outputs());
  r.changes.clear();
  for (int k = 0; k < r.pi.rows(); ++k)
    for (int i = 0; i < q; ++i) {
      const double d = r.pi(k, i) - (k > 0 ? r.pi(k - 1, i) : 0.0);
      // A jump exactly at the threshold is free in (12)-(13): count only those above it.
      if (std::abs(d) > mu[i] * (1 + 1e-6) + 1e-9) r.changes.push_back({k, i, d});
    }
}

}  // namespace

int TvBoundData::parameters() const {
  const int N = samples();
  return N > 0 ? static_cast<int>(regression.xi.cols()) / N : 0;
}

void TvBoundData::validate() const {
  const int N = samples();
  if (N <= 0) throw InputError("TvBoundData: the regression has no samples (build it with biaffine_regression)");
  const int l = outputs();
  if (y.rows() != N + 1)
    throw InputError("TvBoundData: the measured output has " + std::to_string(y.rows()) + " samples, the model " +
                     std::to_string(N + 1) + " (y(0..N) for N = " + std::to_string(N) + " input samples)");
  if (l == 0 || regression.upsilon.size() != static_cast<Eigen::Index>(N + 1) * l)
    throw InputError("TvBoundData: the measured output has " + std::to_string(l) +
                     " columns, which does not match the model's outputs");
  if (regression.xi.rows() != regression.upsilon.size() || regression.xi.cols() % N != 0 ||
      regression.xi.cols() == 0)
    throw InputError("TvBoundData: Xi is " + std::to_string(regression.xi.rows()) + " x " +
                     std::to_string(regression.xi.cols()) + ", inconsistent with Upsilon and N");
  if (!y.allFinite()) throw InputError("TvBoundData: the measured output holds a non-finite value");
  if (windows.size() != 1 && static_cast<int>(windows.size()) != l)
    throw InputError("TvBoundData: " + std::to_string(windows.size()) + " windows given for " + std::to_string(l) +
                     " outputs (give one, or one per output)");
}

WindowNormBall TvBoundData::ball() const {
  std::vector<WindowNorm> w = windows;
  if (w.size() == 1) w.assign(static_cast<std::size_t>(outputs()), windows.front());
  return WindowNormBall(std::move(w), samples() + 1);
}

Eigen::VectorXd paper_epsilon_weight(const TvBoundData& data) {
  data.validate();
  Eigen::VectorXd h = data.ball().norms(stack_samples(data.y) - data.regression.upsilon);
  for (Eigen::Index j = 0; j < h.size(); ++j) {
    if (h[j] == 0)
      throw InputError("paper_epsilon_weight: output " + std::to_string(j) +
                       " equals the nominal model exactly, so h = 1/||y_m - C zeta||_w is undefined; give h or epsilon");
    h[j] = 1.0 / h[j];
  }
  return h;
}

TvBoundResult linf_bound(const TvBoundData& data, const LinfBoundOptions& options) {
  data.validate();
  const auto t0 = Clock::now();
  const int N = data.samples(), q = data.parameters(), l = data.outputs();
  const Eigen::VectorXd F = diagonal_or_ones(options.F, q, "linf_bound: F");
  const Eigen::VectorXd G = diagonal_or_ones(options.G, q, "linf_bound: G");
  const WindowNormBall ball = data.ball();
  const Eigen::VectorXd offset = stack_samples(data.y) - data.regression.upsilon;
  const bool fixed_eps = options.epsilon.size() > 0;
  if (fixed_eps) {
    if (options.epsilon.size() != l || !options.epsilon.allFinite() || (options.epsilon.array() < 0).any())
      throw InputError("linf_bound: epsilon needs one finite non-negative window-norm bound per output (" +
                       std::to_string(l) + "), got " + std::to_string(options.epsilon.size()) + " entries");
    if (options.h.size() > 0)
      throw InputError("linf_bound: give either epsilon (a known noise bound) or its weight h, not both");
  }
  Eigen::VectorXd h = options.h;
  if (!fixed_eps && h.size() == 0) {
    h = paper_epsilon_weight(data);
  } else if (!fixed_eps && (h.size() != l || !h.allFinite() || (h.array() < 0).any())) {
    throw InputError("linf_bound: h needs one finite non-negative weight per output");
  }

  LinearProgram lp(N * q);
  const int tF = lp.add_variables(1, 0, inf), tG = lp.add_variables(1, 0, inf);
  add_peak_rows(lp, N, q, F, tF, false, options.initial_difference);
  add_peak_rows(lp, N, q, G, tG, true, options.initial_difference);
  const auto blk = ball.add_to(lp, offset, data.regression.xi, 0, options.epsilon);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(lp.num_variables());
  c[tF] = 1;
  c[tG] = 1;
  if (!fixed_eps) c.segment(blk.first_eps, l) = h;
  lp.set_objective(c, Sense::minimize);
  const LpSolution s = lp.solve();
  // Falsified only with an exactly verified Farkas certificate; an infeasible floating-point LP
  // alone cannot tell "the data falsify the model" from rounding.
  if (fixed_eps && s.status == LpStatus::infeasible && !prove_infeasible(lp))
    throw NumericalError("linf_bound: the LP solver found no perturbation trajectory within epsilon, but no "
                         "certificate of it could be verified: whether the data falsify the model is undecided");
  TvBoundResult r;
  if (fixed_eps && s.status == LpStatus::infeasible) {
    r.consistency.falsified = Falsified::yes;
    r.epsilon = options.epsilon;
    return r;
  }
  if (s.status != LpStatus::optimal)
    throw NumericalError(std::string("linf_bound: the LP is ") + to_string(s.status) + " (it is feasible by construction)");

  if (!fixed_eps) {
    r.consistency.falsified = Falsified::no;
  } else {
    r.consistency.reason = "the LP found a perturbation trajectory within epsilon in floating point (not verified)";
  }
  r.objective = s.objective;
  r.epsilon = fixed_eps ? options.epsilon : Eigen::VectorXd(s.x.segment(blk.first_eps, l));
  Eigen::VectorXd mu = options.mu;
  const Eigen::VectorXd pi = s.x.head(static_cast<Eigen::Index>(N) * q);
  if (mu.size() == 0) mu = 1e-3 * unstack_samples(pi, q).cwiseAbs().colwise().maxCoeff().transpose();
  else diagonal_or_ones(mu, q, "linf_bound: mu");
  fill_result(data, pi, mu, r);
  r.seconds = seconds_since(t0);
  return r;
}

namespace {

void check_sparse_options(const SparseBoundOptions& o, int N, int q, int l) {
  if (o.mu.size() != q || !o.mu.allFinite() || (o.mu.array() <= 0).any())
    throw InputError("sparse_bound: mu needs one positive threshold per parameter (" + std::to_string(q) + ")");
  if (o.max_abs.size() != q || !o.max_abs.allFinite() || (o.max_abs.array() <= 0).any())
    throw InputError("sparse_bound: max_abs needs one positive finite bound per parameter (" + std::to_string(q) +
                     "); it sets the big-M of (12)");
  if (o.epsilon.size() != l || !o.epsilon.allFinite() || (o.epsilon.array() < 0).any())
    throw InputError("sparse_bound: epsilon needs one non-negative window-norm bound per output (" +
                     std::to_string(l) + "), e.g. linf_bound(...).epsilon");
  if (o.start.size() > 0 && (o.start.rows() != N || o.start.cols() != q))
    throw InputError("sparse_bound: the start trajectory is " + std::to_string(o.start.rows()) + " x " +
                     std::to_string(o.start.cols()) + ", expected " + std::to_string(N) + " x " + std::to_string(q));
  if (o.grid < 1) throw InputError("sparse_bound: grid must be >= 1 (1 = a jump may occur at every sample)");
  if (!(o.epsilon_slack >= 0) || !std::isfinite(o.epsilon_slack))
    throw InputError("sparse_bound: epsilon_slack must be finite and >= 0");
}

// The MILP (14): pi (N x q) within max_abs, the peak t_F, one or two binaries per difference
// Delta pi_i(k) (13), the window-norm rows; minimise t_F + the number of jumps.
struct SparseMilp {
  SparseMilp(const TvBoundData& data, const SparseBoundOptions& o, const Eigen::VectorXd& F);
  int bin(int k, int i, int which) const { return first_bin + ((k - k0) * q + i) * per + which; }
  Eigen::VectorXd start_point(const TvBoundData& data, const SparseBoundOptions& o, const Eigen::VectorXd& F) const;

  const int N, q, k0, per;
  const Eigen::VectorXd offset;
  LinearProgram lp;
  int tF = -1, first_bin = -1;
  WindowNormBall::LpBlock blk;

 private:
  void add_jump_rows(const SparseBoundOptions& o);
};

SparseMilp::SparseMilp(const TvBoundData& data, const SparseBoundOptions& o, const Eigen::VectorXd& F)
    : N(data.samples()), q(data.parameters()), k0(o.initial_difference ? 0 : 1),
      per(o.formulation == SparseFormulation::paper ? 2 : 1),
      offset(stack_samples(data.y) - data.regression.upsilon), lp(N * q) {
  for (int k = 0; k < N; ++k)
    for (int i = 0; i < q; ++i) lp.set_variable_bounds(k * q + i, -o.max_abs[i], o.max_abs[i]);
  tF = lp.add_variables(1, 0, inf);
  add_peak_rows(lp, N, q, F, tF, false, o.initial_difference);
  first_bin = lp.add_variables((N - k0) * q * per, 0, 1);
  for (int j = first_bin; j < lp.num_variables(); ++j) lp.set_integer(j);
  for (int k = k0; k < N; ++k)  // the quantized approximation: no jump off the grid
    if (k % o.grid != 0)
      for (int i = 0; i < q; ++i)
        for (int w = 0; w < per; ++w) lp.set_variable_bounds(bin(k, i, w), 0, 0);
  add_jump_rows(o);
  blk = data.ball().add_to(lp, offset, data.regression.xi, 0, o.epsilon * (1 + o.epsilon_slack));
  Eigen::VectorXd c = Eigen::VectorXd::Zero(lp.num_variables());
  c[tF] = 1;
  c.segment(first_bin, (N - k0) * q * per).setOnes();
  lp.set_objective(c, Sense::minimize);
}

// The big-M rows linking each difference to its binaries.
void SparseMilp::add_jump_rows(const SparseBoundOptions& o) {
  for (int k = k0; k < N; ++k)
    for (int i = 0; i < q; ++i) {
      const double mu = o.mu[i], M = (k == 0 ? 1.0 : 2.0) * o.max_abs[i] + mu;
      std::vector<std::pair<int, double>> s{{k * q + i, 1.0}};
      if (k > 0) s.emplace_back((k - 1) * q + i, -1.0);
      auto row = s;
      if (per == 1) {  // -mu - M d <= s <= mu + M d
        row.emplace_back(bin(k, i, 0), -M);
        lp.add_row(row, -inf, mu);
        row.back().second = M;
        lp.add_row(row, -mu, inf);
      } else {  // (12): 2 mu d1 - M d2 - mu <= s <= M d1 - 2 mu d2 + mu,  d1 + d2 <= 1
        row.emplace_back(bin(k, i, 0), -2 * mu);
        row.emplace_back(bin(k, i, 1), M);
        lp.add_row(row, -mu, inf);
        row = s;
        row.emplace_back(bin(k, i, 0), -M);
        row.emplace_back(bin(k, i, 1), 2 * mu);
        lp.add_row(row, -inf, mu);
        lp.add_row(std::vector<std::pair<int, double>>{{bin(k, i, 0), 1.0}, {bin(k, i, 1), 1.0}}, -inf, 1.0);
      }
    }
}

// The user's start trajectory as a point of the MILP: its peak, its jumps on the grid, its
// window-norm slacks.
Eigen::VectorXd SparseMilp::start_point(const TvBoundData& data, const SparseBoundOptions& o,
                                        const Eigen::VectorXd& F) const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(lp.num_variables());
  const Eigen::VectorXd pi = stack_samples(o.start);
  x.head(pi.size()) = pi;
  x[tF] = (o.start * F.asDiagonal()).cwiseAbs().maxCoeff();
  for (int k = k0; k < N; ++k)
    for (int i = 0; i < q; ++i) {
      const double d = o.start(k, i) - (k > 0 ? o.start(k - 1, i) : 0.0);
      if (std::abs(d) <= o.mu[i] || k % o.grid != 0) continue;
      if (per == 1) x[bin(k, i, 0)] = 1;
      else x[bin(k, i, d > 0 ? 0 : 1)] = 1;
    }
  x.segment(blk.first_t, offset.size()) = (offset - data.regression.xi * pi).cwiseAbs();
  return x;
}

}  // namespace

TvBoundResult sparse_bound(const TvBoundData& data, const SparseBoundOptions& o) {
  data.validate();
  const auto t0 = Clock::now();
  const int N = data.samples(), q = data.parameters();
  const Eigen::VectorXd F = diagonal_or_ones(o.F, q, "sparse_bound: F");
  check_sparse_options(o, N, q, data.outputs());
  if (o.solver == SparseSolver::jump_search) {
    TvBoundResult r = detail::jump_search(data, o);
    r.epsilon = o.epsilon;
    fill_result(data, stack_samples(r.pi), o.mu, r);
    r.seconds = seconds_since(t0);
    return r;
  }
  SparseMilp milp(data, o, F);
  std::optional<Eigen::VectorXd> start;
  if (o.start.size() > 0) start = milp.start_point(data, o, F);
  const MilpSolution s = milp.lp.solve_milp(o.milp, start);
  if (s.status == MilpStatus::infeasible)
    throw NumericalError("sparse_bound: the MILP is infeasible: eps is below what any perturbation inside max_abs "
                         "can reach (use eps from linf_bound and a larger max_abs)");
  if (s.status == MilpStatus::no_solution)
    throw NumericalError("sparse_bound: no integer solution within the time limit (" +
                         std::to_string(o.milp.time_limit_s) + " s) or node limit; give a start trajectory or more time");
  TvBoundResult r;
  r.status = s.status;
  r.objective = s.objective;
  r.best_bound = s.best_bound;
  r.gap = s.gap;
  r.nodes = s.nodes;
  r.epsilon = o.epsilon;
  fill_result(data, s.x.head(static_cast<Eigen::Index>(N) * q), o.mu, r);
  r.seconds = seconds_since(t0);
  return r;
}

Eigen::VectorXd rms_tracking_error(const Eigen::Ref<const Eigen::MatrixXd>& estimate, const Eigen::Ref<const Eigen::MatrixXd>& truth) {
  if (estimate.rows() != truth.rows() || estimate.cols() != truth.cols() || estimate.rows() == 0)
    throw InputError("rms_tracking_error: estimate and truth differ in size or are empty");
  return ((estimate - truth).array().square().colwise().sum() / static_cast<double>(truth.rows())).sqrt().transpose();
}

}  // namespace sets
