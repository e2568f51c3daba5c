#include "sets/models/orthonormal_basis.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "sets/core/error.hpp"

namespace sets {

OrthonormalBasis OrthonormalBasis::fir() { return laguerre(0.0); }

OrthonormalBasis OrthonormalBasis::laguerre(double a) {
  if (!(a > -1 && a < 1))
    throw InputError("Laguerre pole a = " + std::to_string(a) + " must satisfy -1 < a < 1");
  OrthonormalBasis B;
  B.kind_ = a == 0 ? BasisKind::fir : BasisKind::laguerre;
  B.pole_ = a;
  // front = sqrt(1-a^2) z^-1 / (1 - a z^-1), all-pass = (z^-1 - a) / (1 - a z^-1)
  TransferFunction f{Eigen::Vector2d(0, std::sqrt(1 - a * a)), Eigen::Vector2d(1, -a), {std::abs(a)}};
  B.fronts_ = {f};
  B.allpass_ = TransferFunction{Eigen::Vector2d(-a, 1), Eigen::Vector2d(1, -a), {std::abs(a)}};
  return B;
}

OrthonormalBasis OrthonormalBasis::kautz(std::complex<double> xi) {
  if (!(std::abs(xi) < 1) || xi.imag() == 0)
    throw InputError("Kautz pole xi must satisfy |xi| < 1 and Im(xi) != 0 (use Laguerre for a real pole)");
  OrthonormalBasis B;
  B.kind_ = BasisKind::kautz;
  B.pole_ = xi;
  // Wahlberg's two-parameter Kautz functions: b = 2 Re xi / (1 + |xi|^2), c = -|xi|^2,
  // den = 1 - 2 Re xi z^-1 + |xi|^2 z^-2.
  const double r2 = std::norm(xi), b = 2 * xi.real() / (1 + r2), c = -r2;
  const Eigen::Vector3d den(1, -2 * xi.real(), r2);
  const std::vector<double> mod{std::abs(xi), std::abs(xi)};
  B.fronts_ = {TransferFunction{Eigen::Vector3d(0, 1, -b) * std::sqrt(1 - c * c), den, mod},
               TransferFunction{Eigen::Vector3d(0, 0, std::sqrt((1 - c * c) * (1 - b * b))), den, mod}};
  B.allpass_ = TransferFunction{Eigen::Vector3d(r2, -2 * xi.real(), 1), den, mod};
  return B;
}

std::string OrthonormalBasis::describe() const {
  std::ostringstream os;
  switch (kind_) {
    case BasisKind::fir: os << "FIR (F_k = z^-(k+1))"; break;
    case BasisKind::laguerre: os << "Laguerre, pole a = " << pole_.real(); break;
    case BasisKind::kautz:
      os << "Kautz, poles " << pole_.real() << " +- " << std::abs(pole_.imag()) << "i (|xi| = "
         << std::abs(pole_) << ", angle " << std::abs(std::arg(pole_)) << " rad)";
      break;
  }
  return os.str();
}

Eigen::MatrixXd OrthonormalBasis::responses(const Eigen::Ref<const Eigen::VectorXd>& u, int count) const {
  const int m = block();
  Eigen::MatrixXd X(u.size(), count);
  for (int k = 0; k < count; ++k) {
    if (k < m)
      X.col(k) = fronts_[k].filter(u);
    else
      X.col(k) = allpass_.filter(X.col(k - m));
  }
  return X;
}

Eigen::VectorXcd OrthonormalBasis::frequency_responses(double w, int count) const {
  const int m = block();
  Eigen::VectorXcd F(count);
  const std::complex<double> A = allpass_(w);
  for (int k = 0; k < count; ++k) F[k] = k < m ? fronts_[k](w) : F[k - m] * A;
  return F;
}

Eigen::MatrixXd OrthonormalBasis::impulse_responses(int length, int count) const {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(length);
  if (length > 0) d[0] = 1;
  return responses(d, count);
}

double OrthonormalBasis::hinf_bound() const {
  double h = 0;
  for (const auto& f : fronts_) h = std::max(h, f.hinf_bound());
  return h;
}

double OrthonormalBasis::front_derivative_bound() const {
  double d = 0;
  for (const auto& f : fronts_) d = std::max(d, f.derivative_bound());
  return d;
}

double OrthonormalBasis::allpass_derivative_bound() const {
  // |dA/dw| of an inner function is its group delay, sum_i (1-|p|^2)/|e^{iw}-p|^2.
  double g = 0;
  for (double r : allpass_.pole_moduli) g += (1 + r) / (1 - r);
  return g;
}

double OrthonormalBasis::beta1(double M, double rho) const {
  // |dF_k/dw| <= D0 + j H0 L'  with j = floor(k/m) (product rule on front * A^j, |A| = 1).
  const double D0 = front_derivative_bound(), H0 = hinf_bound(), Lp = allpass_derivative_bound();
  const double s0 = 1 / (1 - rho);
  const double s1 = block() == 1 ? rho / ((1 - rho) * (1 - rho))
                                 : (1 + rho) * rho * rho / ((1 - rho * rho) * (1 - rho * rho));
  return M * (D0 * s0 + H0 * Lp * s1);
}

const char* to_string(BasisKind k) {
  switch (k) {
    case BasisKind::fir: return "fir";
    case BasisKind::laguerre: return "laguerre";
    case BasisKind::kautz: return "kautz";
  }
  return "?";
}

}  // namespace sets
