// The verified linear-algebra steps the set types rely on: each bound is checked against the
// quantity it bounds, computed independently (exact rationals, or long double SVDs with a margin
// far smaller than any mistake would make).

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpq.h>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>

#include <cmath>

#include "numeric/verified_linear_algebra.hpp"

namespace {

using sets::Interval;
using sets::IntervalMatrix;
using Q = CGAL::Gmpq;
using MatrixXld = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;

rc::Gen<double> gen_entry() {
  return rc::gen::map(rc::gen::inRange(-1000000, 1000000), [](int v) { return v / 997.0 / 1000.0; });
}

Eigen::MatrixXd gen_matrix(int n) {
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = *gen_entry();
  return A;
}

long double spectral_norm(const MatrixXld& M) {
  return Eigen::JacobiSVD<MatrixXld>(M).singularValues()(0);
}

}  // namespace

RC_GTEST_PROP(VerifiedLinearAlgebra, InverseBoundsHoldForWellConditionedMatrices, ()) {
  const int n = *rc::gen::inRange(1, 6);
  const Eigen::MatrixXd A = gen_matrix(n) + 2.0 * Eigen::MatrixXd::Identity(n, n);
  const MatrixXld inverse = A.cast<long double>().inverse();
  RC_PRE(spectral_norm(inverse) * spectral_norm(A.cast<long double>()) < 1e4L);
  // An approximate inverse with a deliberate error of size up to 1e-3.
  Eigen::MatrixXd X = A.inverse();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) X(i, j) += *gen_entry() * 1e-3;
  const auto deviation = sets::detail::inverse_deviation_bound(A, X);
  const auto norm = sets::detail::inverse_norm_bound(A, X);
  RC_ASSERT(deviation.has_value());
  RC_ASSERT(norm.has_value());
  const long double true_deviation = spectral_norm(inverse - X.cast<long double>());
  RC_ASSERT(static_cast<long double>(*deviation) >= true_deviation * (1 - 1e-12L));
  RC_ASSERT(static_cast<long double>(*norm) >= spectral_norm(inverse) * (1 - 1e-12L));
}

TEST(VerifiedLinearAlgebra, AnInverseThatIsNotOneCannotBeVerified) {
  const Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  EXPECT_FALSE(sets::detail::inverse_deviation_bound(A, Eigen::Matrix2d::Zero()).has_value());
  EXPECT_FALSE(sets::detail::inverse_norm_bound(A, 3.0 * Eigen::Matrix2d::Identity()).has_value());
  const auto exact = sets::detail::inverse_norm_bound(A, A);
  ASSERT_TRUE(exact.has_value());
  // The bound goes through the Frobenius norm of X (>= the spectral norm): sqrt(2) for I_2.
  EXPECT_GE(*exact, std::sqrt(2.0));
  EXPECT_LE(*exact, std::sqrt(2.0) * (1 + 1e-12));
}

RC_GTEST_PROP(VerifiedLinearAlgebra, NormsAndDotEncloseEverySampledMember, ()) {
  const int m = *rc::gen::inRange(1, 5), n = *rc::gen::inRange(1, 5);
  IntervalMatrix M(m, n);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) {
      const double a = *gen_entry(), b = *gen_entry();
      M(i, j) = Interval(std::min(a, b), std::max(a, b));
    }
  const double frobenius = sets::detail::frobenius_upper(M);
  const sets::IntervalVector column = M.col(0);
  const double norm = sets::detail::norm_upper(column);
  for (int sample = 0; sample < 6; ++sample) {
    Q sum_squares(0), column_squares(0), dot(0);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < n; ++j) {
        const Interval& e = M(i, j);
        const double v = (sample + i + j) % 2 ? e.lower() : e.upper();
        sum_squares += Q(v) * Q(v);
        if (j == 0) column_squares += Q(v) * Q(v), dot += Q(v) * Q(e.upper());
      }
    RC_ASSERT(Q(frobenius) * Q(frobenius) >= sum_squares);
    RC_ASSERT(Q(norm) * Q(norm) >= column_squares);
    const Interval d = sets::detail::dot(column, sets::upper(column).cast<Interval>());
    RC_ASSERT(Q(d.lower()) <= dot);
    RC_ASSERT(dot <= Q(d.upper()));
  }
}

RC_GTEST_PROP(VerifiedLinearAlgebra, UpperSymmetricBoundDominatesEverySymmetricMember, ()) {
  const int n = *rc::gen::inRange(1, 6);
  IntervalMatrix P(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) {
      const double a = *gen_entry(), b = *gen_entry();
      P(i, j) = P(j, i) = Interval(std::min(a, b), std::max(a, b));
    }
  const Eigen::MatrixXd M = sets::detail::upper_symmetric_bound(P);
  RC_ASSERT((M - M.transpose()).cwiseAbs().maxCoeff() == 0.0);
  for (int sample = 0; sample < 6; ++sample) {
    MatrixXld T(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j <= i; ++j)
        T(i, j) = T(j, i) = ((sample * 7 + i * 3 + j) % 3 == 0) ? P(i, j).lower() : P(i, j).upper();
    const MatrixXld gap = M.cast<long double>() - T;
    const long double lowest = Eigen::SelfAdjointEigenSolver<MatrixXld>(gap).eigenvalues().minCoeff();
    RC_ASSERT(lowest >= -1e-15L * (1 + spectral_norm(M.cast<long double>())));
  }
}
