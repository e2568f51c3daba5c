// Branch and bound over jump patterns for the sparse-derivative problem (14).
//
// A solution of (14) is a trajectory Pi; its jumps are the (sample, parameter) pairs where
// |Delta pi_i(k)| > mu_i, and its objective is (number of jumps) + max F_i |pi_i(k)|. Sort the
// solutions by the signs of their jumps in time intervals: on an interval, a parameter has no
// jump (none), only upward jumps (up: Delta pi >= -mu everywhere, at least one jump), only
// downward ones (down) or both (mixed: at least two jumps). A *pattern* gives each parameter a
// partition of the jump positions into intervals with one of these states; every solution lies
// in exactly one pattern of any given partition. The LP of a pattern (the threshold rows turned
// into the monotone rows of its states, the window-norm ball, min peak) is a relaxation of all
// solutions in it, so  (jumps the states imply) + LP  bounds them from below. Splitting an interval
// into halves partitions its solutions by the states of the halves (up -> (up, none), (none, up),
// (up, up); mixed -> the nine pairs whose union is mixed), and a pattern of single positions is
// exact. Monotonicity is what makes the bound strong: a relaxation that lets an interval vary
// freely (big-M with delta in [0, 1], or "one indicator per block") fits the data with
// oscillations inside it for almost no cost.
//
// Bounds are certified: the LP carries an elastic variable on the noise bound (eps_j + s_j with
// s_j penalised), so it is always feasible and its Neumaier-Shcherbina safe bound is a rigorous
// lower bound on the pattern's optimum whether or not the pattern is feasible; infeasible patterns
// get a large bound from the penalty and are pruned. A node is fathomed when its LP point has no
// more jumps than its states imply (the LP point is then optimal in the node) or its bound reaches
// the incumbent. Incumbents come from those LP points and from rounding each node's LP point to
// one jump per up/down interval (two per mixed one).

#include "methods/tv_bound/jump_search.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <queue>
#include <string>
#include <vector>

#include "sets/core/error.hpp"
#include "sets/numeric/interval.hpp"

namespace sets::detail {

namespace {

using Clock = std::chrono::steady_clock;

enum class State : std::uint8_t { none, up, down, mixed };

int least_jumps(State s) { return s == State::mixed ? 2 : (s == State::none ? 0 : 1); }

State unite(State a, State b) {
  if (a == State::none) return b;
  if (b == State::none) return a;
  return a == b && a != State::mixed ? a : State::mixed;
}

struct Span {
  int first = 0, last = 0;  // position indices [first, last)
  int param = 0;
  State state = State::none;
};

struct Node {
  std::vector<Span> intervals;
  int jumps = 0;       // every solution in the node has at least this many jumps
  double bound = 0;    // certified lower bound of the objective over the node
  int split = -1;      // interval to split next and the position where its right half starts
  int split_at = -1;
  std::vector<Span> rounding;  // the LP point rounded to one jump per up/down interval
  LpBasis basis;                // the optimal basis of its LP: its children start from it
  long id = 0;
};

struct Worse {
  bool operator()(const Node& a, const Node& b) const {
    if (a.bound != b.bound) return a.bound > b.bound;
    return a.id < b.id;  // equal bounds: the newer (more refined) node first
  }
};

// True if the regression carries the state recursion behind Xi and it reproduces Xi (to rounding).
bool recursion_reproduces_xi(const BiaffineRegression& reg) {
  const int N = reg.samples();
  if (reg.transition.size() != static_cast<std::size_t>(N) || reg.input_map.size() != static_cast<std::size_t>(N) ||
      reg.output_map.size() == 0 || N <= 0)
    return false;
  const Eigen::Index n = reg.output_map.cols(), l = reg.output_map.rows(), q = reg.xi.cols() / N;
  if (reg.xi.rows() != (N + 1) * l) return false;
  for (int k = 0; k < N; ++k) {
    const auto& A = reg.transition[static_cast<std::size_t>(k)];
    const auto& M = reg.input_map[static_cast<std::size_t>(k)];
    if (A.rows() != n || A.cols() != n || M.rows() != n || M.cols() != q || !A.allFinite() || !M.allFinite()) return false;
  }
  const double scale = std::max(reg.xi.cwiseAbs().maxCoeff(), 1e-300);
  for (int j = 0; j < N; ++j) {
    Eigen::MatrixXd G = reg.input_map[static_cast<std::size_t>(j)];
    for (int k = j + 1; k <= N; ++k) {
      const Eigen::MatrixXd block = reg.output_map * G;
      if ((block - reg.xi.block(k * l, j * q, l, q)).cwiseAbs().maxCoeff() > 1e-9 * scale) return false;
      if (k < N) G = reg.transition[static_cast<std::size_t>(k)] * G;
    }
  }
  return true;
}

// The LP of a pattern over the regression Y = Upsilon + Xi Pi + V:
//   min t + sum_j c_j e_j
//   s.t. -t <= F_i pi_i(k) <= t,  0 <= t <= cap,  |pi_i| <= max_abs_i
//        Delta pi_i(k) in [-mu_i, mu_i] (none) / [-mu_i, inf) (up) / (-inf, mu_i] (down) / free
//        T >= |Y - Upsilon - Xi Pi|,  W T <= e,  eps_j <= e_j <= eps_j + s_max_j
// Every column has finite bounds (T and e by bounds that no optimal point needs to exceed), so
// the safe bound never degenerates to -inf.
class PatternLp {
 public:
  PatternLp(const TvBoundData& data, const SparseBoundOptions& o, const Eigen::VectorXd& eps,
            std::vector<int> positions)
      : N_(data.samples()), q_(data.parameters()), l_(data.outputs()), positions_(std::move(positions)),
        mu_(o.mu), eps_(eps), lp_(N_ * q_) {
    const Eigen::VectorXd F = o.F.size() ? o.F : Eigen::VectorXd::Ones(q_);
    F_ = F;
    for (int k = 0; k < N_; ++k)
      for (int i = 0; i < q_; ++i) lp_.set_variable_bounds(k * q_ + i, -o.max_abs[i], o.max_abs[i]);
    t_ = lp_.add_variables(1, 0, inf);
    for (int k = 0; k < N_; ++k)
      for (int i = 0; i < q_; ++i) {
        std::vector<std::pair<int, double>> row{{k * q_ + i, F[i]}, {t_, -1.0}};
        lp_.add_row(row, -inf, 0.0);
        row.back().second = 1.0;
        lp_.add_row(row, 0.0, inf);
      }
    const int k0 = o.initial_difference ? 0 : 1;
    jump_row_.assign(static_cast<std::size_t>(N_ * q_), -1);
    for (int k = k0; k < N_; ++k)
      for (int i = 0; i < q_; ++i) {
        std::vector<std::pair<int, double>> row{{k * q_ + i, 1.0}};
        if (k > 0) row.emplace_back((k - 1) * q_ + i, -1.0);
        jump_row_[static_cast<std::size_t>(k * q_ + i)] = lp_.add_row(row, -mu_[i], mu_[i]);
      }
    const WindowNormBall ball = data.ball();
    const Eigen::VectorXd offset = stack_samples(data.y) - data.regression.upsilon;
    // The residual offset - Xi Pi, either through the state recursion behind Xi (sparse rows:
    // far cheaper simplex iterations) or through the dense Xi. t_max bounds |Xi Pi| per row.
    Eigen::VectorXd t_max;
    WindowNormBall::LpBlock blk;
    if (recursion_reproduces_xi(data.regression)) {
      const auto& reg = data.regression;
      const int n = static_cast<int>(reg.output_map.cols());
      const int first_s = lp_.num_variables();  // s(1..N), n each: s(k) at first_s + (k-1) n
      lp_.add_variables(N_ * n);
      Eigen::MatrixXd s_max = Eigen::MatrixXd::Zero(N_ + 1, n);
      for (int j = 0; j < N_; ++j) {
        Eigen::MatrixXd G = reg.input_map[static_cast<std::size_t>(j)];
        for (int k = j + 1; k <= N_; ++k) {
          s_max.row(k) += (G.cwiseAbs() * o.max_abs).transpose();
          if (k < N_) G = reg.transition[static_cast<std::size_t>(k)] * G;
        }
      }
      for (int k = 1; k <= N_; ++k)
        for (int a = 0; a < n; ++a) {
          const double b = s_max(k, a) * (1 + 1e-6) + 1e-300;  // margin for rounding in s_max
          lp_.set_variable_bounds(first_s + (k - 1) * n + a, -b, b);
        }
      for (int k = 0; k < N_; ++k) {  // s(k+1) - A(k) s(k) - M_k pi(k) = 0
        const Eigen::MatrixXd& A = reg.transition[static_cast<std::size_t>(k)];
        const Eigen::MatrixXd& M = reg.input_map[static_cast<std::size_t>(k)];
        for (int a = 0; a < n; ++a) {
          std::vector<std::pair<int, double>> row{{first_s + k * n + a, 1.0}};
          if (k > 0)
            for (int b = 0; b < n; ++b)
              if (A(a, b) != 0) row.emplace_back(first_s + (k - 1) * n + b, -A(a, b));
          for (int i = 0; i < q_; ++i)
            if (M(a, i) != 0) row.emplace_back(k * q_ + i, -M(a, i));
          lp_.add_row(row, 0.0, 0.0);
        }
      }
      Eigen::MatrixXd map = Eigen::MatrixXd::Zero(offset.size(), static_cast<Eigen::Index>(N_) * n);
      t_max = offset.cwiseAbs();
      for (int k = 1; k <= N_; ++k) {
        map.block(static_cast<Eigen::Index>(k) * l_, static_cast<Eigen::Index>(k - 1) * n, l_, n) = reg.output_map;
        t_max.segment(static_cast<Eigen::Index>(k) * l_, l_) += reg.output_map.cwiseAbs() * s_max.row(k).transpose();
      }
      blk = ball.add_to(lp_, offset, map, first_s);
    } else {
      blk = ball.add_to(lp_, offset, data.regression.xi, 0);
      t_max = offset.cwiseAbs() + data.regression.xi.cwiseAbs() * o.max_abs.replicate(N_, 1);
    }
    // Bounds no optimal point needs to exceed: T <= t_max, then e <= W t_max.
    for (Eigen::Index r = 0; r < t_max.size(); ++r)
      lp_.set_variable_bounds(blk.first_t + static_cast<int>(r), 0, t_max[r] * (1 + 1e-6) + 1e-300);
    first_e_ = blk.first_eps;
    penalty_.resize(l_);
    for (int j = 0; j < l_; ++j) {
      Eigen::VectorXd tj(N_ + 1);
      for (int k = 0; k <= N_; ++k) tj[k] = t_max[static_cast<Eigen::Index>(k) * l_ + j];
      const double e_max = std::max(ball.windows()[static_cast<std::size_t>(j)](tj), eps_[j]);
      lp_.set_variable_bounds(first_e_ + j, eps_[j], e_max * (1 + 1e-9) + 1e-300);
      // A violation of the noise bound by 0.1 % costs 1: infeasible patterns get large bounds.
      const double scale = std::max(eps_[j], 1e-9 * std::max(offset.cwiseAbs().maxCoeff(), 1e-300));
      penalty_[j] = 1e3 / scale;
    }
    set_penalty(1);
  }

  int positions() const { return static_cast<int>(positions_.size()); }
  int sample(int p) const { return positions_[static_cast<std::size_t>(p)]; }

  struct Solution {
    double peak_bound = -inf;  // certified lower bound on the peak term over the pattern
    bool feasible = false;     // the LP point keeps the noise bound: pi solves (14)'s constraints
    Eigen::MatrixXd pi;        // N x q
  };

  // `stop_above`: the caller drops the pattern if its peak bound reaches this, so the dual simplex
  // may stop there (inf = solve to the end).
  Solution solve(const std::vector<Span>& intervals, double cap, double stop_above = inf, double penalty_scale = 1) {
    for (int r : touched_) {
      const int i = row_param_[static_cast<std::size_t>(r)];
      lp_.set_row_bounds(r, -mu_[i], mu_[i]);
    }
    touched_.clear();
    for (const Span& iv : intervals)
      for (int p = iv.first; p < iv.last; ++p) {
        const int r = jump_row_[static_cast<std::size_t>(sample(p) * q_ + iv.param)];
        const double m = mu_[iv.param];
        switch (iv.state) {
          case State::none: continue;
          case State::up: lp_.set_row_bounds(r, -m, inf); break;
          case State::down: lp_.set_row_bounds(r, -inf, m); break;
          case State::mixed: lp_.set_row_bounds(r, -inf, inf); break;
        }
        remember(r, iv.param);
      }
    lp_.set_variable_bounds(t_, 0, std::max(cap, 0.0));
    if (penalty_scale != scale_) set_penalty(penalty_scale);
    if (std::getenv("SETS_JS_COLD")) lp_.reset_basis();
    const auto tA = Clock::now();
    LpSolveOptions opt;
    opt.long_step = true;
    if (std::isfinite(stop_above)) {
      double shift = 0;  // the objective carries sum_j c_j eps_j on top of the peak
      for (int j = 0; j < l_; ++j) shift += lp_.objective()[first_e_ + j] * eps_[j];
      opt.cutoff = (stop_above + shift) * (1 + 1e-9) + 1e-9;
    }
    LpSolution s = lp_.solve(opt);
    if (s.status == LpStatus::cutoff) {
      ++solves_;
      Solution out;
      out.peak_bound = peak_bound(s);
      if (std::getenv("SETS_JS_DEBUG"))
        std::fprintf(stderr, "lp %ld n %zu it %d solve %.1f ms cutoff\n", solves_, intervals.size(), s.iterations,
                     std::chrono::duration<double, std::milli>(Clock::now() - tA).count());
      if (out.peak_bound >= stop_above) return out;
      opt.cutoff.reset();
      s = lp_.solve(opt);  // rounding left the bound just short: finish the solve
    }
    const auto tB = Clock::now();
    if (s.status != LpStatus::optimal)
      throw NumericalError(std::string("sparse_bound (jump search): the elastic LP of a pattern is ") +
                           to_string(s.status) + " (it is feasible and bounded by construction)");
    ++solves_;
    Solution out;
    out.peak_bound = peak_bound(s);
    if (std::getenv("SETS_JS_DEBUG"))
      std::fprintf(stderr, "lp %ld n %zu it %d solve %.1f ms safe %.1f ms obj %.4f\n", solves_, intervals.size(), s.iterations,
                   std::chrono::duration<double, std::milli>(tB - tA).count(),
                   std::chrono::duration<double, std::milli>(Clock::now() - tB).count(), s.objective);
    out.feasible = true;
    for (int j = 0; j < l_; ++j)
      if (s.x[first_e_ + j] > eps_[j]) out.feasible = false;
    out.pi = unstack_samples(s.x.head(static_cast<Eigen::Index>(N_) * q_), q_);
    return out;
  }

  long solves() const { return solves_; }
  // Certified lower bound on the peak term: the safe bound minus the constant sum_j c_j eps_j.
  double peak_bound(const LpSolution& s) const {
    Interval bound(lp_.safe_bound(s));
    for (int j = 0; j < l_; ++j) bound -= Interval(lp_.objective()[first_e_ + j]) * Interval(eps_[j]);
    return bound.lower();
  }
  LpBasis basis() const { return lp_.basis(); }
  void restore(const LpBasis& b) { lp_.set_basis(b); }

 private:
  void remember(int r, int param) {
    if (row_param_.size() <= static_cast<std::size_t>(r)) row_param_.resize(static_cast<std::size_t>(r) + 1, 0);
    row_param_[static_cast<std::size_t>(r)] = param;
    touched_.push_back(r);
  }
  void set_penalty(double scale) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(lp_.num_variables());
    c[t_] = 1;
    for (int j = 0; j < l_; ++j) c[first_e_ + j] = penalty_[j] * scale;
    lp_.set_objective(c, Sense::minimize);
    scale_ = scale;
  }

  int N_, q_, l_;
  std::vector<int> positions_;
  Eigen::VectorXd mu_, eps_, F_, penalty_;
  LinearProgram lp_;
  int t_ = -1, first_e_ = -1;
  std::vector<int> jump_row_, touched_, row_param_;
  double scale_ = 0;
  long solves_ = 0;
};

class Search {
 public:
  Search(const TvBoundData& data, const SparseBoundOptions& o, const Eigen::VectorXd& eps)
      : data_(data), o_(o), eps_(eps), N_(data.samples()), q_(data.parameters()),
        F_(o.F.size() ? o.F : Eigen::VectorXd::Ones(q_)), positions_(grid_positions()), lp_(data, o, eps, positions_),
        t0_(Clock::now()) {
    peak_cap_ = (F_.cwiseProduct(o.max_abs)).maxCoeff();
    gap_ = std::max(o.milp.relative_gap, 0.0);
  }

  TvBoundResult run() {
    offer_start();
    if (std::isfinite(best_)) drop_jumps();  // a start with a removable jump: cheaper at once
    roots();
    while (!open_.empty() && !out_of_budget()) {
      if (best_ < searched_) drop_jumps();  // a new incumbent: try to drop its jumps
      if (prunable(open_.top().bound)) break;
      report_progress();
      Node n = open_.top();
      open_.pop();
      lp_.restore(n.basis);
      branch(n);
      if (!n.rounding.empty()) try_rounding(n.rounding, n.jumps);
    }
    return result();
  }

 private:
  std::vector<int> grid_positions() const {
    std::vector<int> p;
    const int k0 = o_.initial_difference ? 0 : 1, g = std::max(o_.grid, 1);
    for (int k = k0; k < N_; ++k)
      if (k % g == 0) p.push_back(k);
    return p;
  }

  bool out_of_budget() const {
    if (o_.milp.node_limit > 0 && lp_.solves() >= o_.milp.node_limit) return true;
    return std::chrono::duration<double>(Clock::now() - t0_).count() >= o_.milp.time_limit_s;
  }

  // Nodes whose bound reaches this cannot improve the incumbent by more than the gap.
  double prune_level() const {
    if (!std::isfinite(best_)) return inf;
    return best_ - gap_ * std::max(1.0, std::abs(best_));
  }
  // True if a node of this bound may be dropped; remembers the bounds dropped below the incumbent
  // (by the gap tolerance) because they still count in the final lower bound.
  bool prunable(double bound) {
    if (bound < prune_level()) return false;
    if (bound < best_) pruned_ = std::min(pruned_, bound);
    return true;
  }

  // Objective of (14) at pi: jumps above the threshold plus the weighted peak.
  std::pair<int, double> objective(const Eigen::MatrixXd& pi) const {
    int jumps = 0;
    const int k0 = o_.initial_difference ? 0 : 1;
    for (int k = k0; k < N_; ++k)
      for (int i = 0; i < q_; ++i) {
        const double d = pi(k, i) - (k > 0 ? pi(k - 1, i) : 0.0);
        if (std::abs(d) > o_.mu[i] * (1 + 1e-6) + 1e-9) ++jumps;
      }
    return {jumps, (pi * F_.asDiagonal()).cwiseAbs().maxCoeff()};
  }

  // The jumps of pi as single-position spans; nullopt if one lies off the jump grid.
  std::optional<std::vector<Span>> jump_spans(const Eigen::MatrixXd& pi) const {
    std::vector<Span> out;
    const int k0 = o_.initial_difference ? 0 : 1;
    for (int k = k0; k < N_; ++k)
      for (int i = 0; i < q_; ++i) {
        const double d = pi(k, i) - (k > 0 ? pi(k - 1, i) : 0.0);
        if (std::abs(d) <= o_.mu[i] * (1 + 1e-6) + 1e-9) continue;
        const int p = position_of(k);
        if (p < 0) return std::nullopt;
        out.push_back({p, p + 1, i, d > 0 ? State::up : State::down});
      }
    return out;
  }

  int position_of(int k) const {
    const auto it = std::lower_bound(positions_.begin(), positions_.end(), k);
    return it != positions_.end() && *it == k ? static_cast<int>(it - positions_.begin()) : -1;
  }

  void offer(const Eigen::MatrixXd& pi) {
    const auto [jumps, peak] = objective(pi);
    if (jumps + peak < best_ && jump_spans(pi)) {  // a point with a jump off the grid is not a solution
      best_ = jumps + peak;
      best_pi_ = pi;
    }
  }

  // Local search on the incumbent's jumps (a dominance step: a pattern with one jump fewer is
  // cheaper whenever it stays feasible): drop one jump at a time, keep the first drop whose exact
  // pattern LP still keeps the noise bound, repeat. Each try is one warm-started LP.
  void drop_jumps() {
    const LpBasis saved = lp_.basis();
    for (bool improved = true; improved && !out_of_budget();) {
      improved = false;
      const auto spans = jump_spans(best_pi_);
      if (!spans || spans->size() > kMaxLocalJumps) break;
      for (std::size_t d = 0; d < spans->size() && !improved && !out_of_budget(); ++d) {
        std::vector<Span> rest;
        for (std::size_t j = 0; j < spans->size(); ++j)
          if (j != d) rest.push_back((*spans)[j]);
        const int jumps = static_cast<int>(rest.size());
        if (jumps >= prune_level()) continue;
        const double before = best_;
        const PatternLp::Solution s = lp_.solve(rest, std::min(peak_cap_, best_ - jumps), prune_level() - jumps);
        if (s.feasible) offer(s.pi);
        improved = best_ < before;
      }
    }
    lp_.restore(saved);
    searched_ = best_;
  }

  // The warm start, if it keeps the noise bound and the box.
  void offer_start() {
    if (o_.start.size() == 0) return;
    const Eigen::VectorXd v = stack_samples(data_.y) - data_.regression.upsilon - data_.regression.xi * stack_samples(o_.start);
    if (!data_.ball().contains(v, eps_)) return;
    for (int i = 0; i < q_; ++i)
      if (o_.start.col(i).cwiseAbs().maxCoeff() > o_.max_abs[i]) return;
    offer(o_.start);
  }

  void roots() {
    const int P = lp_.positions();
    std::vector<State> s(static_cast<std::size_t>(q_), State::none);
    const int combos = P == 0 ? 1 : static_cast<int>(std::pow(P >= 2 ? 4 : 3, q_));
    for (int c = 0; c < combos; ++c) {
      Node n;
      int code = c;
      for (int i = 0; i < q_; ++i) {
        const int base = P >= 2 ? 4 : 3;
        const auto st = static_cast<State>(code % base);
        code /= base;
        if (st != State::none) n.intervals.push_back({0, P, i, st});
      }
      evaluate(std::move(n));
    }
  }

  void branch(const Node& n) {
    const Span iv = n.intervals[static_cast<std::size_t>(n.split)];
    const int m = n.split_at;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const auto sa = static_cast<State>(a), sb = static_cast<State>(b);
        if (unite(sa, sb) != iv.state) continue;
        if ((sa == State::mixed && m - iv.first < 2) || (sb == State::mixed && iv.last - m < 2)) continue;
        Node c;
        c.intervals.reserve(n.intervals.size() + 1);
        for (std::size_t j = 0; j < n.intervals.size(); ++j)
          if (static_cast<int>(j) != n.split) c.intervals.push_back(n.intervals[j]);
        if (sa != State::none) c.intervals.push_back({iv.first, m, iv.param, sa});
        if (sb != State::none) c.intervals.push_back({m, iv.last, iv.param, sb});
        c.bound = n.bound;  // until its own LP says more
        evaluate(std::move(c));
      }
  }

  // Jumps of pi inside interval iv: (position index, Delta pi).
  std::vector<std::pair<int, double>> jumps_in(const Eigen::MatrixXd& pi, const Span& iv) const {
    std::vector<std::pair<int, double>> out;
    for (int p = iv.first; p < iv.last; ++p) {
      const int k = lp_.sample(p);
      const double d = pi(k, iv.param) - (k > 0 ? pi(k - 1, iv.param) : 0.0);
      if (std::abs(d) > o_.mu[iv.param] * (1 + 1e-6) + 1e-9) out.emplace_back(p, d);
    }
    return out;
  }

  void evaluate(Node n) {
    n.jumps = 0;
    for (const Span& iv : n.intervals) n.jumps += least_jumps(iv.state);
    n.bound = std::max(n.bound, static_cast<double>(n.jumps));
    if (prunable(n.bound)) return;
    if (out_of_budget()) {  // not evaluated: what it covers stays open at the bound it inherited
      unexplored_ = std::min(unexplored_, n.bound);
      return;
    }
    const double cap = std::isfinite(best_) ? std::min(peak_cap_, best_ - n.jumps) : peak_cap_;
    PatternLp::Solution s = lp_.solve(n.intervals, cap, prune_level() - n.jumps);
    n.bound = std::max(n.bound, n.jumps + std::max(s.peak_bound, 0.0));
    if (s.feasible) offer(s.pi);
    if (prunable(n.bound)) return;
    // Where the LP point has more jumps than the states imply, the relaxation is not exact.
    int worst = 0;
    bool single = true;
    n.rounding.clear();
    for (std::size_t j = 0; j < n.intervals.size(); ++j) {
      const Span& iv = n.intervals[j];
      const auto js = jumps_in(s.pi, iv);
      const int excess = static_cast<int>(js.size()) - least_jumps(iv.state);
      if (iv.last - iv.first > 1) single = false;
      if (excess > worst && iv.last - iv.first > 1) {
        worst = excess;
        n.split = static_cast<int>(j);
        n.split_at = std::clamp(js[1].first, iv.first + 1, iv.last - 1);  // between the first two jumps
      }
      add_rounding(n.rounding, iv, js);
    }
    if (s.feasible && worst == 0) return;  // the LP point is optimal in the node (and was offered)
    if (n.split < 0) {
      if (single) {  // exact pattern, but the LP used the elastic slack: make the penalty decisive
        resolve_leaf(n);
        return;
      }
      // Split the longest interval in the middle.
      int len = 0;
      for (std::size_t j = 0; j < n.intervals.size(); ++j) {
        const Span& iv = n.intervals[j];
        if (iv.last - iv.first > len) {
          len = iv.last - iv.first;
          n.split = static_cast<int>(j);
          n.split_at = iv.first + len / 2;
        }
      }
    }
    n.id = ++ids_;
    n.basis = lp_.basis();
    open_.push(std::move(n));
  }

  // One jump per up/down interval at the LP point's largest jump of that sign (two for mixed).
  void add_rounding(std::vector<Span>& r, const Span& iv, const std::vector<std::pair<int, double>>& js) const {
    if (iv.state == State::none) return;
    int up = -1, down = -1;
    double best_up = 0, best_down = 0;
    for (const auto& [p, d] : js) {
      if (d > best_up) best_up = d, up = p;
      if (d < best_down) best_down = d, down = p;
    }
    const bool want_up = iv.state == State::up || iv.state == State::mixed;
    const bool want_down = iv.state == State::down || iv.state == State::mixed;
    if (want_up && up < 0) up = iv.first;
    if (want_down && down < 0) down = iv.last - 1;
    if (want_up) r.push_back({up, up + 1, iv.param, State::up});
    if (want_down && down != up) r.push_back({down, down + 1, iv.param, State::down});
  }

  void try_rounding(const std::vector<Span>& pattern, int jumps) {
    if (jumps >= prune_level() || out_of_budget()) return;
    const double cap = std::isfinite(best_) ? std::min(peak_cap_, best_ - jumps) : peak_cap_;
    const PatternLp::Solution s = lp_.solve(pattern, cap, prune_level() - jumps);
    if (s.feasible) offer(s.pi);
  }

  // A pattern of single positions whose LP leaned on the elastic slack: raise the penalty until
  // the bound prunes it; if it never does, keep its bound as an unexplored part of the tree.
  void resolve_leaf(const Node& n) {
    double bound = n.bound;
    for (double scale : {1e3, 1e6}) {
      if (out_of_budget()) break;
      const double cap = std::isfinite(best_) ? std::min(peak_cap_, best_ - n.jumps) : peak_cap_;
      const PatternLp::Solution s = lp_.solve(n.intervals, cap, prune_level() - n.jumps, scale);
      bound = std::max(bound, n.jumps + std::max(s.peak_bound, 0.0));
      if (s.feasible) offer(s.pi);
      if (s.feasible || prunable(bound)) return;
    }
    unexplored_ = std::min(unexplored_, bound);
  }

  // With milp.verbose: one line every 2 s (LPs, open nodes, incumbent, lower bound).
  void report_progress() {
    if (!o_.milp.verbose) return;
    const double t = std::chrono::duration<double>(Clock::now() - t0_).count();
    if (t < next_report_) return;
    next_report_ = t + 2;
    const double lower = std::min({best_, unexplored_, pruned_, open_.empty() ? inf : open_.top().bound});
    std::fprintf(stderr, "jump search: %6.1f s  %6ld LPs  %6zu open  incumbent %.4f  bound %.4f\n", t, lp_.solves(),
                 open_.size(), best_, lower);
  }

  TvBoundResult result() {
    TvBoundResult r;
    double lower = std::min({best_, unexplored_, pruned_});
    if (!open_.empty()) lower = std::min(lower, open_.top().bound);
    if (!std::isfinite(best_)) {
      if (open_.empty() && !std::isfinite(unexplored_))
        throw NumericalError("sparse_bound: no trajectory inside max_abs keeps the residual within eps "
                             "(use eps from linf_bound and a larger max_abs)");
      throw NumericalError("sparse_bound: no solution found within the node or time limit (" +
                           std::to_string(lp_.solves()) + " LPs); raise the limits or give a start trajectory");
    }
    r.objective = best_;
    r.best_bound = std::min(lower, best_);
    r.gap = std::abs(best_ - r.best_bound) / std::max(1.0, std::abs(best_));
    r.status = r.gap <= gap_ ? MilpStatus::optimal : MilpStatus::feasible;
    r.nodes = lp_.solves();
    r.pi = best_pi_;
    return r;
  }

  const TvBoundData& data_;
  const SparseBoundOptions& o_;
  Eigen::VectorXd eps_;
  int N_, q_;
  Eigen::VectorXd F_;
  std::vector<int> positions_;  // the samples where a jump may occur (the jump grid)
  PatternLp lp_;
  Clock::time_point t0_;
  double peak_cap_ = inf, gap_ = 0;
  double best_ = inf, unexplored_ = inf, pruned_ = inf, next_report_ = 0;
  double searched_ = inf;  // the incumbent value drop_jumps last started from
  // The local search costs one LP per jump and round: only for incumbents with few jumps.
  static constexpr std::size_t kMaxLocalJumps = 24;
  Eigen::MatrixXd best_pi_;
  std::priority_queue<Node, std::vector<Node>, Worse> open_;
  long ids_ = 0;
};

}  // namespace

TvBoundResult jump_search(const TvBoundData& data, const SparseBoundOptions& options) {
  const Eigen::VectorXd eps = options.epsilon * (1 + options.epsilon_slack);
  Search search(data, options, eps);
  return search.run();
}

}  // namespace sets::detail
