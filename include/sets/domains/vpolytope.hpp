#pragma once
// V-polytope: the convex hull of finitely many points, and the H <-> V conversions.
//
// Guarantees. `outer_box` and `support` are exact/rigorous (maxima over the points in interval
// arithmetic). `contains` answers yes/no only with an exact certificate (convex weights
// solved in rationals, or a Farkas certificate), else unknown (sets/numeric/lp_certificate.hpp). The H <-> V conversions run in CGAL's exact arithmetic (Epeck) in 1-3
// dimensions and throw UnsupportedError above 3-D. to_hpolytope(VPolytope) rounds facet normals
// and certifies offsets, so its result contains the hull; to_vpolytope(HPolytope) returns the
// exact vertices rounded to the nearest double (not an enclosure: a vertex may lie a rounding
// error outside the polytope).

#include <Eigen/Core>

#include <string>

#include "sets/core/bool_interval.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/numeric/interval_matrix.hpp"
#include "sets/domains/zonotope.hpp"

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

/// The 2^n corners of a bounded box (n <= 20).
VPolytope to_vpolytope(const IntervalVector& box);

IntervalVector outer_box(const VPolytope& V);
double support(const VPolytope& V, const Eigen::VectorXd& d);
BoolInterval contains(const VPolytope& V, const Eigen::VectorXd& x);
/// Image A V (points mapped in floating point, rounded to nearest: approximate).
VPolytope linear_map(const Eigen::MatrixXd& A, const VPolytope& V);

/// Only the vertices of the hull (CGAL, exact), in counter-clockwise order in 2-D.
/// 1-3 dimensions; UnsupportedError above.
VPolytope convex_hull(const VPolytope& V);
/// Vertices of a bounded full-dimensional H-polytope (CGAL exact, by polar duality around a
/// Chebyshev centre), rounded to nearest. 1-3 dimensions. Throws EmptySetError if P is empty,
/// UnsupportedError if P is unbounded, not full-dimensional, or above 3-D.
VPolytope to_vpolytope(const HPolytope& P);
/// Facets of the hull: normals from CGAL's exact hull (rounded), offsets certified, so the
/// result contains the hull. Flat hulls get equality pairs. 1-3 dimensions.
HPolytope to_hpolytope(const VPolytope& V);
/// Vertices of a 2-D or 3-D zonotope (via its facets); rounded to nearest.
VPolytope to_vpolytope(const Zonotope& Z);

/// Counter-clockwise polygon vertices (2 x k) of a 2-D set, for plotting.
Eigen::MatrixXd polygon_vertices(const VPolytope& V);
Eigen::MatrixXd polygon_vertices(const HPolytope& P);

std::string to_string(const VPolytope& V);

}  // namespace sets
