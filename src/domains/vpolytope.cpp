#include "sets/domains/vpolytope.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

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

namespace {

// Points whose convex hull contains the box b: its centre c if b is a point, else the 2 m'
// corners c +- m' r_j e_j of a cross-polytope over the m' coordinates of nonzero width (a point
// y of the box has sum_j |y_j - c_j| / (m' r_j) <= 1), each rounded outward.
void append_cross_polytope(const IntervalVector& b, std::vector<Eigen::VectorXd>& out) {
  const auto m = b.size();
  Eigen::VectorXd c(m), r(m);
  int wide = 0;
  for (Eigen::Index j = 0; j < m; ++j) {
    if (!std::isfinite(b[j].lower()) || !std::isfinite(b[j].upper()))
      throw NumericalError("linear_map(VPolytope): the image of a point overflows");
    c[j] = b[j].lower() == b[j].upper() ? b[j].lower() : midpoint(b[j]);
    r[j] = std::max((Interval(b[j].upper()) - c[j]).upper(), (Interval(c[j]) - b[j].lower()).upper());
    wide += r[j] > 0;
  }
  if (wide == 0) {
    out.push_back(c);
    return;
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    if (r[j] == 0) continue;
    const Interval reach = Interval(static_cast<double>(wide)) * r[j];
    Eigen::VectorXd p = c;
    p[j] = (Interval(c[j]) + reach).upper();
    out.push_back(p);
    p[j] = (Interval(c[j]) - reach).lower();
    out.push_back(p);
    if (!std::isfinite(out.end()[-2][j]) || !std::isfinite(p[j]))
      throw NumericalError("linear_map(VPolytope): the image of a point overflows");
  }
}

}  // namespace

VPolytope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const VPolytope& V) {
  if (A.cols() != V.dimension()) throw InputError("linear_map: matrix has the wrong number of columns");
  std::vector<Eigen::VectorXd> points;
  const Eigen::MatrixXd Ad = A;
  for (int k = 0; k < V.num_points(); ++k) append_cross_polytope(multiply(Ad, detail::iv(V.points().col(k))), points);
  Eigen::MatrixXd P(A.rows(), static_cast<Eigen::Index>(points.size()));
  for (std::size_t k = 0; k < points.size(); ++k) P.col(static_cast<Eigen::Index>(k)) = points[k];
  return VPolytope(std::move(P));
}

VPolytope unreliable_linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const VPolytope& V) {
  if (A.cols() != V.dimension()) throw InputError("unreliable_linear_map: matrix has the wrong number of columns");
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
