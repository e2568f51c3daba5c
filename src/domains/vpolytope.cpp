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

IntervalVector outer_box(const VPolytope& V) {
  IntervalVector b(V.dimension());
  for (int i = 0; i < V.dimension(); ++i) b[i] = Interval(V.points().row(i).minCoeff(), V.points().row(i).maxCoeff());
  return b;
}

double support(const VPolytope& V, const Eigen::Ref<const Eigen::VectorXd>& d) {
  if (d.size() != V.dimension()) throw InputError("support: direction has the wrong dimension");
  const IntervalVector di = detail::iv(d);
  double best = -inf;
  for (int k = 0; k < V.num_points(); ++k)
    best = std::max(best, detail::dot(di, detail::iv(V.points().col(k))).upper());
  return best;
}

BoolInterval contains(const VPolytope& V, const Eigen::Ref<const Eigen::VectorXd>& x) {
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

VPolytope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const VPolytope& V) {
  if (A.cols() != V.dimension()) throw InputError("linear_map: matrix has the wrong number of columns");
  return VPolytope(A * V.points());
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
