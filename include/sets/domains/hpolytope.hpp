#pragma once
// H-polytope {x : A x <= b} and its operations.
//
// Guarantees. `contains` evaluates A x - b in interval arithmetic (yes/no/unknown). `is_empty`
// answers yes/no only with a certificate checked in exact rational arithmetic on the stored
// doubles (sets/numeric/lp_certificate.hpp), else unknown. `outer_box` and `support`
// certify every finite bound with a Neumaier–Shcherbina safe bound over an artificial box that is
// proven to contain the polytope (as pui() does), so they contain the polytope; when a direction
// cannot be certified the answer is +inf (still a bound, just useless) — this happens only for
// unbounded polytopes. Operations that can only enlarge (remove_redundant) or are built from
// certified bounds (linear_map) return polytopes that contain the exact result.
//
// The generic operations (support, outer_box, contains, linear_map, to_string) are declared in
// set_operations.hpp, the conversions to other set types in conversions.hpp.

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "sets/core/bool_interval.hpp"
#include "sets/domains/set_operations.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets {

/// The set {x : A x <= b}; possibly empty or unbounded. Rows are half-spaces a_i^T x <= b_i.
class HPolytope {
 public:
  HPolytope() = default;
  /// Throws InputError if A and b disagree in size or hold NaN. b may hold +inf (no constraint).
  HPolytope(Eigen::MatrixXd A, Eigen::VectorXd b);

  int dimension() const { return static_cast<int>(A_.cols()); }
  int num_constraints() const { return static_cast<int>(A_.rows()); }
  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::VectorXd& b() const { return b_; }

 private:
  Eigen::MatrixXd A_;
  Eigen::VectorXd b_;
};

/// yes: a Farkas certificate verified exactly; no: a point verified exactly; else unknown.
BoolInterval is_empty(const HPolytope& P);

/// Largest inscribed ball (floating point LP, not a guarantee). radius = inf if P contains
/// arbitrarily large balls, 0 for a flat polytope. Throws EmptySetError if P is empty.
struct ChebyshevBall {
  Eigen::VectorXd center;
  double radius = 0;
};
ChebyshevBall chebyshev_ball(const HPolytope& P);

/// P ∩ Q (rows stacked; exact).
HPolytope intersect(const HPolytope& P, const HPolytope& Q);
/// Removes rows that the LP finds redundant (its optimum, in floating point, does not exceed
/// b_i), zero rows with b >= 0, and exact duplicates. Removing rows can only enlarge the set, so the result always contains P.
HPolytope remove_redundant(const HPolytope& P);

static_assert(ConvexSet<HPolytope>);  // the generic operations, sets/domains/set_operations.hpp

}  // namespace sets
