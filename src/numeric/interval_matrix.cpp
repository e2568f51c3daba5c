#include "sets/numeric/interval_matrix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "sets/core/error.hpp"

namespace sets {

Eigen::VectorXd lower(const IntervalVector& x) {
  return x.unaryExpr([](const Interval& v) { return v.lower(); });
}
Eigen::VectorXd upper(const IntervalVector& x) {
  return x.unaryExpr([](const Interval& v) { return v.upper(); });
}
namespace {

// Midpoints and radii of n intervals, equal bit for bit to the scalar midpoint() and radius()
// but with two rounding-mode switches in all instead of about six per interval: midpoints
// (l + u) / 2 in round-to-nearest (as boost::numeric::median), then radii
// max(u - m, m - l) rounded upward (as the hull of the two outward-rounded differences).
// Entries with an infinite end take the scalar functions (they set their own modes).
bool finite(const Interval& x) { return std::isfinite(x.lower()) && std::isfinite(x.upper()); }

void midpoints_and_radii(const Interval* x, Eigen::Index n, double* mid, double* rad) {
  Interval::traits_type::rounding mode;  // saves the caller's mode, restores it at the end
  mode.to_nearest();
  for (Eigen::Index k = 0; k < n; ++k)
    mid[k] = finite(x[k]) ? (x[k].lower() + x[k].upper()) / 2 : midpoint(x[k]);
  if (!rad) return;
  mode.upward();
  for (Eigen::Index k = 0; k < n; ++k)
    rad[k] = finite(x[k]) ? std::max(x[k].upper() - mid[k], mid[k] - x[k].lower()) : radius(x[k]);
}

}  // namespace

Eigen::VectorXd midpoint(const IntervalVector& x) {
  Eigen::VectorXd m(x.size());
  midpoints_and_radii(x.data(), x.size(), m.data(), nullptr);
  return m;
}
Eigen::VectorXd radius(const IntervalVector& x) {
  Eigen::VectorXd m(x.size()), r(x.size());
  midpoints_and_radii(x.data(), x.size(), m.data(), r.data());
  return r;
}
Eigen::MatrixXd lower(const IntervalMatrix& x) {
  return x.unaryExpr([](const Interval& v) { return v.lower(); });
}
Eigen::MatrixXd upper(const IntervalMatrix& x) {
  return x.unaryExpr([](const Interval& v) { return v.upper(); });
}
Eigen::MatrixXd midpoint(const IntervalMatrix& x) {
  Eigen::MatrixXd m(x.rows(), x.cols());
  midpoints_and_radii(x.data(), x.size(), m.data(), nullptr);
  return m;
}
Eigen::MatrixXd radius(const IntervalMatrix& x) {
  Eigen::MatrixXd m(x.rows(), x.cols()), r(x.rows(), x.cols());
  midpoints_and_radii(x.data(), x.size(), m.data(), r.data());
  return r;
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

namespace {

// A x for a point or interval matrix A: one rounding-mode switch per call (pure interval work).
template <class Matrix>
IntervalVector multiply_enclosure(const Matrix& A, const IntervalVector& x) {
  if (A.cols() != x.size()) throw InputError("multiply: dimensions do not match");
  IntervalVector r(A.rows());
  RoundingScope upward;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    UnprotectedInterval s(0.0);
    for (Eigen::Index j = 0; j < A.cols(); ++j) s += UnprotectedInterval(A(i, j)) * UnprotectedInterval(x[j]);
    r[i] = s;
  }
  return r;
}

}  // namespace

IntervalVector multiply(const IntervalMatrix& A, const IntervalVector& x) { return multiply_enclosure(A, x); }

IntervalVector multiply(const Eigen::MatrixXd& A, const IntervalVector& x) { return multiply_enclosure(A, x); }

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
