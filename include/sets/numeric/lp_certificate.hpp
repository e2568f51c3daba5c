#pragma once
// Exact certificates for "is the feasible set of this LP empty?".
//
// The constraint system is  row_lo <= A x <= row_hi,  col_lo <= x <= col_hi  with double data
// (bounds may be infinite). Every double is a rational number, so the question has an exact
// answer; floating point only proposes candidates, and exact rational arithmetic (GMP) checks
// them on the ORIGINAL data:
//
//   empty      a Farkas certificate: multipliers y with  min_{z in [row_lo,row_hi]} y^T z  >
//              max_{x in [col_lo,col_hi]} (A^T y)^T x. Then y^T A x would have to lie on both
//              sides at once, so no x exists. Candidates are the optimal duals of the
//              minimax-violation LP  min t  s.t.  row_lo - t w <= A x <= row_hi + t w  (in
//              floating point, then GLPK's exact simplex used as a solver only). A candidate is
//              "repaired" exactly where it must be: the reduced costs of unbounded columns are
//              made exactly zero by solving a small rational system.
//   non-empty  a point checked exactly: the candidate itself (outward rounding first, rationals
//              where that cannot decide), or the vertex of its nearly active constraints solved
//              in rational arithmetic.
//
// glp_exact's own verdict is never trusted: it first replaces every double by a nearby simple
// fraction (relative tolerance ~1e-9) and so decides a different problem.

#include <Eigen/Core>

#include "sets/core/bool_interval.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/numeric/safe_bound.hpp"

namespace sets {

/// Do the multipliers y (one per row) prove the system empty? Exact; y may be approximate (a
/// repaired copy is checked as well). False means "not proven", not "feasible".
bool verify_infeasibility_certificate(const LpRows& rows, const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                                      const Eigen::Ref<const Eigen::VectorXd>& col_hi,
                                      const Eigen::Ref<const Eigen::VectorXd>& y);

/// Does x, or the exact vertex of the constraints nearly active at x, satisfy every constraint?
/// Exact. False means "not proven", not "infeasible".
bool verify_feasible_point(const LpRows& rows, const Eigen::Ref<const Eigen::VectorXd>& col_lo,
                           const Eigen::Ref<const Eigen::VectorXd>& col_hi, const Eigen::Ref<const Eigen::VectorXd>& x);

/// Proves the LP's constraint system empty (objective ignored) with a certificate from the
/// minimax-violation LP; false if no certificate verifies. Does not modify `lp`.
bool prove_infeasible(const LinearProgram& lp);

/// Is the LP's feasible set empty? yes / no only with an exact proof; unknown otherwise
/// (including when the floating-point solver fails). `lp`'s objective is replaced by zero.
BoolInterval certified_is_empty(LinearProgram& lp);

}  // namespace sets
