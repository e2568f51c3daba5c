#include "numeric/certified_extent.hpp"

#include <algorithm>
#include <cmath>

#include "sets/numeric/lp_certificate.hpp"

namespace sets::detail {

namespace {

// Phase 2 with one artificial box X; false if some certified end reaches an artificial face.
bool certify_in_box(LinearProgram& lp, const SolveOverSet& solve, const std::vector<LpSolution>& phase1,
                    const Eigen::VectorXd& own_lo, const Eigen::VectorXd& own_hi, double factor, Extent& e) {
  const int n = lp.num_variables();
  Eigen::VectorXd xlo(n), xhi(n);
  std::vector<char> art_lo(static_cast<std::size_t>(n)), art_hi(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    const double w = std::isfinite(e.float_hi[j] - e.float_lo[j]) ? e.float_hi[j] - e.float_lo[j] : 0.0;
    const double lo = e.float_lo[j] - factor * w - 1e-8 * (1 + std::abs(e.float_lo[j]));
    const double hi = e.float_hi[j] + factor * w + 1e-8 * (1 + std::abs(e.float_hi[j]));
    // A face of X that lies outside the set's own bound is not artificial: the bound is true.
    art_lo[static_cast<std::size_t>(j)] = lo > own_lo[j];
    art_hi[static_cast<std::size_t>(j)] = hi < own_hi[j];
    xlo[j] = std::max(lo, own_lo[j]);
    xhi[j] = std::min(hi, own_hi[j]);
    lp.set_variable_bounds(j, xlo[j], std::max(xhi[j], xlo[j]));
  }
  Eigen::VectorXd slo = e.float_lo, shi = e.float_hi;
  for (int l = 0; l < n; ++l) {
    for (Sense sense : {Sense::minimize, Sense::maximize}) {
      const bool lower = sense == Sense::minimize;
      // An unbounded end stays infinite: nothing to certify.
      if (std::isinf(lower ? e.float_lo[l] : e.float_hi[l])) continue;
      lp.set_objective_coordinate(l, sense);
      // Any multipliers give a valid bound: first try phase 1's (zero for rows added later)
      // with the box X, which saves a re-solve whenever they certify the end.
      LpSolution sol = phase1[static_cast<std::size_t>(2 * l + !lower)];
      const auto inside = [&](double b) {
        return lower ? (b > xlo[l] || !art_lo[static_cast<std::size_t>(l)])
                     : (b < xhi[l] || !art_hi[static_cast<std::size_t>(l)]);
      };
      if (sol.status == LpStatus::optimal) {
        const Eigen::Index m_before = sol.row_dual.size();
        sol.row_dual.conservativeResize(lp.num_rows());
        sol.row_dual.tail(lp.num_rows() - m_before).setZero();
        if (!inside(lp.safe_bound(sol))) sol.status = LpStatus::infeasible;  // re-solve below
      }
      if (sol.status != LpStatus::optimal) sol = solve(e.lps);
      if (sol.status != LpStatus::optimal) return false;
      const double bound = lp.safe_bound(sol);
      if (!inside(bound)) return false;
      // Ends on a true bound of the set are that bound.
      (lower ? slo : shi)[l] = lower ? std::max(bound, own_lo[l]) : std::min(bound, own_hi[l]);
      (lower ? e.lower_points : e.upper_points).col(l) = sol.x;
    }
  }
  e.lo = slo;
  e.hi = shi.cwiseMax(slo);
  return true;
}

}  // namespace

Extent certified_extent(LinearProgram& lp, const SolveOverSet& solve, const std::vector<Eigen::VectorXd>& directions,
                        bool safe) {
  const int n = lp.num_variables();
  Extent e;
  e.float_lo.resize(n);
  e.float_hi.resize(n);
  e.lower_points.resize(n, n);
  e.upper_points.resize(n, n);
  Eigen::VectorXd own_lo(n), own_hi(n);
  for (int j = 0; j < n; ++j) {
    own_lo[j] = lp.variable_lower(j);
    own_hi[j] = lp.variable_upper(j);
  }
  // Phase 1: floating-point extremes; the 2n problems share one constraint matrix and warm-start.
  std::vector<LpSolution> phase1(static_cast<std::size_t>(2 * n));
  for (int l = 0; l < n; ++l) {
    for (Sense sense : {Sense::minimize, Sense::maximize}) {
      const bool lower = sense == Sense::minimize;
      lp.set_objective_coordinate(l, sense);
      const LpSolution& sol = phase1[static_cast<std::size_t>(2 * l + !lower)] = solve(e.lps);
      if (sol.status == LpStatus::infeasible) {
        // Empty only with a Farkas certificate checked in exact arithmetic. (With row
        // generation the LP is a relaxation: if it is empty, so is the set.)
        ++e.lps;
        e.status = prove_infeasible(lp) ? ExtentStatus::empty : ExtentStatus::unknown;
        return e;
      }
      const double end = sol.status == LpStatus::unbounded ? (lower ? -inf : inf) : sol.objective;
      (lower ? e.float_lo : e.float_hi)[l] = end;
      (lower ? e.lower_points : e.upper_points).col(l) = sol.x;
    }
  }
  e.status = ExtentStatus::feasible;
  e.lo = e.float_lo.cwiseMin(e.float_hi);
  e.hi = e.float_hi.cwiseMax(e.float_lo);

  auto maximise = [&](const Eigen::VectorXd& d) {
    lp.set_objective(d, Sense::maximize);
    const LpSolution sol = solve(e.lps);
    if (sol.status != LpStatus::optimal) return inf;  // unbounded (infeasible: a numerical failure)
    return safe ? lp.safe_bound(sol) : sol.objective;
  };
  if (!safe) {
    for (const auto& d : directions) e.maxima.push_back(maximise(d));
    return e;
  }
  for (double factor : {1e-2, 1e-1, 1.0, 10.0}) {
    if (!certify_in_box(lp, solve, phase1, own_lo, own_hi, factor, e)) continue;
    e.certified = true;
    for (const auto& d : directions) e.maxima.push_back(maximise(d));
    return e;
  }
  // Nothing certified: +inf is still a bound, and so are the set's own variable bounds. The
  // floating-point extent stays in float_lo/float_hi, as an estimate only (it can miss the set:
  // seen on badly scaled regressions, width-0 intervals off by GLPK's tolerance).
  e.maxima.assign(directions.size(), inf);
  e.lo = own_lo;
  e.hi = own_hi;
  return e;
}

}  // namespace sets::detail
