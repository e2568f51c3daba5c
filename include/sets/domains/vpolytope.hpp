#pragma once
// V-polytope: the convex hull of finitely many points. The generic operations (support,
// outer_box, contains, linear_map, to_string) are declared in set_operations.hpp, the conversions
// to and from other set types in conversions.hpp.
//
// Guarantees. `linear_map` contains the exact image (`unreliable_linear_map` does not).
// `outer_box` and `support` are exact/rigorous (maxima over the points in interval
// arithmetic). `contains` answers yes/no only with an exact certificate (convex weights solved
// in rationals, or a Farkas certificate; sets/numeric/lp_certificate.hpp), else unknown.
// `convex_hull` runs in CGAL's exact arithmetic (Epeck) in 1-3 dimensions.

#include <Eigen/Core>

#include <string>

#include "sets/core/bool_interval.hpp"
#include "sets/domains/set_operations.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets {

class VPolytope {
 public:
  VPolytope() = default;
  /// Points as the columns of an n x k matrix (k >= 1). Throws InputError for non-finite entries
  /// or no points (the empty set has no V-representation here).
  explicit VPolytope(Eigen::MatrixXd points);

  int dimension() const { return static_cast<int>(V_.rows()); }
  int num_points() const { return static_cast<int>(V_.cols()); }
  const Eigen::MatrixXd& points() const { return V_; }

 private:
  Eigen::MatrixXd V_;
};

/// The points mapped in floating point, rounded to nearest: NOT an outer approximation (the
/// exact image of a point can lie outside; linear_map is the outward version). For plots and as
/// input to exact arithmetic.
VPolytope unreliable_linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const VPolytope& V);

/// Only the vertices of the hull (CGAL, exact), in counter-clockwise order in 2-D.
/// 1-3 dimensions; UnsupportedError above.
VPolytope convex_hull(const VPolytope& V);

static_assert(ConvexSet<VPolytope>);  // the generic operations, sets/domains/set_operations.hpp

}  // namespace sets
