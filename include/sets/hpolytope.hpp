#pragma once
// H-polytope {x : A x <= b}.

#include <Eigen/Core>

namespace sets {

/// The set {x : A x <= b}; possibly empty or unbounded. Rows are half-spaces a_i^T x <= b_i.
class HPolytope {
 public:
  HPolytope() = default;
  /// Throws InputError if A and b disagree in size or hold NaN.
  HPolytope(Eigen::MatrixXd A, Eigen::VectorXd b);

  int dimension() const { return static_cast<int>(A_.cols()); }
  int num_constraints() const { return static_cast<int>(A_.rows()); }
  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::VectorXd& b() const { return b_; }

 private:
  Eigen::MatrixXd A_;
  Eigen::VectorXd b_;
};

}  // namespace sets
