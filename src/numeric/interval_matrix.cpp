#include "sets/numeric/interval_matrix.hpp"

#include <cmath>
#include <string>

#include "sets/core/error.hpp"

namespace sets {

Eigen::VectorXd lower(const IntervalVector& x) {
  return x.unaryExpr([](const Interval& v) { return v.lower(); });
}
Eigen::VectorXd upper(const IntervalVector& x) {
  return x.unaryExpr([](const Interval& v) { return v.upper(); });
}
Eigen::VectorXd midpoint(const IntervalVector& x) {
  return x.unaryExpr([](const Interval& v) { return midpoint(v); });
}
Eigen::VectorXd radius(const IntervalVector& x) {
  return x.unaryExpr([](const Interval& v) { return radius(v); });
}
Eigen::MatrixXd lower(const IntervalMatrix& x) {
  return x.unaryExpr([](const Interval& v) { return v.lower(); });
}
Eigen::MatrixXd upper(const IntervalMatrix& x) {
  return x.unaryExpr([](const Interval& v) { return v.upper(); });
}
Eigen::MatrixXd midpoint(const IntervalMatrix& x) {
  return x.unaryExpr([](const Interval& v) { return midpoint(v); });
}

IntervalVector make_box(const Eigen::Ref<const Eigen::VectorXd>& lo,
                        const Eigen::Ref<const Eigen::VectorXd>& hi) {
  if (lo.size() != hi.size())
    throw InputError("make_box: lower bound has " + std::to_string(lo.size()) +
                      " entries, upper bound " + std::to_string(hi.size()));
  IntervalVector b(lo.size());
  for (Eigen::Index i = 0; i < lo.size(); ++i) {
    if (std::isnan(lo[i]) || std::isnan(hi[i]) || lo[i] > hi[i])
      throw InputError("make_box: coordinate " + std::to_string(i) + " has bounds [" +
                        std::to_string(lo[i]) + ", " + std::to_string(hi[i]) + "]");
    b[i] = Interval(lo[i], hi[i]);
  }
  return b;
}

IntervalVector multiply(const IntervalMatrix& A, const IntervalVector& x) {
  if (A.cols() != x.size()) throw InputError("multiply: dimensions do not match");
  IntervalVector r(A.rows());
  RoundingScope upward;  // pure interval work: one rounding-mode switch per call
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    UnprotectedInterval s(0.0);
    for (Eigen::Index j = 0; j < A.cols(); ++j) s += UnprotectedInterval(A(i, j)) * UnprotectedInterval(x[j]);
    r[i] = s;
  }
  return r;
}

IntervalVector multiply(const Eigen::MatrixXd& A, const IntervalVector& x) {
  if (A.cols() != x.size()) throw InputError("multiply: dimensions do not match");
  IntervalVector r(A.rows());
  RoundingScope upward;  // pure interval work: one rounding-mode switch per call
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    UnprotectedInterval s(0.0);
    for (Eigen::Index j = 0; j < A.cols(); ++j) s += UnprotectedInterval(A(i, j)) * UnprotectedInterval(x[j]);
    r[i] = s;
  }
  return r;
}

bool contains(const IntervalVector& box, const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (box.size() != x.size()) throw InputError("contains: dimensions do not match");
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!(box[i].lower() <= x[i] && x[i] <= box[i].upper())) return false;
  return true;
}

IntervalVector hull(const IntervalVector& a, const IntervalVector& b) {
  if (a.size() != b.size()) throw InputError("hull: dimensions do not match");
  IntervalVector r(a.size());
  for (Eigen::Index i = 0; i < a.size(); ++i) r[i] = sets::hull(a[i], b[i]);
  return r;
}

double volume(const IntervalVector& box) {
  Interval v(1.0);
  for (Eigen::Index i = 0; i < box.size(); ++i) v *= boost::numeric::width(box[i]);
  return v.upper();
}

}  // namespace sets
