#pragma once
// Private helpers (not installed): small verified linear-algebra steps shared by the set types.
// Numeric only; the set-valued enclosures built from them are in domains/interval_enclosure.hpp.

#include <Eigen/Core>

#include <optional>

#include "sets/numeric/interval_matrix.hpp"

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
}  // namespace sets::detail
