#pragma once
// The operations every set type offers, declared in one place, and the concept `ConvexSet` that
// names them. Each set type's header includes this one and checks `static_assert(ConvexSet<T>)`
// after its class, so a new set type cannot miss an operation; the type's own header keeps only
// what is particular to it (reduce_order, intersect_strip, project, remove_redundant, ...), and
// conversions between types are in conversions.hpp.
//
// Contract, for every set type S in R^n:
//   s.dimension()       n
//   support(S, d)       a rigorous UPPER bound on max_{x in S} d^T x (+inf if it cannot be certified)
//   outer_box(S)        a box that CONTAINS S (+-inf ends where S is unbounded)
//   contains(S, x)      yes / no only when proven; unknown otherwise
//   linear_map(A, S)    a set of the same type that contains {A x : x in S} (throwing for an
//                       HPolytope and a singular or non-square A)
//   to_string(S)        text with 17 significant digits that sets::from_string (set_io.hpp)
//                       reads back
// minkowski_sum, translate and the strip intersections exist for Zonotope and Ellipsoid only and
// are declared in their headers.

#include <Eigen/Core>

#include <concepts>
#include <string>
#include <vector>

#include "sets/core/bool_interval.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets {

class Ellipsoid;
class HPolytope;
class VPolytope;
class Zonotope;

// ------------------------------------------------------------------------------- support

/// d^T c + sum_j |d^T g_j|, rounded up.
double support(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& d);
/// d^T c + sqrt(d^T P d), rounded up.
double support(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& d);
/// Maximum over the points in interval arithmetic (exact up to the final rounding up).
double support(const VPolytope& V, const Eigen::Ref<const Eigen::VectorXd>& d);
/// Certified by a Neumaier–Shcherbina safe bound from the LP's dual (+inf if unbounded or not
/// certifiable). Throws EmptySetError if P is empty.
double support(const HPolytope& P, const Eigen::Ref<const Eigen::VectorXd>& d);
/// Rigorous upper bounds for several directions at once (one LP set-up).
std::vector<double> support(const HPolytope& P, const std::vector<Eigen::VectorXd>& directions);

// ------------------------------------------------------------------------------- outer_box

/// Interval hull c_i +- sum_j |G_ij|, rounded outward (the tightest box containing Z).
IntervalVector outer_box(const Zonotope& Z);
/// c_i +- sqrt(P_ii), rounded outward.
IntervalVector outer_box(const Ellipsoid& E);
/// Minimum and maximum of each coordinate over the points (exact).
IntervalVector outer_box(const VPolytope& V);
/// +-inf ends where P is unbounded or the end cannot be certified. Throws EmptySetError if P is
/// empty.
IntervalVector outer_box(const HPolytope& P);

// ------------------------------------------------------------------------------- contains

/// Decided by the LP  min t  s.t.  G xi = x - c, |xi_j| <= t. `no` is certified by a separating
/// direction (support function), `yes` by a feasible xi whose residual is absorbed with a
/// verified inverse of n independent generators; otherwise `unknown`.
BoolInterval contains(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& x);
/// yes/no only when proven in interval arithmetic; unknown near the boundary and for most points
/// of a flat ellipsoid (rounding cannot decide membership in a lower-dimensional set).
BoolInterval contains(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& x);
/// yes / no only with an exact certificate (convex weights solved in rationals, or a Farkas
/// certificate; sets/numeric/lp_certificate.hpp), else unknown.
BoolInterval contains(const VPolytope& V, const Eigen::Ref<const Eigen::VectorXd>& x);
/// `unknown` when some a_i^T x - b_i cannot be sign-decided in interval arithmetic.
BoolInterval contains(const HPolytope& P, const Eigen::Ref<const Eigen::VectorXd>& x);

// ------------------------------------------------------------------------------- linear_map

/// Centre A c, generators A G, plus rounding generators (contains the exact image).
Zonotope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const Zonotope& Z);
/// Centre A c, shape A P A^T, enlarged for rounding so that it contains the exact image. A may be
/// rectangular.
Ellipsoid linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const Ellipsoid& E);
/// Contains the exact image: each point's image is enclosed in an interval box, and the box in
/// the cross-polytope c +- m' r_j e_j (m' its coordinates of nonzero width r_j; the l1 ball of
/// radius m' contains the unit cube), whose 2 m' corners (rounded outward) replace the point.
/// A point whose image is exact stays one point, so at most 2 m points per point. For plots,
/// unreliable_linear_map (vpolytope.hpp) maps to nearest without the extra points.
VPolytope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const VPolytope& V);
/// For square invertible A: normals A^{-T} a_i (rounded) with certified offsets, so the result
/// contains A P and equals it up to rounding. Throws UnsupportedError for singular or non-square
/// A (a projection; use to_vpolytope in 2-D/3-D) and for unbounded P.
HPolytope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const HPolytope& P);

// ------------------------------------------------------------------------------- to_string

/// "Zonotope(dim=2, center=[0, 0], generators=[[1, 0], [0.5, 1]])" (one list per generator).
std::string to_string(const Zonotope& Z);
/// "Ellipsoid(dim=2, center=[..], shape=[[..], [..]])".
std::string to_string(const Ellipsoid& E);
/// "VPolytope(dim=2, points=[[..], ...])" (one list per point).
std::string to_string(const VPolytope& V);
/// "HPolytope(dim=2, rows=[[1, 0 | 1], [0, 1 | inf]])" (a | b per row).
std::string to_string(const HPolytope& P);

// ------------------------------------------------------------------------------- the concept

/// A set type with every operation above.
template <class S>
concept ConvexSet = requires(const S& s, const Eigen::VectorXd& x, const Eigen::MatrixXd& A) {
  { s.dimension() } -> std::convertible_to<int>;
  { support(s, x) } -> std::same_as<double>;
  { outer_box(s) } -> std::same_as<IntervalVector>;
  { contains(s, x) } -> std::same_as<BoolInterval>;
  { linear_map(A, s) } -> std::same_as<S>;
  { to_string(s) } -> std::same_as<std::string>;
};

}  // namespace sets
