#pragma once
// Private helpers (not installed): stored sets that contain every set of an interval enclosure of
// their data (the last step of every guaranteed set operation).

#include "sets/domains/ellipsoid.hpp"
#include "sets/domains/zonotope.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets::detail {

/// A stored ellipsoid that contains E(c, T) for every c in the box `c` and symmetric PSD T in P.
Ellipsoid outer_ellipsoid(const IntervalVector& c, const IntervalMatrix& P);

/// A stored zonotope containing {c + G xi} for every c in the box `c` and G in the enclosure:
/// centre and generators at the midpoints plus one axis-aligned generator per coordinate
/// carrying the radii (only where nonzero).
Zonotope outer_zonotope(const IntervalVector& c, const IntervalMatrix& G);

}  // namespace sets::detail
