#include "sets/numeric/lp_certificate.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>

#include "sets/core/error.hpp"
#include "sets/numeric/interval_matrix.hpp"
#include "numeric/exact_rational.hpp"

namespace sets {

namespace {

using detail::Rational;

// ---------------------------------------------------------------- Farkas certificates

// min over z in [lo, hi] of y z (exact); false if it is -inf.
bool row_term(const Rational& y, double lo, double hi, Rational& out) {
  if (sgn(y) == 0) {
    out = 0;
    return true;
  }
  const double b = sgn(y) > 0 ? lo : hi;
  if (!std::isfinite(b)) return false;
  out = y * Rational(b);
  return true;
}

// max over x in [lo, hi] of g x (exact); false if it is +inf.
bool col_term(const Rational& g, double lo, double hi, Rational& out) {
  if (sgn(g) == 0) {
    out = 0;
    return true;
  }
  const double b = sgn(g) > 0 ? hi : lo;
  if (!std::isfinite(b)) return false;
  out = g * Rational(b);
  return true;
}

class FarkasCheck {
 public:
  FarkasCheck(const LpRows& rows, const Eigen::Ref<const Eigen::VectorXd>& col_lo,
              const Eigen::Ref<const Eigen::VectorXd>& col_hi)
      : rows_(rows), col_lo_(col_lo), col_hi_(col_hi), n_(static_cast<int>(col_lo.size())) {}

  /// Proves min_z y^T z > max_x (A^T y)^T x for y as given (after cleaning and repair).
  bool oriented(const Eigen::Ref<const Eigen::VectorXd>& y_in) {
    if (!select_support(y_in)) return false;
    std::vector<int> forced;  // columns whose reduced cost must be exactly zero
    for (int round = 0; round <= 3; ++round) {
      const std::vector<Rational> g = reduced_costs();
      std::vector<int> bad;
      for (int j = 0; j < n_; ++j) {
        Rational t;
        if (!col_term(g[static_cast<std::size_t>(j)], col_lo_[j], col_hi_[j], t)) bad.push_back(j);
      }
      if (bad.empty()) return gap_is_positive(g);
      if (round == 3) return false;
      for (int j : bad)
        if (std::find(forced.begin(), forced.end(), j) == forced.end()) forced.push_back(j);
      if (!repair(forced, g)) return false;
    }
    return false;
  }

 private:
  // The rows that carry a usable multiplier; a row whose relevant side is infinite gets 0 (the
  // certificate holds for any y, and such a multiplier would only make the bound -inf).
  bool select_support(const Eigen::Ref<const Eigen::VectorXd>& y_in) {
    support_.clear();
    y_.clear();
    double ymax = 0;
    for (Eigen::Index i = 0; i < y_in.size(); ++i)
      if (std::isfinite(y_in[i])) ymax = std::max(ymax, std::abs(y_in[i]));
    if (!(ymax > 0)) return false;
    for (Eigen::Index i = 0; i < y_in.size(); ++i) {
      const double yi = y_in[i];
      const auto k = static_cast<std::size_t>(i);
      if (!std::isfinite(yi) || !(std::abs(yi) > 1e-14 * ymax)) continue;
      if ((yi > 0 && !std::isfinite(rows_.lo[k])) || (yi < 0 && !std::isfinite(rows_.hi[k]))) continue;
      support_.push_back(static_cast<int>(i));
      y_.emplace_back(yi);
    }
    return !support_.empty();
  }

  std::vector<Rational> reduced_costs() const {
    std::vector<Rational> g(static_cast<std::size_t>(n_), Rational(0));
    for (std::size_t s = 0; s < support_.size(); ++s)
      for (const auto& [j, a] : rows_.entries[static_cast<std::size_t>(support_[s])])
        g[static_cast<std::size_t>(j)] += y_[s] * Rational(a);
    return g;
  }

  bool gap_is_positive(const std::vector<Rational>& g) const {
    Rational low(0), high(0), t;
    for (std::size_t s = 0; s < support_.size(); ++s) {
      const auto i = static_cast<std::size_t>(support_[s]);
      if (!row_term(y_[s], rows_.lo[i], rows_.hi[i], t)) return false;
      low += t;
    }
    for (int j = 0; j < n_; ++j) {
      if (!col_term(g[static_cast<std::size_t>(j)], col_lo_[j], col_hi_[j], t)) return false;
      high += t;
    }
    return low > high;
  }

  // Changes the multipliers of some support rows so that g_j = 0 exactly for j in forced. A
  // full-pivoting LU of the (|y|-weighted, so large multipliers move the least, relatively)
  // coefficient matrix picks r = rank independent forced columns and r support rows; the change
  // is solved in rational arithmetic on those. The other forced columns depend on them in
  // floating point (e.g. two identical rows) and usually come out exactly zero too; the caller
  // re-checks every reduced cost.
  bool repair(const std::vector<int>& forced, const std::vector<Rational>& g) {
    const int k = static_cast<int>(forced.size()), s = static_cast<int>(support_.size());
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(k, s);
    for (int c = 0; c < s; ++c) {
      const double w = std::abs(y_[static_cast<std::size_t>(c)].get_d());
      for (const auto& [j, a] : rows_.entries[static_cast<std::size_t>(support_[static_cast<std::size_t>(c)])]) {
        const auto it = std::find(forced.begin(), forced.end(), j);
        if (it != forced.end()) M(it - forced.begin(), c) = a * w;
      }
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
    const int r = static_cast<int>(lu.rank());
    if (r == 0) return false;
    // P M Q = L U: the first r rows of P M and columns of M Q are the pivots.
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> row_of(lu.permutationP().inverse());
    std::vector<int> cols(static_cast<std::size_t>(r)), eqs(static_cast<std::size_t>(r));
    for (int c = 0; c < r; ++c) {
      cols[static_cast<std::size_t>(c)] = lu.permutationQ().indices()[c];                       // support rows
      eqs[static_cast<std::size_t>(c)] = forced[static_cast<std::size_t>(row_of.indices()[c])];  // forced columns
    }
    // E delta = -g_eqs with E(q, c) = a(support[cols[c]], eqs[q]).
    std::vector<Rational> E(static_cast<std::size_t>(r * r), Rational(0)), rhs(static_cast<std::size_t>(r));
    for (int c = 0; c < r; ++c)
      for (const auto& [j, a] : rows_.entries[static_cast<std::size_t>(support_[static_cast<std::size_t>(cols[static_cast<std::size_t>(c)])])]) {
        const auto it = std::find(eqs.begin(), eqs.end(), j);
        if (it != eqs.end()) E[static_cast<std::size_t>((it - eqs.begin()) * r + c)] = Rational(a);
      }
    for (int q = 0; q < r; ++q) rhs[static_cast<std::size_t>(q)] = -g[static_cast<std::size_t>(eqs[static_cast<std::size_t>(q)])];
    std::vector<Rational> delta;
    if (!detail::solve_exact(std::move(E), std::move(rhs), r, delta)) return false;
    for (int c = 0; c < r; ++c) y_[static_cast<std::size_t>(cols[static_cast<std::size_t>(c)])] += delta[static_cast<std::size_t>(c)];
    return true;
  }

  const LpRows& rows_;
  Eigen::Ref<const Eigen::VectorXd> col_lo_, col_hi_;
  int n_;
  std::vector<int> support_;
  std::vector<Rational> y_;
};

// ---------------------------------------------------------------- feasible points

// Does the row hold at the exact point x (given as doubles, or as rationals with enclosures)?
// Outward rounding decides almost always; rationals decide the rest.
template <class ExactAt>
bool row_holds(const std::vector<std::pair<int, double>>& entries, double lo, double hi, const IntervalVector& xi,
               const ExactAt& exact_at) {
  Interval s(0.0);
  for (const auto& [j, a] : entries) s += Interval(a) * xi[j];
  if (s.lower() >= lo && s.upper() <= hi) return true;
  if (s.upper() < lo || s.lower() > hi) return false;
  Rational e(0);
  for (const auto& [j, a] : entries) e += Rational(a) * exact_at(j);
  return (!std::isfinite(lo) || e >= Rational(lo)) && (!std::isfinite(hi) || e <= Rational(hi));
}

bool point_holds(const LpRows& rows, const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                 const Eigen::Ref<const Eigen::VectorXd>& col_hi, const std::vector<Rational>& x) {
  const auto n = static_cast<Eigen::Index>(x.size());
  IntervalVector xi(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Rational& q = x[static_cast<std::size_t>(j)];
    if ((std::isfinite(col_lo[j]) && q < Rational(col_lo[j])) || (std::isfinite(col_hi[j]) && q > Rational(col_hi[j])))
      return false;
    xi[j] = detail::enclose(q);
  }
  const auto exact_at = [&](int j) -> const Rational& { return x[static_cast<std::size_t>(j)]; };
  for (std::size_t i = 0; i < rows.entries.size(); ++i)
    if (!row_holds(rows.entries[i], rows.lo[i], rows.hi[i], xi, exact_at)) return false;
  return true;
}

// The vertex of the constraints nearly active at x, in rational arithmetic: columns exactly at a
// bound stay there, the most nearly active rows (equalities first) are imposed as equations by
// exact Gauss–Jordan elimination, and the columns they do not determine keep their values.
std::vector<Rational> snapped_vertex(const LpRows& rows, const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                                     const Eigen::Ref<const Eigen::VectorXd>& col_hi,
                                     const Eigen::Ref<const Eigen::VectorXd>& x) {
  const auto n = static_cast<int>(x.size());
  std::vector<Rational> out(static_cast<std::size_t>(n));
  std::vector<char> free(static_cast<std::size_t>(n));
  int nfree = 0;
  for (int j = 0; j < n; ++j) {
    double v = x[j];
    if (col_lo[j] == col_hi[j] || v <= col_lo[j]) v = col_lo[j];
    else if (v >= col_hi[j]) v = col_hi[j];
    out[static_cast<std::size_t>(j)] = Rational(v);
    free[static_cast<std::size_t>(j)] = v != col_lo[j] && v != col_hi[j];
    nfree += free[static_cast<std::size_t>(j)];
  }
  if (nfree == 0) return out;
  // Candidate rows: relative slack at x to the nearer finite bound.
  std::vector<std::tuple<double, int, double>> cand;  // (slack, row, target)
  for (std::size_t i = 0; i < rows.entries.size(); ++i) {
    double act = 0, mag = 0;
    for (const auto& [j, a] : rows.entries[i]) {
      act += a * x[j];
      mag += std::abs(a * x[j]);
    }
    for (double b : {rows.lo[i], rows.hi[i]}) {
      if (!std::isfinite(b)) continue;
      const double slack = std::abs(act - b) / (mag + std::abs(b) + 1e-300);
      if (slack <= 1e-7 || rows.lo[i] == rows.hi[i]) cand.emplace_back(rows.lo[i] == rows.hi[i] ? -1.0 : slack, static_cast<int>(i), b);
      if (rows.lo[i] == rows.hi[i]) break;
    }
  }
  std::sort(cand.begin(), cand.end());
  if (cand.size() > static_cast<std::size_t>(4 * nfree + 20)) cand.resize(static_cast<std::size_t>(4 * nfree + 20));
  // Gauss–Jordan on the accepted equations over the free columns: row r has pivot column piv[r].
  std::vector<std::vector<Rational>> eq;  // coefficients over all n columns (fixed ones zero), rhs last
  std::vector<int> piv;
  for (const auto& [slack, i, target] : cand) {
    if (static_cast<int>(piv.size()) == nfree) break;
    std::vector<Rational> r(static_cast<std::size_t>(n + 1), Rational(0));
    r[static_cast<std::size_t>(n)] = Rational(target);
    for (const auto& [j, a] : rows.entries[static_cast<std::size_t>(i)]) {
      if (free[static_cast<std::size_t>(j)]) r[static_cast<std::size_t>(j)] += Rational(a);
      else r[static_cast<std::size_t>(n)] -= Rational(a) * out[static_cast<std::size_t>(j)];
    }
    for (std::size_t k = 0; k < eq.size(); ++k) {
      const Rational f = r[static_cast<std::size_t>(piv[k])];
      if (sgn(f) == 0) continue;
      for (int j = 0; j <= n; ++j) r[static_cast<std::size_t>(j)] -= f * eq[k][static_cast<std::size_t>(j)];
    }
    int best = -1;
    double best_mag = 0;
    for (int j = 0; j < n; ++j) {
      const double m = std::abs(r[static_cast<std::size_t>(j)].get_d());
      if (sgn(r[static_cast<std::size_t>(j)]) != 0 && (best < 0 || m > best_mag)) {
        best = j;
        best_mag = m;
      }
    }
    if (best < 0) continue;  // dependent on the accepted ones
    const Rational p = r[static_cast<std::size_t>(best)];
    for (auto& v : r) v /= p;
    for (auto& e : eq) {
      const Rational f = e[static_cast<std::size_t>(best)];
      if (sgn(f) == 0) continue;
      for (int j = 0; j <= n; ++j) e[static_cast<std::size_t>(j)] -= f * r[static_cast<std::size_t>(j)];
    }
    eq.push_back(std::move(r));
    piv.push_back(best);
  }
  // Columns that are neither fixed nor pivots keep their double values.
  std::vector<char> is_piv(static_cast<std::size_t>(n), 0);
  for (int j : piv) is_piv[static_cast<std::size_t>(j)] = 1;
  for (std::size_t k = 0; k < eq.size(); ++k) {
    Rational v = eq[k][static_cast<std::size_t>(n)];
    for (int j = 0; j < n; ++j)
      if (!is_piv[static_cast<std::size_t>(j)] && free[static_cast<std::size_t>(j)] && sgn(eq[k][static_cast<std::size_t>(j)]) != 0)
        v -= eq[k][static_cast<std::size_t>(j)] * out[static_cast<std::size_t>(j)];
    out[static_cast<std::size_t>(piv[k])] = v;
  }
  return out;
}

void check_sizes(const LpRows& rows, const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                 const Eigen::Ref<const Eigen::VectorXd>& col_hi, bool sizes_match, const char* what) {
  if (rows.lo.size() != rows.entries.size() || rows.hi.size() != rows.entries.size() || col_hi.size() != col_lo.size() ||
      !sizes_match)
    throw InputError(std::string("LP certificate: the size of ") + what + " does not match the constraint system");
  for (const auto& entries : rows.entries)
    for (const auto& [j, a] : entries)
      if (j < 0 || j >= col_lo.size() || !std::isfinite(a))
        throw InputError("LP certificate: a row has a column index out of range or a non-finite coefficient");
}

}  // namespace

bool verify_infeasibility_certificate(const LpRows& rows, const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                                      const Eigen::Ref<const Eigen::VectorXd>& col_hi,
                                      const Eigen::Ref<const Eigen::VectorXd>& y) {
  check_sizes(rows, col_lo, col_hi, y.size() == static_cast<Eigen::Index>(rows.entries.size()), "y");
  FarkasCheck check(rows, col_lo, col_hi);
  const Eigen::VectorXd minus_y = -y;
  return check.oriented(y) || check.oriented(minus_y);
}

bool verify_feasible_point(const LpRows& rows, const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                           const Eigen::Ref<const Eigen::VectorXd>& col_hi, const Eigen::Ref<const Eigen::VectorXd>& x) {
  check_sizes(rows, col_lo, col_hi, x.size() == col_lo.size(), "x");
  if (!x.allFinite()) return false;
  std::vector<Rational> q(static_cast<std::size_t>(x.size()));
  for (Eigen::Index j = 0; j < x.size(); ++j) q[static_cast<std::size_t>(j)] = Rational(x[j]);
  if (point_holds(rows, col_lo, col_hi, q)) return true;
  return point_holds(rows, col_lo, col_hi, snapped_vertex(rows, col_lo, col_hi, x));
}

bool prove_infeasible(const LinearProgram& lp) {
  const int n = lp.num_variables(), m = lp.num_rows();
  const LpRows& rows = lp.rows();
  Eigen::VectorXd col_lo(n), col_hi(n);
  for (int j = 0; j < n; ++j) {
    col_lo[j] = lp.variable_lower(j);
    col_hi[j] = lp.variable_upper(j);
  }
  // Minimax violation: min t  s.t.  row_lo - t w <= A x <= row_hi + t w, x in its bounds, t >= 0,
  // one GLPK row per finite side; w = the row's largest coefficient (scale-free violations).
  LinearProgram el(n + 1);
  for (int j = 0; j < n; ++j) el.set_variable_bounds(j, col_lo[j], col_hi[j]);
  el.set_variable_bounds(n, 0, inf);
  std::vector<std::pair<int, int>> sides(static_cast<std::size_t>(m), {-1, -1});
  for (int i = 0; i < m; ++i) {
    const auto k = static_cast<std::size_t>(i);
    double w = 0;
    for (const auto& [j, a] : rows.entries[k]) w = std::max(w, std::abs(a));
    if (w == 0) w = 1;
    std::vector<std::pair<int, double>> e = rows.entries[k];
    e.emplace_back(n, w);
    if (std::isfinite(rows.lo[k])) sides[k].first = el.add_row(e, rows.lo[k], inf);
    e.back().second = -w;
    if (std::isfinite(rows.hi[k])) sides[k].second = el.add_row(e, -inf, rows.hi[k]);
  }
  el.set_objective_coordinate(n, Sense::minimize);
  auto certificate = [&](const LpSolution& sol) {
    if (sol.status != LpStatus::optimal || sol.row_dual.size() != el.num_rows()) return false;
    Eigen::VectorXd y = Eigen::VectorXd::Zero(m);
    for (int i = 0; i < m; ++i) {
      const auto& [lo_row, hi_row] = sides[static_cast<std::size_t>(i)];
      if (lo_row >= 0) y[i] += sol.row_dual[lo_row];
      if (hi_row >= 0) y[i] += sol.row_dual[hi_row];
    }
    return verify_infeasibility_certificate(rows, col_lo, col_hi, y);
  };
  try {
    if (certificate(el.solve())) return true;
  } catch (const NumericalError&) {
  }
  // GLPK's exact simplex as a solver only: it solves a rounded copy of the problem, but its
  // duals are often a certificate for the original one too — which is checked here.
  try {
    if (certificate(el.solve_exact())) return true;
  } catch (const NumericalError&) {
  }
  return false;
}

BoolInterval certified_is_empty(LinearProgram& lp) {
  const int n = lp.num_variables();
  lp.set_objective(Eigen::VectorXd::Zero(n), Sense::minimize);
  Eigen::VectorXd col_lo(n), col_hi(n);
  for (int j = 0; j < n; ++j) {
    col_lo[j] = lp.variable_lower(j);
    col_hi[j] = lp.variable_upper(j);
  }
  try {
    const LpSolution sol = lp.solve();
    if (sol.status != LpStatus::infeasible && verify_feasible_point(lp.rows(), col_lo, col_hi, sol.x))
      return BoolInterval::no;
  } catch (const NumericalError&) {
  }
  return prove_infeasible(lp) ? BoolInterval::yes : BoolInterval::unknown;
}

}  // namespace sets
