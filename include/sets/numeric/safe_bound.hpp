#pragma once
// Safe bounds for linear programs (Neumaier & Shcherbina, "Safe bounds in linear and mixed-integer
// programming", Math. Prog. 99, 2004).
//
// For  min c^T x  s.t.  row_lo <= A x <= row_hi,  col_lo <= x <= col_hi  and ANY vector y,
//   c^T x = y^T (A x) + r^T x,   r = c - A^T y,
// so  c^T x >= sum_i inf(y_i [row_lo_i, row_hi_i]) + sum_j inf(r_j [col_lo_j, col_hi_j]).
// Evaluated in outward-rounded interval arithmetic this is a rigorous lower bound for every
// feasible x, however inaccurate the (approximate) dual y is; a good y makes it tight. A term
// whose multiplier is nonzero and whose bound is infinite makes the bound -inf (nothing certified).

#include <Eigen/Core>

#include <utility>
#include <vector>

namespace sets {

struct LpRows {
  std::vector<std::vector<std::pair<int, double>>> entries;  // sparse rows of A
  std::vector<double> lo, hi;                                 // row bounds (may be infinite)
};

/// Rigorous lower bound on min c^T x over the LP's feasible set, from multipliers y.
double safe_lower_bound(const Eigen::Ref<const Eigen::VectorXd>& c, const LpRows& rows,
                        const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                        const Eigen::Ref<const Eigen::VectorXd>& col_hi,
                        const Eigen::Ref<const Eigen::VectorXd>& y);

/// Rigorous upper bound on max c^T x (the mirror image of safe_lower_bound).
double safe_upper_bound(const Eigen::Ref<const Eigen::VectorXd>& c, const LpRows& rows,
                        const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                        const Eigen::Ref<const Eigen::VectorXd>& col_hi,
                        const Eigen::Ref<const Eigen::VectorXd>& y);

}  // namespace sets
