#include "sets/domains/vpolytope.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/numeric/lp_certificate.hpp"
#include "numeric/verified_linear_algebra.hpp"

namespace sets {

VPolytope::VPolytope(Eigen::MatrixXd points) : V_(std::move(points)) {
  if (V_.cols() == 0) throw InputError("VPolytope: no points (the empty set has no V-representation)");
  if (!V_.allFinite()) throw InputError("VPolytope: a point has a NaN or infinite coordinate");
}

VPolytope to_vpolytope(const IntervalVector& box) {
  const auto n = box.size();
  if (n > 20) throw UnsupportedError("to_vpolytope(box): 2^" + std::to_string(n) + " corners is too many");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isfinite(box[i].lower()) || !std::isfinite(box[i].upper()))
      throw UnsupportedError("to_vpolytope(box): coordinate " + std::to_string(i) + " is unbounded");
  Eigen::MatrixXd V(n, 1L << n);
  for (long k = 0; k < (1L << n); ++k)
    for (Eigen::Index i = 0; i < n; ++i) V(i, k) = (k >> i) & 1 ? box[i].upper() : box[i].lower();
  return VPolytope(V);
}

IntervalVector outer_box(const VPolytope& V) {
  IntervalVector b(V.dimension());
  for (int i = 0; i < V.dimension(); ++i) b[i] = Interval(V.points().row(i).minCoeff(), V.points().row(i).maxCoeff());
  return b;
}

double support(const VPolytope& V, const Eigen::VectorXd& d) {
  if (d.size() != V.dimension()) throw InputError("support: direction has the wrong dimension");
  const IntervalVector di = detail::iv(d);
  double best = -inf;
  for (int k = 0; k < V.num_points(); ++k)
    best = std::max(best, detail::dot(di, detail::iv(V.points().col(k))).upper());
  return best;
}

BoolInterval contains(const VPolytope& V, const Eigen::VectorXd& x) {
  if (x.size() != V.dimension()) throw InputError("contains: point has the wrong dimension");
  if (!x.allFinite()) throw InputError("contains: point has a NaN or infinite entry");
  // x = V lambda, sum lambda = 1, lambda >= 0: the data are doubles, so the question has an
  // exact answer; it is given only with an exact certificate (a lambda solved in rationals, or
  // a Farkas certificate of the system's emptiness), else unknown.
  const int k = V.num_points();
  LinearProgram lp;
  lp.add_variables(k, 0.0, inf);
  lp.add_rows(V.points(), x, x);
  lp.add_row(Eigen::VectorXd::Ones(k), 1.0, 1.0);
  return !certified_is_empty(lp);
}

VPolytope linear_map(const Eigen::MatrixXd& A, const VPolytope& V) {
  if (A.cols() != V.dimension()) throw InputError("linear_map: matrix has the wrong number of columns");
  return VPolytope(A * V.points());
}

VPolytope to_vpolytope(const Zonotope& Z) {
  if (Z.dimension() == 2) return VPolytope(polygon_vertices(Z));
  if (Z.dimension() == 1) {
    const auto b = outer_box(Z);
    Eigen::MatrixXd V(1, 2);
    V << b[0].lower(), b[0].upper();
    return VPolytope(V);
  }
  if (Z.dimension() != 3) throw UnsupportedError("to_vpolytope(Zonotope): only 1-3 dimensions");
  // Small generator sets: all 2^m sums, then the exact hull; otherwise through the facets.
  const Zonotope C = compact(Z);
  const int m = C.num_generators();
  if (m <= 12) {
    Eigen::MatrixXd P(3, 1 << m);
    for (int mask = 0; mask < (1 << m); ++mask) {
      Eigen::VectorXd xi(m);
      for (int j = 0; j < m; ++j) xi[j] = (mask >> j) & 1 ? 1.0 : -1.0;
      P.col(mask) = C.center() + C.generators() * xi;
    }
    return convex_hull(VPolytope(P));
  }
  return to_vpolytope(to_hpolytope(Z));
}

Eigen::MatrixXd polygon_vertices(const VPolytope& V) {
  if (V.dimension() != 2) throw InputError("polygon_vertices: the polytope is not 2-D");
  return convex_hull(V).points();
}

Eigen::MatrixXd polygon_vertices(const HPolytope& P) {
  if (P.dimension() != 2) throw InputError("polygon_vertices: the polytope is not 2-D");
  return polygon_vertices(to_vpolytope(P));
}

std::string to_string(const VPolytope& V) {
  std::ostringstream os;
  os.precision(17);
  os << "VPolytope(dim=" << V.dimension() << ", points=[";
  for (int k = 0; k < V.num_points(); ++k) {
    os << (k ? ", [" : "[");
    for (int i = 0; i < V.dimension(); ++i) os << (i ? ", " : "") << V.points()(i, k);
    os << "]";
  }
  os << "])";
  return os.str();
}

}  // namespace sets
