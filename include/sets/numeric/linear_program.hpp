#pragma once
// LP and MILP over GLPK: build once, change the objective, re-solve from the last basis.
//
// Threads: GLPK keeps its state in thread-local storage (Debian builds it so), but a problem
// object must be created, used and destroyed on one thread. `LinearProgram` is movable, not
// copyable; never share one between threads. Separate objects on separate threads are safe
// (tests/linear_program_test.cpp runs PUIs on several threads at once).
//
// Errors: bad input (NaN, infinite coefficients, magnitudes beyond 1e+-150, bad limits) is an
// InputError; a GLPK failure it cannot recover from, or a GLPK internal error (which would
// abort() without the hook of glpk_error.hpp), is a NumericalError on the calling thread.
//
// Guarantees: `LpSolution::objective` is a floating-point optimum, not a bound. For a rigorous
// bound call `safe_bound` (Neumaier–Shcherbina, see safe_bound.hpp), which needs finite variable
// bounds wherever the reduced cost is not exactly zero.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sets/numeric/safe_bound.hpp"

namespace sets {

inline constexpr double inf = std::numeric_limits<double>::infinity();

enum class Sense { minimize, maximize };
/// cutoff: a solve with LpSolveOptions::cutoff stopped early, the optimum being proven beyond it.
enum class LpStatus { optimal, infeasible, unbounded, cutoff };

struct LpSolution {
  LpStatus status = LpStatus::infeasible;
  Sense sense = Sense::minimize;
  double objective = 0;          // floating-point optimum (not a guaranteed bound)
  Eigen::VectorXd x;             // primal point
  Eigen::VectorXd row_dual;      // multipliers of the rows, GLPK convention
  Eigen::VectorXd reduced_cost;  // c - A^T row_dual, as GLPK computed it
  int iterations = 0;
};

struct LpSolveOptions {
  /// Stop a minimisation as soon as the dual simplex has proven the optimum above this value (a
  /// maximisation: below it): status LpStatus::cutoff, and the solution carries the dual-feasible
  /// point reached, from which safe_bound still gives a rigorous bound (about the cutoff or better).
  /// Branch and bound uses it to drop a node without solving its LP to the end.
  std::optional<double> cutoff;
  /// GLPK's long-step (bound-flipping) ratio test in the dual simplex: far fewer iterations when
  /// many variables and rows are boxed.
  bool long_step = false;
};

enum class MilpStatus { optimal, feasible, infeasible, no_solution };

struct MilpOptions {
  double time_limit_s = 60;    // GLPK branch-and-cut stops here with its incumbent (> 0; inf: none)
  double relative_gap = 1e-6;  // finite, >= 0
  bool verbose = false;
  /// Stop after this many branch-and-bound nodes (0 = no limit). Unlike the wall-clock time
  /// limit, the outcome does not depend on the machine's speed or load: tests use it.
  long node_limit = 0;
};

struct MilpSolution {
  MilpStatus status = MilpStatus::no_solution;
  double objective = 0;   // incumbent value (valid when status is optimal or feasible)
  double best_bound = 0;  // bound from the branch-and-bound tree
  double gap = inf;       // |objective - best_bound| / max(1, |objective|)
  double seconds = 0;
  long nodes = 0;         // branch-and-bound nodes created
  Eigen::VectorXd x;
};

/// A simplex basis: the status of every row and column (basic, or non-basic at which bound), to
/// restart a later solve of the same problem from it (e.g. a branch-and-bound child from its
/// parent's optimal basis). Opaque: take it from basis(), give it to set_basis().
struct LpBasis {
  std::vector<unsigned char> rows, cols;
};

/// A linear program  min/max c^T x  s.t.  row_lo <= A x <= row_hi,  col_lo <= x <= col_hi.
/// Bounds may be infinite. Integer columns turn it into a MILP (solve_milp).
class LinearProgram {
 public:
  explicit LinearProgram(int num_variables = 0);
  ~LinearProgram();
  LinearProgram(LinearProgram&&) noexcept;
  LinearProgram& operator=(LinearProgram&&) noexcept;
  LinearProgram(const LinearProgram&) = delete;
  LinearProgram& operator=(const LinearProgram&) = delete;

  int num_variables() const;
  int num_rows() const;

  /// Appends variables with bounds [lo, hi]; returns the index of the first one.
  int add_variables(int count, double lo = -inf, double hi = inf);
  void set_variable_bounds(int j, double lo, double hi);
  double variable_lower(int j) const;
  double variable_upper(int j) const;
  void set_integer(int j, bool integer = true);

  /// Appends the row lo <= a^T x <= hi (dense or sparse coefficients); returns its index.
  int add_row(const Eigen::Ref<const Eigen::VectorXd>& a, double lo, double hi);
  int add_row(const std::vector<std::pair<int, double>>& entries, double lo, double hi);
  /// Appends the rows lo <= A x <= hi.
  int add_rows(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::VectorXd>& lo,
               const Eigen::Ref<const Eigen::VectorXd>& hi);
  int add_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& A,
               const Eigen::Ref<const Eigen::VectorXd>& lo, const Eigen::Ref<const Eigen::VectorXd>& hi);
  void set_row_bounds(int i, double lo, double hi);
  double row_lower(int i) const;
  double row_upper(int i) const;
  /// Row i's stored coefficients as (column, value) pairs.
  const std::vector<std::pair<int, double>>& row(int i) const;
  /// All rows with their bounds, exactly as given (certificates are checked on these, never on
  /// GLPK's scaled copy).
  const LpRows& rows() const;

  void set_objective(const Eigen::Ref<const Eigen::VectorXd>& c, Sense sense);
  /// Objective +-x_j: the building block of every PUI.
  void set_objective_coordinate(int j, Sense sense);
  const Eigen::VectorXd& objective() const;
  Sense sense() const;

  /// Simplex from the last basis (warm start), on GLPK's scaled copy (power-of-2 factors, so
  /// exact). When GLPK fails it recovers (advanced basis, slack basis with the textbook ratio
  /// test, exact simplex as a search aid) before throwing NumericalError. `infeasible` is a
  /// floating-point verdict, not a proof: see lp_certificate.hpp.
  LpSolution solve();
  LpSolution solve(const LpSolveOptions& options);
  /// GLPK's exact rational simplex (glp_exact), as a solver only: it first replaces every
  /// double by a nearby simple fraction, so its verdict is about a different problem and is
  /// NOT a certificate. Prove emptiness with lp_certificate.hpp.
  LpSolution solve_exact();
  /// Forgets the basis: the next solve starts cold (for benchmarks and recovery).
  void reset_basis();
  /// The current basis, and restoring one taken from this problem (same rows and columns; bounds
  /// may have changed since: a status the new bounds do not allow is corrected). Throws
  /// InputError if the sizes differ.
  LpBasis basis() const;
  void set_basis(const LpBasis& basis);
  /// Branch and cut with a time limit; optional starting incumbent (e.g. an LP-rounded point).
  MilpSolution solve_milp(const MilpOptions& options = {},
                          const std::optional<Eigen::VectorXd>& start = std::nullopt);

  /// Rigorous bound on the optimum from the dual of `solution` (min: lower bound; max: upper
  /// bound), or -inf/+inf if none can be certified. See safe_bound.hpp.
  double safe_bound(const LpSolution& solution) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

const char* to_string(LpStatus s);
const char* to_string(MilpStatus s);

}  // namespace sets
