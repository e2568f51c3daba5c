#pragma once
// Ellipsoids {x : (x-c)^T P^{-1} (x-c) <= 1} with P symmetric positive semidefinite.
//
// The set is c + P^{1/2} B (B the unit ball), which stays meaningful when P is singular: a flat
// (zero-volume) ellipsoid lying in c + range(P). Nothing here inverts P unless it has to.
//
// Guarantees. Operations that produce a new ellipsoid from an old one (linear_map,
// intersect_strip, minkowski_sum, from_level_set) compute the exact result's centre and shape in
// outward-rounded interval arithmetic and then enlarge the stored shape just enough (a multiple
// of the identity, and a ball for the centre's uncertainty) that the stored ellipsoid contains
// the exact one. `support` and `outer_box` are rigorous upper bounds; `contains` answers
// yes/no only when it can prove it. `project` is exact (a sub-block of P). `slice` and `volume`
// are computed in floating point (approximate; see their comments).
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

class Ellipsoid {
 public:
  Ellipsoid() = default;
  /// {x : (x-c)^T P^{-1} (x-c) <= 1}. Throws InputError if sizes disagree, an entry is not
  /// finite, P is not symmetric (relative 1e-9; it is then symmetrised) or P has an
  /// eigenvalue below -1e-9 ||P|| (not positive semidefinite).
  Ellipsoid(Eigen::VectorXd center, Eigen::MatrixXd shape);

  /// Quadratic level set {theta : (theta-theta0)^T R (theta-theta0) <= gamma}, R symmetric
  /// positive definite, gamma >= 0: the ellipsoid with P = gamma R^{-1}. The inverse is
  /// verified and the stored P enlarged so that the result contains the level set.
  static Ellipsoid from_level_set(const Eigen::Ref<const Eigen::VectorXd>& theta0,
                                  const Eigen::Ref<const Eigen::MatrixXd>& R, double gamma);
  /// The ball of radius r around c.
  static Ellipsoid ball(const Eigen::Ref<const Eigen::VectorXd>& c, double r);

  int dimension() const { return static_cast<int>(c_.size()); }
  const Eigen::VectorXd& center() const { return c_; }
  const Eigen::MatrixXd& shape() const { return P_; }

 private:
  Eigen::VectorXd c_;
  Eigen::MatrixXd P_;
};

/// Which ellipsoid `intersect_strip` (and `minkowski_sum`) keeps from the one-parameter family
/// that contains the exact set.
enum class EllipsoidCriterion { min_volume, min_trace };

/// Exact projection (shadow) onto the listed coordinates, in that order: {x_K : x in E} is the
/// ellipsoid with centre c_K and shape P_KK. Throws InputError for an index out of range.
Ellipsoid project(const Ellipsoid& E, const std::vector<int>& coords);

/// Slice: {x_K : x in E, x_F = v} with F the coordinates not listed (increasing order) and v
/// their fixed values. Via the Schur complement of the level-set matrix P^{-1} (equivalently the
/// conditional-Gaussian formulas in P): centre c_K + P_KF P_FF^+ (v - c_F), shape
/// (1 - (v-c_F)^T P_FF^+ (v-c_F)) (P_KK - P_KF P_FF^+ P_FK). nullopt when the slice is empty
/// (also when v - c_F is off range(P_FF), i.e. outside a flat ellipsoid). Floating point:
/// the slice is exact up to rounding, not enlarged. A slice is contained in the projection.
std::optional<Ellipsoid> slice(const Ellipsoid& E, const std::vector<int>& coords,
                               const Eigen::Ref<const Eigen::VectorXd>& fixed_values_of_other_coords);

/// Volume (Lebesgue measure) = vol(unit ball) sqrt(det P); 0 for a flat ellipsoid.
/// Floating point (approximate, not a bound).
double volume(const Ellipsoid& E);
/// Smallest eigenvalue over largest (0 for flat ellipsoids); floating point.
double flatness(const Ellipsoid& E);

/// E + b.
Ellipsoid translate(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& b);

/// Outer approximation of the Minkowski sum E1 + E2 by the ellipsoid
/// (1 + 1/p) P1 + (1 + p) P2 with p chosen by the criterion (min-trace: closed form;
/// min-volume: 1-D search). Always contains the sum.
Ellipsoid minkowski_sum(const Ellipsoid& E1, const Ellipsoid& E2,
                        EllipsoidCriterion criterion = EllipsoidCriterion::min_trace);

struct StripOptions {
  EllipsoidCriterion criterion = EllipsoidCriterion::min_volume;
};

/// Optimal bounding ellipsoid (OBE) of E intersected with the strip {x : |y - a^T x| <= delta}
/// (Fogel & Huang 1982; Schweppe's family): for q >= 0 the ellipsoid
///   (x-c)^T P^{-1} (x-c) + q (y - a^T x)^2 / delta^2 <= 1 + q
/// contains the intersection; q is chosen for minimum volume (closed form of Fogel & Huang) or
/// minimum trace (1-D search). q = 0 (E returned unchanged) when the strip does not cut E enough
/// to help. Works for singular P and delta = 0 (a hyperplane). The result is enlarged for
/// rounding, so it always contains E ∩ strip. nullopt when E ∩ strip is provably empty.
std::optional<Ellipsoid> try_intersect_strip(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& a, double y,
                                             double delta, const StripOptions& options = {});
/// As try_intersect_strip, but throws EmptySetError when the intersection is provably empty
/// (the data falsify the model).
Ellipsoid intersect_strip(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& a, double y, double delta,
                          const StripOptions& options = {});
Ellipsoid intersect_strip(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& a, double y, double delta,
                          EllipsoidCriterion criterion);

static_assert(ConvexSet<Ellipsoid>);  // the generic operations, sets/domains/set_operations.hpp

}  // namespace sets
