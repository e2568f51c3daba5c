#pragma once
// The feasible parameter set of the canonical regression, kept as one FPS per block of
// equations that share parameters.
//
// In the regression of Remark 1 every equation has its own parameters (a row of A_c and of B_c,
// a row of C_c and of D_c), so the set is the Cartesian product of the equations' sets: its
// membership is the conjunction of theirs and its PUIs are the product of their boxes. Computing
// them per block replaces one LP in every parameter (12 for the paper's example) by small LPs
// (2, 2, 5 and 3 parameters), and with interval regressors only the block's own parameters are
// split into orthants.

#include <Eigen/Core>

#include <vector>

#include "sets/core/bool_interval.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets {

class CanonicalFps {
 public:
  struct Block {
    std::vector<int> parameters;  // indices into theta, increasing
    std::vector<int> rows;        // rows of the regression, in order (block sample k = rows[k])
    FeasibleParameterSet set{1};  // in the block's parameters
  };

  /// Groups the rows {phi in Psi_t, phi^T theta in Y_t} by the parameters they involve (rows
  /// that share a parameter, directly or through others, go into one block). Rows whose
  /// regressor is zero constrain no parameter: they are kept as checks, and a row with 0 not in
  /// its Y_t is listed in falsified_rows(). Throws InputError for sizes that do not match or a
  /// block with fewer rows than parameters.
  CanonicalFps(const IntervalMatrix& Psi, const IntervalVector& Y);
  /// The same with exact regressors (no interval copy of the whole Psi is made). `const MatrixXd&`,
  /// not Ref: an exact match beside the IntervalMatrix overload (see multiply()).
  CanonicalFps(const Eigen::MatrixXd& Psi, const IntervalVector& Y);
  CanonicalFps() = default;  // no parameters, no rows

  int dimension() const { return dimension_; }
  /// Rows used by the blocks (rows without parameters are not counted).
  int size() const;
  const std::vector<Block>& blocks() const { return blocks_; }
  /// Rows without parameters whose output interval excludes 0: the data contradict the bounds.
  const std::vector<int>& falsified_rows() const { return falsified_; }
  bool has_interval_regressors() const;

  /// Is theta in the set? `no` also when a row without parameters is falsified.
  BoolInterval contains(const Eigen::Ref<const Eigen::VectorXd>& theta) const;

 private:
  int dimension_ = 0;
  std::vector<Block> blocks_;
  std::vector<int> falsified_;
};

/// PUIs block by block, assembled: box, central, consistency, guaranteed, lp_solves and, when empty,
/// the verdict of the first certified-empty block (samples are rows of the regression). The
/// attaining points are assembled from one feasible point per block. `orthants` stays empty
/// (the blocks' orthants are in their own parameters). A falsified row without parameters makes
/// the result empty too (its row is the falsification).
PuiResult pui(const CanonicalFps& fps, const PuiOptions& options = {});

}  // namespace sets
