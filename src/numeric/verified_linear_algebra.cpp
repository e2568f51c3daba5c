#include "numeric/verified_linear_algebra.hpp"

#include <algorithm>
#include <cmath>

namespace sets::detail {

// The loops below are pure interval work: one rounding-mode switch per call (RoundingScope), not
// three per operation; the results are the same.
using I = UnprotectedInterval;

double frobenius_upper(const IntervalMatrix& M) {
  RoundingScope upward;
  I s(0.0);
  for (Eigen::Index j = 0; j < M.cols(); ++j)
    for (Eigen::Index i = 0; i < M.rows(); ++i) {
      const double m = std::max(std::abs(M(i, j).lower()), std::abs(M(i, j).upper()));
      s += I(m) * I(m);
    }
  return boost::numeric::sqrt(s).upper();
}

double norm_upper(const IntervalVector& v) {
  RoundingScope upward;
  I s(0.0);
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    const double m = std::max(std::abs(v[i].lower()), std::abs(v[i].upper()));
    s += I(m) * I(m);
  }
  return boost::numeric::sqrt(s).upper();
}

IntervalMatrix multiply(const IntervalMatrix& A, const IntervalMatrix& B) {
  IntervalMatrix C(A.rows(), B.cols());
  RoundingScope upward;
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    for (Eigen::Index j = 0; j < B.cols(); ++j) {
      I s(0.0);
      for (Eigen::Index k = 0; k < A.cols(); ++k) s += I(A(i, k)) * I(B(k, j));
      C(i, j) = s;
    }
  return C;
}

Interval dot(const IntervalVector& a, const IntervalVector& b) {
  RoundingScope upward;
  I s(0.0);
  for (Eigen::Index i = 0; i < a.size(); ++i) s += I(a[i]) * I(b[i]);
  return s;
}

std::optional<double> inverse_deviation_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& X) {
  const auto n = A.rows();
  IntervalMatrix E = multiply(detail::im(X), detail::im(A));
  {
    RoundingScope upward;
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < n; ++j) E(i, j) = (i == j ? I(1.0) : I(0.0)) - I(E(i, j));
  }
  const double alpha = frobenius_upper(E);
  if (!(alpha < 1)) return std::nullopt;
  const double xn = frobenius_upper(detail::im(X));
  return (Interval(xn) * Interval(alpha) / (Interval(1.0) - Interval(alpha))).upper();
}

std::optional<double> inverse_norm_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& X) {
  const auto dev = inverse_deviation_bound(A, X);
  if (!dev) return std::nullopt;
  return (Interval(frobenius_upper(detail::im(X))) + Interval(*dev)).upper();
}

Eigen::MatrixXd upper_symmetric_bound(const IntervalMatrix& P) {
  // Midpoint M of the (symmetrised) enclosure; the true T satisfies ||T - M||_2 <= ||rad||_F,
  // so M + ||rad||_F I (diagonal rounded up) dominates T in the Loewner order.
  const auto n = P.rows();
  Eigen::MatrixXd M(n, n);
  IntervalMatrix D(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i; j < n; ++j) {
      const Interval h = hull(P(i, j), P(j, i));
      const double m = midpoint(h);
      M(i, j) = M(j, i) = m;
      D(i, j) = D(j, i) = h - Interval(m);
    }
  const double eps = frobenius_upper(D);
  for (Eigen::Index i = 0; i < n; ++i) M(i, i) = (Interval(M(i, i)) + Interval(eps)).upper();
  return M;
}

}  // namespace sets::detail
