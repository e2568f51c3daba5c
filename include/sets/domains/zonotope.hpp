#pragma once
// Zonotopes Z = {c + G xi : xi in [-1, 1]^m}: centre c (n) and generator matrix G (n x m).
//
// Guarantees. Every operation that computes a new zonotope (linear_map, minkowski_sum,
// reduce_order, intersect_strip) evaluates the exact result in
// outward-rounded interval arithmetic and adds the rounding error as extra axis-aligned
// generators, so the stored zonotope contains the exact one. Rank-deficient ("flat") generator
// matrices are allowed everywhere.
//
// The generic operations (support, outer_box, contains, linear_map, to_string) are declared in
// set_operations.hpp, the conversions to other set types in conversions.hpp.

#include <Eigen/Core>

#include <optional>
#include <string>

#include "sets/core/bool_interval.hpp"
#include "sets/domains/set_operations.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets {


class Zonotope {
 public:
  Zonotope() = default;
  /// Throws InputError if G has a different number of rows than c or an entry is not finite.
  Zonotope(Eigen::VectorXd center, Eigen::MatrixXd generators);
  /// The box itself (one axis-aligned generator per coordinate with nonzero width); the centre
  /// and radii are rounded so that the zonotope contains the box. Throws on unbounded boxes.
  static Zonotope from_box(const IntervalVector& box);

  int dimension() const { return static_cast<int>(c_.size()); }
  int num_generators() const { return static_cast<int>(G_.cols()); }
  /// Generators per dimension, m / n.
  double order() const { return dimension() ? double(num_generators()) / dimension() : 0.0; }
  const Eigen::VectorXd& center() const { return c_; }
  const Eigen::MatrixXd& generators() const { return G_; }

 private:
  Eigen::VectorXd c_;
  Eigen::MatrixXd G_;
};

Zonotope translate(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& b);
/// Z1 + Z2: centres added, generators concatenated (exact up to rounding of the centre).
Zonotope minkowski_sum(const Zonotope& Z1, const Zonotope& Z2);

/// Order-reduction methods: each keeps the `order*n - n` most important generators and
/// encloses the rest in a parallelotope (a box in Girard's and Combastel's methods, a box in the
/// principal axes of the discarded generators for PCA).
enum class ReductionMethod {
  girard,     // importance ||g||_1 - ||g||_inf (Girard 2005)
  combastel,  // importance ||g||_2 (Combastel 2003)
  pca         // discarded generators boxed in their principal axes (Kopetzki et al. 2017)
};
/// An outer approximation of Z with at most max(n, order*n) generators (order >= 1). Zero
/// generators are dropped first. The result always contains Z.
Zonotope reduce_order(const Zonotope& Z, double order, ReductionMethod method = ReductionMethod::girard);
/// Removes zero generators and merges parallel ones (exact up to rounding; contains Z).
Zonotope compact(const Zonotope& Z);

/// Alamo–Bravo–Camacho (2005) update: an outer zonotope of Z ∩ {x : |y - a^T x| <= delta},
///   c + lambda (y - a^T c) + [(I - lambda a^T) G, delta lambda] B,
/// with lambda = G G^T a / (a^T G G^T a + delta^2) (minimum Frobenius norm of the generators).
/// nullopt when Z and the strip provably do not meet.
std::optional<Zonotope> try_intersect_strip(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& a, double y,
                                            double delta);

static_assert(ConvexSet<Zonotope>);  // the generic operations, sets/domains/set_operations.hpp

}  // namespace sets
