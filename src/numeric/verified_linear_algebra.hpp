#pragma once
// Private helpers (not installed): small verified linear-algebra steps shared by the set types.

#include <Eigen/Core>

#include <optional>

#include "sets/domains/ellipsoid.hpp"
#include "sets/numeric/interval_matrix.hpp"
#include "sets/domains/zonotope.hpp"

namespace sets::detail {

/// Point enclosures of double vectors/matrices (short names for the many uses in zonotope.cpp).
inline IntervalVector iv(const Eigen::VectorXd& x) { return to_interval(x); }
inline IntervalMatrix im(const Eigen::MatrixXd& x) { return to_interval(x); }

/// Upper bound on the Frobenius norm of the magnitudes of an interval matrix (>= spectral norm).
double frobenius_upper(const IntervalMatrix& M);
/// Upper bound on the Euclidean norm of the magnitudes of an interval vector.
double norm_upper(const IntervalVector& v);
/// Outward-rounded interval matrix product.
IntervalMatrix multiply(const IntervalMatrix& A, const IntervalMatrix& B);
Interval dot(const IntervalVector& a, const IntervalVector& b);
/// For an approximate inverse X of A: a rigorous bound on ||A^{-1} - X||_2, or nullopt when
/// ||I - X A||_F >= 1 (cannot verify).
std::optional<double> inverse_deviation_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& X);
/// Rigorous bound on ||A^{-1}||_2 from an approximate inverse X, or nullopt.
std::optional<double> inverse_norm_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& X);
/// A symmetric double matrix M with M >= T (Loewner order) for every symmetric T in P.
Eigen::MatrixXd upper_symmetric_bound(const IntervalMatrix& P);
/// A stored ellipsoid that contains E(c, T) for every c in the box `c` and symmetric PSD T in P.
Ellipsoid outer_ellipsoid(const IntervalVector& c, const IntervalMatrix& P);

/// A stored zonotope containing {c + G xi} for every c in the box `c` and G in the enclosure:
/// centre and generators at the midpoints plus one axis-aligned generator per coordinate
/// carrying the radii (only where nonzero).
Zonotope outer_zonotope(const IntervalVector& c, const IntervalMatrix& G);

}  // namespace sets::detail
