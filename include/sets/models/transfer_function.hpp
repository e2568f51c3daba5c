#pragma once
// A rational discrete-time transfer function in z^-1 (SISO, real coefficients): the model type of
// the orthonormal bases (their fronts and inner factor), of the nominal models and weights of the
// H-infinity method, and of the papers' example systems.

#include <Eigen/Core>

#include <complex>
#include <string>
#include <vector>

namespace sets {

/// c(e^{iw}) = sum_k c_k e^{-ikw}, a polynomial in z^-1 on the unit circle (Horner).
std::complex<double> polynomial_at(const Eigen::Ref<const Eigen::VectorXd>& c, double w);
/// sum_k k |c_k|: an upper bound on sup_w |d/dw c(e^{iw})|.
double polynomial_derivative_bound(const Eigen::Ref<const Eigen::VectorXd>& c);

/// G(z) = (b0 + b1 z^-1 + ...) / (1 + a1 z^-1 + ...), a(0) == 1, evaluated at z = e^{iw}.
struct TransferFunction {
  Eigen::VectorXd b, a;
  /// |p_i| of the roots of a when known exactly (the bases know their poles); used by the
  /// closed-form bounds. Empty: those bounds use only the certified grid minimum of |a|.
  std::vector<double> pole_moduli;

  std::complex<double> operator()(double w) const;
  /// d/dw G(e^{iw}).
  std::complex<double> derivative(double w) const;
  /// The roots of z^n a(z^-1) (companion-matrix eigenvalues; throws NumericalError on failure).
  Eigen::VectorXcd poles() const;
  /// Every pole modulus < 1 - margin.
  bool stable(double margin = 0) const;
  /// y = G(q) x with zero initial state.
  Eigen::VectorXd filter(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// sup_w |G| (rigorous: grid maximum plus half a spacing times derivative_bound(), or
  /// sum|b_k| / prod(1 - |p_i|) when that is smaller).
  double hinf_bound() const;
  /// sup_w |dG/dw| <= sum k|b_k|/amin + sum|b_k| sum k|a_k| / amin^2, amin a certified lower
  /// bound of |a(e^{iw})|.
  double derivative_bound() const;
  /// "(b0 + b1 z^-1 ...) / (1 + a1 z^-1 ...)".
  std::string to_string() const;
};

}  // namespace sets
