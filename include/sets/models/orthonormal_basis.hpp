#pragma once
// Orthonormal basis functions F_k(z) for linearly parametrised models G(z) = sum_k g(k) F_k(z):
// FIR (F_k = z^-(k+1)), Laguerre (one real pole a) and Kautz (one complex pole pair xi, conj xi).
//
// All three share one structure used by the error bounds in hinf_bound.hpp: with block size m
// (1 for FIR/Laguerre, 2 for Kautz), F_k = front_{k mod m}(z) * A(z)^{floor(k/m)}, where A is an
// inner (all-pass) function. Every F_k has unit l2 norm (orthonormal in H2), |A(e^{iw})| = 1, and
// the bounds below are closed-form and rigorous (docs/methods/hinf-bound.md, "Basis bounds").

#include <Eigen/Core>

#include <complex>
#include <string>
#include <vector>

#include "sets/models/transfer_function.hpp"

namespace sets {

enum class BasisKind { fir, laguerre, kautz };

/// The former name of TransferFunction (kept for source compatibility).
using DiscreteTf = TransferFunction;

class OrthonormalBasis {
 public:
  static OrthonormalBasis fir();
  /// Throws InputError unless -1 < a < 1.
  static OrthonormalBasis laguerre(double a);
  /// Throws InputError unless |xi| < 1 and Im xi != 0.
  static OrthonormalBasis kautz(std::complex<double> xi);

  BasisKind kind() const { return kind_; }
  int block() const { return static_cast<int>(fronts_.size()); }
  std::string describe() const;

  /// Zero-state responses x_k = F_k(q) u, k = 0..count-1, as the columns of an N x count matrix.
  Eigen::MatrixXd responses(const Eigen::Ref<const Eigen::VectorXd>& u, int count) const;
  /// F_k(e^{iw}) for k = 0..count-1.
  Eigen::VectorXcd frequency_responses(double w, int count) const;
  /// Impulse responses f_k(s), s = 0..length-1 (column k).
  Eigen::MatrixXd impulse_responses(int length, int count) const;

  /// H0 >= sup_w |F_k(e^{iw})| for every k.
  double hinf_bound() const;
  /// D0 >= sup_w |d front_i/dw| over the fronts.
  double front_derivative_bound() const;
  /// L' >= sup_w |dA/dw| (group delay of the inner factor: sum_i (1+|p_i|)/(1-|p_i|)).
  double allpass_derivative_bound() const;
  /// beta1 = sum_k M rho^k sup|dF_k/dw|, eq. (12), in closed form (see the method doc).
  double beta1(double M, double rho) const;
  /// The fronts and the inner factor (for frequency-local bounds, hinf_bound/error_bound.cpp).
  const std::vector<TransferFunction>& fronts() const { return fronts_; }
  const TransferFunction& allpass() const { return allpass_; }

 private:
  BasisKind kind_ = BasisKind::fir;
  std::complex<double> pole_ = 0;
  std::vector<TransferFunction> fronts_;
  TransferFunction allpass_;
};

const char* to_string(BasisKind k);

}  // namespace sets
