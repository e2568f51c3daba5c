#include "sets/numeric/dense_lp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "sets/core/error.hpp"

namespace sets {

namespace {

constexpr int kNone = std::numeric_limits<int>::min();
// Relative tolerances. They decide only how close to optimal the multipliers are: the bound
// the caller reports is computed from them in directed rounding, whatever they are.
constexpr double kPrimalTol = 1e-9;   // a constraint violated by less is satisfied
constexpr double kDualTol = 1e-11;    // a multiplier of the wrong sign by less is zero
constexpr double kPivotTol = 1e-9;    // smaller pivots are not taken (relative to the rows' norms)
constexpr double kMinRcond = 1e-13;   // a basis worse conditioned than this is not trusted

}  // namespace

DenseLp::DenseLp(int num_variables) : n_(num_variables) {
  if (num_variables <= 0) throw InputError("DenseLp: need at least one variable");
  col_lo_.setConstant(n_, -inf);
  col_hi_.setConstant(n_, inf);
  c_.setZero(n_);
  col_in_.assign(static_cast<std::size_t>(n_), 0);
  A_.resize(0, n_);  // 0 x n, not 0 x 0: A^T y and A x must have n columns before the first row
}

void DenseLp::add_row(const Eigen::Ref<const Eigen::VectorXd>& a, double lo, double hi) {
  if (a.size() != n_)
    throw InputError("DenseLp::add_row: " + std::to_string(a.size()) + " coefficients for " + std::to_string(n_) +
                     " variables");
  if (!a.allFinite() || std::isnan(lo) || std::isnan(hi) || lo > hi || lo == inf || hi == -inf)
    throw InputError("DenseLp::add_row: coefficients must be finite and lo <= hi");
  if (m_ == A_.rows()) {  // grow geometrically: row generation adds rows one batch at a time
    const Eigen::Index capacity = std::max<Eigen::Index>(16, 2 * m_);
    A_.conservativeResize(capacity, n_);
    lo_.conservativeResize(capacity);
    hi_.conservativeResize(capacity);
    norm_.conservativeResize(capacity);
  }
  A_.row(m_) = a.transpose();
  lo_[m_] = lo;
  hi_[m_] = hi;
  norm_[m_] = a.norm();
  row_in_.push_back(0);
  ++m_;
}

void DenseLp::set_variable_bounds(int j, double lo, double hi) {
  if (j < 0 || j >= n_) throw InputError("DenseLp::set_variable_bounds: variable index out of range");
  if (std::isnan(lo) || std::isnan(hi) || lo > hi || lo == inf || hi == -inf)
    throw InputError("DenseLp::set_variable_bounds: need lo <= hi");
  col_lo_[j] = lo;
  col_hi_[j] = hi;
}

void DenseLp::set_objective(const Eigen::Ref<const Eigen::VectorXd>& c, Sense sense) {
  if (c.size() != n_ || !c.allFinite()) throw InputError("DenseLp::set_objective: need n finite costs");
  c_ = c;
  sense_ = sense;
}

// ---------------------------------------------------------------- constraints

// ---------------------------------------------------------------- the simplex

// Every column at the bound its cost pushes it to: dual feasible for any cost. An infinite
// bound is held at a far finite value ("artificial") until the simplex moves off it.
void DenseLp::cold_start(const Eigen::VectorXd& g) {
  std::fill(row_in_.begin(), row_in_.end(), 0);
  basis_.assign(static_cast<std::size_t>(n_), 0);
  side_.assign(static_cast<std::size_t>(n_), 1);
  artificial_.assign(static_cast<std::size_t>(n_), 0);
  for (int j = 0; j < n_; ++j) {
    const bool at_lower = g[j] > 0 || (g[j] == 0 && (std::isfinite(col_lo_[j]) || !std::isfinite(col_hi_[j])));
    const auto i = static_cast<std::size_t>(j);
    basis_[i] = -1 - j;
    side_[i] = at_lower ? 1 : -1;
    artificial_[i] = !std::isfinite(at_lower ? col_lo_[j] : col_hi_[j]);
    col_in_[i] = 1;
  }
}

bool DenseLp::factorise() {
  B_.resize(n_, n_);
  rhs_.resize(n_);
  for (int i = 0; i < n_; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const int k = basis_[u];
    if (k >= 0) {
      B_.row(i) = A_.row(k);
    } else {
      B_.row(i).setZero();
      B_(i, -1 - k) = 1;
    }
    rhs_[i] = artificial_[u] ? (side_[u] > 0 ? -artificial_far_ : artificial_far_)
                             : (side_[u] > 0 ? lower(k) : upper(k));
  }
  lu_.compute(B_);
  Binv_ = lu_.inverse();
  const auto norm1 = [](const Eigen::MatrixXd& M) { return M.cwiseAbs().colwise().sum().maxCoeff(); };
  if (!(1 / (norm1(B_) * norm1(Binv_)) > kMinRcond)) return false;  // NaN (singular) fails too
  x_.noalias() = Binv_ * rhs_;
  mu_.noalias() = Binv_.transpose() * g_;
  return x_.allFinite() && mu_.allFinite();
}

// The non-basic constraint that x violates most (violation over the row's norm: the distance
// to its hyperplane); `side` +1 if x is below its lower bound, -1 if above its upper one.
int DenseLp::most_violated(const Eigen::VectorXd& x, int& side) const {
  const double xscale = std::max(1.0, x.lpNorm<Eigen::Infinity>());
  int best = kNone;
  double best_score = 0;
  const auto consider = [&](int k, double v, double lo, double hi, double nk) {
    const double below = lo - v, above = v - hi;
    const double viol = std::max(below, above);
    const double tol = kPrimalTol * std::max({1.0, std::abs(below > above ? lo : hi), nk * xscale});
    if (viol <= tol) return;
    const double score = nk > 0 ? viol / nk : viol;
    if (score > best_score) {
      best_score = score;
      best = k;
      side = below > above ? 1 : -1;
    }
  };
  // Most rows hold with room to spare: test that first, on the raw arrays.
  const double *ax = ax_.data(), *lo = lo_.data(), *hi = hi_.data(), *nrm = norm_.data();
  for (int r = 0; r < m_; ++r)
    if ((ax[r] < lo[r] || ax[r] > hi[r]) && !row_in_[static_cast<std::size_t>(r)])
      consider(r, ax[r], lo[r], hi[r], nrm[r]);
  for (int j = 0; j < n_; ++j)
    if ((x[j] < col_lo_[j] || x[j] > col_hi_[j]) && !col_in_[static_cast<std::size_t>(j)])
      consider(-1 - j, x[j], col_lo_[j], col_hi_[j], 1.0);
  return best;
}

// Constraint q enters at the side it is violated on; the basic constraint whose multiplier
// reaches zero first leaves (Harris' two passes: the largest pivot among the nearly first).
bool DenseLp::dual_step(int q, int side) {
  if (q >= 0) {
    aq_ = A_.row(q).transpose();
  } else {
    aq_.setZero(n_);
    aq_[-1 - q] = 1;
  }
  u_.noalias() = Binv_.transpose() * aq_;  // a_q = B^T u
  const Eigen::VectorXd& u = u_;
  const double nq = norm(q), gscale = std::max(g_.lpNorm<Eigen::Infinity>(), 1e-300);
  // Multiplier i moves as mu_i - t * side * u_i and must keep the sign of its side.
  const auto rate = [&](int i) {
    const auto u_i = static_cast<std::size_t>(i);
    const int k = basis_[u_i];
    if (!artificial_[u_i] && lower(k) == upper(k)) return 0.0;  // equality: free multiplier
    const double r = side * side_[u_i] * u[i];
    return std::abs(u[i]) * norm(k) > kPivotTol * nq ? r : 0.0;
  };
  double tmax = inf;
  for (int i = 0; i < n_; ++i) {
    const double r = rate(i);
    if (r <= 0) continue;
    const double tol = kDualTol * gscale / norm(basis_[static_cast<std::size_t>(i)]);
    tmax = std::min(tmax, (std::max(side_[static_cast<std::size_t>(i)] * mu_[i], 0.0) + tol) / r);
  }
  if (tmax == inf) return false;  // the dual is unbounded: the rows are infeasible
  int leave = -1;
  double best = 0;
  for (int i = 0; i < n_; ++i) {
    const double r = rate(i);
    if (r <= 0 || std::max(side_[static_cast<std::size_t>(i)] * mu_[i], 0.0) / r > tmax) continue;
    const double size = r * norm(basis_[static_cast<std::size_t>(i)]);
    if (size > best) {
      best = size;
      leave = i;
    }
  }
  if (leave < 0) return false;
  const auto l = static_cast<std::size_t>(leave);
  set_in_basis(basis_[l], false);
  basis_[l] = q;
  side_[l] = static_cast<signed char>(side);
  artificial_[l] = 0;
  set_in_basis(q, true);
  return true;
}

// From a feasible vertex, basic constraint r is released in `direction` (+1: its value grows)
// and the first constraint met becomes active (Harris' two passes); r may flip to its other
// bound. False: nothing blocks (the LP is unbounded).
bool DenseLp::primal_step(int r, int direction) {
  d_ = direction * Binv_.col(r);  // B d = direction e_r
  ad_.noalias() = A_.topRows(m_) * d_;
  const double dscale = d_.lpNorm<Eigen::Infinity>(), xscale = std::max(1.0, x_.lpNorm<Eigen::Infinity>());
  const auto ur = static_cast<std::size_t>(r);
  const int k_r = basis_[ur];
  // r may reach its other bound (an artificial one: its finite bound, if any).
  const double other = direction > 0 ? upper(k_r) : lower(k_r);
  const bool may_flip = std::isfinite(other);
  const double flip_step = may_flip ? std::abs(other - rhs_[r]) : inf;
  // Pass 1: tmax, the shortest step to a bound with (Harris') tolerance. Every constraint whose
  // exact step may still be <= tmax is kept for pass 2 (tmax only shrinks, and the exact step
  // is never longer than the tolerant one, so nothing pass 2 needs is dropped).
  double tmax = inf;
  blocking_.clear();
  const auto visit = [&](int k, double v, double rk, double lo, double hi, double nk) {
    if (std::abs(rk) <= kPivotTol * nk * dscale) return;  // moves (nearly) parallel: never met
    const double bound = rk > 0 ? hi : lo;
    if (!std::isfinite(bound)) return;
    const double exact = std::max(0.0, (bound - v) / rk);
    if (exact > tmax) return;
    const double tol = kPrimalTol * std::max({1.0, std::abs(bound), nk * xscale});
    tmax = std::min(tmax, std::max(0.0, (bound - v + (rk > 0 ? tol : -tol)) / rk));
    blocking_.push_back({k, exact, std::abs(rk) / std::max(nk, 1e-300), static_cast<signed char>(rk > 0 ? -1 : 1)});
  };
  const double *ax = ax_.data(), *ad = ad_.data(), *lo = lo_.data(), *hi = hi_.data(), *nrm = norm_.data();
  for (int k = 0; k < m_; ++k)
    if (!row_in_[static_cast<std::size_t>(k)]) visit(k, ax[k], ad[k], lo[k], hi[k], nrm[k]);
  for (int j = 0; j < n_; ++j)
    if (!col_in_[static_cast<std::size_t>(j)]) visit(-1 - j, x_[j], d_[j], col_lo_[j], col_hi_[j], 1.0);
  // r reaches its other bound before (or within the tolerance of) any other constraint: a flip.
  if (may_flip && flip_step <= tmax) {
    side_[ur] = static_cast<signed char>(direction > 0 ? -1 : 1);
    artificial_[ur] = 0;
    return true;
  }
  if (tmax == inf) return false;
  // Pass 2: among the constraints met within tmax, the largest pivot.
  int enter = kNone, enter_side = 1;
  double best = 0;
  for (const Blocking& c : blocking_) {
    if (c.step > tmax || !(c.size > best)) continue;
    best = c.size;
    enter = c.k;
    enter_side = c.side;
  }
  if (enter == kNone) return false;
  set_in_basis(k_r, false);
  basis_[ur] = enter;
  side_[ur] = static_cast<signed char>(enter_side);
  artificial_[ur] = 0;
  set_in_basis(enter, true);
  return true;
}

LpSolution DenseLp::make_solution(LpStatus status) const {
  LpSolution s;
  s.status = status;
  s.sense = sense_;
  s.iterations = iterations_;
  s.x = x_;
  s.objective = c_.dot(x_);
  // GLPK's convention: c = A^T y + d for both senses (mu belongs to the minimisation of g).
  s.row_dual = Eigen::VectorXd::Zero(m_);
  const double sign = sense_ == Sense::minimize ? 1.0 : -1.0;
  for (int i = 0; i < n_; ++i)
    if (basis_[static_cast<std::size_t>(i)] >= 0) s.row_dual[basis_[static_cast<std::size_t>(i)]] = sign * mu_[i];
  s.reduced_cost = c_;  // c - A^T y, y nonzero only on the basic rows
  for (int i = 0; i < n_; ++i) {
    const int k = basis_[static_cast<std::size_t>(i)];
    if (k >= 0) s.reduced_cost -= s.row_dual[k] * A_.row(k).transpose();
  }
  return s;
}

std::optional<LpSolution> DenseLp::solve() {
  g_ = sense_ == Sense::minimize ? c_ : Eigen::VectorXd(-c_);
  // Far enough to lie beyond the data's own scale (the rows' distances from the origin).
  double scale = 1;
  for (int r = 0; r < m_; ++r)
    if (norm_[r] > 0)
      for (double b : {lo_[r], hi_[r]})
        if (std::isfinite(b)) scale = std::max(scale, std::abs(b) / norm_[r]);
  for (int j = 0; j < n_; ++j)
    for (double b : {col_lo_[j], col_hi_[j]})
      if (std::isfinite(b)) scale = std::max(scale, std::abs(b));
  artificial_far_ = 1e3 * scale;

  bool restarted = basis_.empty();
  if (restarted) cold_start(g_);
  for (int i = 0; i < n_; ++i) {  // bounds may have changed since the last solve
    const auto u = static_cast<std::size_t>(i);
    const int k = basis_[u];
    const bool finite = std::isfinite(side_[u] > 0 ? lower(k) : upper(k));
    if (k >= 0 && !finite) {
      cold_start(g_);
      restarted = true;
      break;
    }
    if (k < 0) artificial_[u] = !finite;
  }

  iterations_ = 0;
  const int limit = 100 + 20 * (n_ + m_);
  for (; iterations_ < limit; ++iterations_) {
    if (!factorise()) {
      if (restarted) return std::nullopt;
      cold_start(g_);
      restarted = true;
      continue;
    }
    ax_.noalias() = A_.topRows(m_) * x_;
    // The basic constraint whose multiplier has the wrong sign by most (scaled to the cost).
    const double gscale = std::max(g_.lpNorm<Eigen::Infinity>(), 1e-300);
    int wrong = -1, artificial = -1;
    double worst = 0;
    for (int i = 0; i < n_; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const int k = basis_[u];
      const double tol = kDualTol * gscale / norm(k);
      if (artificial_[u] && std::abs(mu_[i]) > tol) artificial = i;
      if (!artificial_[u] && lower(k) == upper(k)) continue;
      const double v = side_[u] * mu_[i];
      if (v < -tol && -v * norm(k) > worst) {
        worst = -v * norm(k);
        wrong = i;
      }
    }
    int side = 0;
    const int q = most_violated(x_, side);
    if (wrong < 0) {  // dual feasible: dual simplex
      if (q != kNone) {
        if (!dual_step(q, side)) return make_solution(LpStatus::infeasible);
        continue;
      }
      if (artificial < 0) return make_solution(LpStatus::optimal);
      // Optimal only in the artificial box: move off the far bound.
      if (!primal_step(artificial, mu_[artificial] > 0 ? -1 : 1)) return make_solution(LpStatus::unbounded);
      continue;
    }
    if (q == kNone) {  // a feasible vertex: primal simplex
      const int r = artificial >= 0 ? artificial : wrong;
      const int direction = artificial >= 0 ? (mu_[r] > 0 ? -1 : 1) : side_[static_cast<std::size_t>(r)];
      if (!primal_step(r, direction)) return make_solution(LpStatus::unbounded);
      continue;
    }
    // Neither primal nor dual feasible (a new objective and new rows at once): start again
    // from the column bounds, which are dual feasible.
    if (restarted) return std::nullopt;
    cold_start(g_);
    restarted = true;
  }
  return std::nullopt;
}

}  // namespace sets
