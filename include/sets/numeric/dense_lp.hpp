#pragma once
// A small dense LP solver for problems with few columns (n up to a few dozen) and any number of
// rows:  min/max c^T x  s.t.  row_lo <= A x <= row_hi,  col_lo <= x <= col_hi.
//
// Why: the PUIs of a feasible parameter set solve 2p LPs with p ~ 6-30 columns and ~100 rows
// each; GLPK's per-call overhead (problem set-up, scaling checks, sparse LU of an (m+n)-basis)
// dominates there. This solver works on the vertex (active-set) form: a basis is n active
// constraints (rows or column bounds) whose n x n matrix is inverted afresh at every iteration
// (n small: cheaper than LU solves plus a condition estimate, and the 1-norm condition number
// comes exactly), so nothing accumulates error. The dual simplex (most violated constraint in, Harris ratio
// test) runs from a dual-feasible basis; the primal simplex runs from a feasible vertex. Both
// restart from the last basis, so the 2p objectives over the same rows warm-start each other,
// and rows added since the last solve (row generation) are priced in by the dual simplex.
//
// Guarantees: none. Floating point throughout; `solve()` returns nullopt whenever it gives up
// (iteration limit, a basis too ill-conditioned to trust). Its verdicts infeasible/unbounded
// are not proofs. Its multipliers are meant for safe_bound.hpp, which gives a rigorous bound
// from ANY multipliers; callers fall back to LinearProgram (GLPK) for everything else.

#include <Eigen/Core>
#include <Eigen/LU>

#include <optional>
#include <vector>

#include "sets/numeric/linear_program.hpp"

namespace sets {

class DenseLp {
 public:
  explicit DenseLp(int num_variables);

  int num_variables() const { return n_; }
  int num_rows() const { return m_; }

  /// Appends lo <= a^T x <= hi (lo may be -inf, hi +inf; lo == hi is an equality).
  void add_row(const Eigen::Ref<const Eigen::VectorXd>& a, double lo, double hi);
  void set_variable_bounds(int j, double lo, double hi);
  void set_objective(const Eigen::Ref<const Eigen::VectorXd>& c, Sense sense);

  /// Simplex from the last basis. The solution follows GLPK's conventions (row_dual y with
  /// c = A^T y + reduced_cost), so LinearProgram::safe_bound of the same rows accepts it.
  /// nullopt: the solver gave up; infeasible/unbounded are floating-point verdicts only.
  std::optional<LpSolution> solve();
  /// Forgets the basis: the next solve starts from the column-bound basis.
  void reset_basis() { basis_.clear(); }
  /// Simplex iterations of the last solve.
  int iterations() const { return iterations_; }

 private:
  // A constraint is a row (k >= 0) or a column bound (k = -1 - j).
  double lower(int k) const { return k >= 0 ? lo_[k] : col_lo_[-1 - k]; }
  double upper(int k) const { return k >= 0 ? hi_[k] : col_hi_[-1 - k]; }
  double norm(int k) const { return k >= 0 ? norm_[k] : 1.0; }
  void set_in_basis(int k, bool in) {
    (k >= 0 ? row_in_[static_cast<std::size_t>(k)] : col_in_[static_cast<std::size_t>(-1 - k)]) = in ? 1 : 0;
  }

  void cold_start(const Eigen::VectorXd& g);
  bool factorise();                                      // false: singular or ill-conditioned
  int most_violated(const Eigen::VectorXd& x, int& side) const;  // -2^31: none
  bool dual_step(int q, int side);                        // false: no leaving constraint (infeasible)
  bool primal_step(int r, int direction);                 // false: no blocking constraint (unbounded)
  LpSolution make_solution(LpStatus status) const;

  int n_, m_ = 0;
  Eigen::MatrixXd A_;  // capacity x n, by column: A x is n vectorised axpys over the rows
  Eigen::VectorXd lo_, hi_, norm_;                                            // per row (capacity)
  Eigen::VectorXd col_lo_, col_hi_, c_;
  Sense sense_ = Sense::minimize;

  // The basis: n active constraints, each at its lower (+1) or upper (-1) bound; an
  // "artificial" one is a column bound that is infinite, held at a far finite value only to
  // start the dual simplex (it must leave before an optimum is reported).
  std::vector<int> basis_;
  std::vector<signed char> side_;
  std::vector<char> artificial_;
  std::vector<char> row_in_, col_in_;
  double artificial_far_ = 0;

  // Work of the current iteration.
  Eigen::VectorXd g_;        // cost in minimisation form
  Eigen::MatrixXd B_;        // rows: normals of the basic constraints
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::MatrixXd Binv_;     // B^-1 (n x n): x, the multipliers and both ratio tests from it
  Eigen::VectorXd x_, mu_, rhs_;
  Eigen::VectorXd ax_;       // A x for every row
  Eigen::VectorXd aq_, u_, d_, ad_;  // ratio-test work (kept: no allocation per iteration)
  struct Blocking {          // a constraint the primal step may meet (see primal_step)
    int k;
    double step, size;
    signed char side;
  };
  std::vector<Blocking> blocking_;
  int iterations_ = 0;
};

}  // namespace sets
