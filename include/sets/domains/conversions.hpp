#pragma once
// Conversions between the set types, all in one place. Each says whether its result CONTAINS
// its input (an outer approximation: safe where a guarantee is at stake), is EXACT, or is only
// rounded to nearest (fine for plots and as input to exact arithmetic, not for a guarantee).
//
//   from \ to   HPolytope               VPolytope                 2-D polygon (2 x k vertices)
//   box         to_hpolytope  exact     to_vpolytope  exact       -
//   Zonotope    to_hpolytope  contains  to_vpolytope  nearest     polygon_vertices  nearest
//   VPolytope   to_hpolytope  contains  convex_hull   nearest     polygon_vertices  nearest
//   HPolytope   -                       to_vpolytope  nearest     polygon_vertices  nearest
//   Ellipsoid   -                       -                         outer_polygon     contains
//
// A box becomes a zonotope with Zonotope::from_box (contains); a feasible parameter set becomes
// a zonotope in fps/outer_zonotope.hpp, one layer up. The H <-> V conversions run in CGAL's exact
// arithmetic (src/domains/polytope_cgal.cpp) in 1-3 dimensions and throw UnsupportedError above.

#include <Eigen/Core>

#include "sets/domains/ellipsoid.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/domains/vpolytope.hpp"
#include "sets/domains/zonotope.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets {

// ------------------------------------------------------------------------------- boxes

/// The box as 2n half-spaces (exact).
HPolytope to_hpolytope(const IntervalVector& box);
/// The 2^n corners of a bounded box (n <= 20).
VPolytope to_vpolytope(const IntervalVector& box);

// ------------------------------------------------------------------------------- polytopes

/// Outer H-polytope of Z. Exact facet enumeration (each facet normal from n-1 generators, in the
/// span of G for flat zonotopes, plus equality pairs orthogonal to the span); offsets are
/// rigorous support bounds, so the polytope always contains Z and equals it up to rounding.
/// Throws UnsupportedError when the number of facet candidates C(m, r-1) exceeds `max_facets`.
HPolytope to_hpolytope(const Zonotope& Z, long max_facets = 200000);
/// Vertices of a 2-D or 3-D zonotope (via its facets); rounded to nearest.
VPolytope to_vpolytope(const Zonotope& Z);
/// Facets of the hull: normals from CGAL's exact hull (rounded), offsets certified, so the
/// result contains the hull. Flat hulls get equality pairs. 1-3 dimensions.
HPolytope to_hpolytope(const VPolytope& V);
/// Vertices of a bounded full-dimensional H-polytope (CGAL exact, by polar duality around a
/// Chebyshev centre), rounded to nearest. 1-3 dimensions. Throws EmptySetError if P is empty,
/// UnsupportedError if P is unbounded, not full-dimensional, or above 3-D.
VPolytope to_vpolytope(const HPolytope& P);

// ------------------------------------------------------------------------------- 2-D polygons (plots)

/// Vertices of a 2-D zonotope in counter-clockwise order (a polygon a plotting tool can draw).
/// Floating point (vertices exact up to rounding). Throws InputError unless Z is 2-D.
Eigen::MatrixXd polygon_vertices(const Zonotope& Z);
/// Counter-clockwise polygon vertices (2 x k) of a 2-D polytope, for plotting.
Eigen::MatrixXd polygon_vertices(const VPolytope& V);
Eigen::MatrixXd polygon_vertices(const HPolytope& P);
/// Outer approximation of a 2-D ellipsoid by a convex polygon, for plotting: `n` vertices
/// (counter-clockwise) of a polygon circumscribed about E (each edge tangent to E), so the
/// polygon contains E. Throws InputError unless E is 2-D.
Eigen::MatrixXd outer_polygon(const Ellipsoid& E, int n = 64);

}  // namespace sets
