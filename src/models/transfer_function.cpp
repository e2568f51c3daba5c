#include "sets/models/transfer_function.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "sets/core/error.hpp"

namespace sets {

namespace {
constexpr double pi = std::numbers::pi;
constexpr int grid_points = 8192;  // grid of the certified sup / inf bounds

// prod (1 - |p_i|) <= |a(e^{iw})| when the moduli are known; 0 (no information) otherwise.
double closed_form_amin(const std::vector<double>& moduli) {
  if (moduli.empty()) return 0;
  double m = 1;
  for (double r : moduli) m *= (1 - r);
  return m;
}
// Rigorous lower bound on min |a(e^{-iw})|: the larger of prod(1-|p_i|) and the grid minimum
// less (spacing/2) sup|a'| (real coefficients: |a| is even in w, so [0, pi] suffices).
double a_min(const TransferFunction& f) {
  double g = std::numeric_limits<double>::infinity();
  for (int i = 0; i < grid_points; ++i) g = std::min(g, std::abs(polynomial_at(f.a, pi * i / (grid_points - 1))));
  return std::max(closed_form_amin(f.pole_moduli), g - 0.5 * pi / (grid_points - 1) * polynomial_derivative_bound(f.a));
}
}  // namespace

std::complex<double> polynomial_at(const Eigen::Ref<const Eigen::VectorXd>& c, double w) {
  std::complex<double> s = 0;
  for (Eigen::Index k = c.size() - 1; k >= 0; --k) s = s * std::polar(1.0, -w) + c[k];
  return s;
}

double polynomial_derivative_bound(const Eigen::Ref<const Eigen::VectorXd>& c) {
  double s = 0;
  for (Eigen::Index k = 0; k < c.size(); ++k) s += k * std::abs(c[k]);
  return s;
}

std::complex<double> TransferFunction::operator()(double w) const { return polynomial_at(b, w) / polynomial_at(a, w); }

std::complex<double> TransferFunction::derivative(double w) const {
  std::complex<double> db = 0, da = 0;
  for (Eigen::Index k = 1; k < b.size(); ++k) db += -std::complex<double>(0, k) * b[k] * std::polar(1.0, -k * w);
  for (Eigen::Index k = 1; k < a.size(); ++k) da += -std::complex<double>(0, k) * a[k] * std::polar(1.0, -k * w);
  const auto B = polynomial_at(b, w), A = polynomial_at(a, w);
  return (db * A - B * da) / (A * A);
}

Eigen::VectorXcd TransferFunction::poles() const {
  // a = [1, a1, ..., an]: the roots of z^n + a1 z^{n-1} + ... + an.
  const Eigen::Index n = a.size() - 1;
  if (n <= 0) return Eigen::VectorXcd(0);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) C(0, i) = -a[i + 1] / a[0];
  for (Eigen::Index i = 1; i < n; ++i) C(i, i - 1) = 1;
  Eigen::EigenSolver<Eigen::MatrixXd> es(C, false);
  if (es.info() != Eigen::Success) throw NumericalError("root finding failed (companion eigenvalues)");
  return es.eigenvalues();
}

bool TransferFunction::stable(double margin) const {
  const auto p = poles();
  for (Eigen::Index i = 0; i < p.size(); ++i)
    if (!(std::abs(p[i]) < 1 - margin)) return false;
  return true;
}

Eigen::VectorXd TransferFunction::filter(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  const Eigen::Index N = x.size();
  Eigen::VectorXd y(N);
  for (Eigen::Index t = 0; t < N; ++t) {
    double s = 0;
    for (Eigen::Index k = 0; k < b.size() && k <= t; ++k) s += b[k] * x[t - k];
    for (Eigen::Index k = 1; k < a.size() && k <= t; ++k) s -= a[k] * y[t - k];
    y[t] = s;
  }
  return y;
}

double TransferFunction::derivative_bound() const {
  const double m = a_min(*this);
  return polynomial_derivative_bound(b) / m + b.cwiseAbs().sum() * polynomial_derivative_bound(a) / (m * m);
}

double TransferFunction::hinf_bound() const {
  // Grid maximum plus (spacing/2) sup|f'|: tight, and rigorous given derivative_bound().
  double g = 0;
  for (int i = 0; i < grid_points; ++i) g = std::max(g, std::abs((*this)(pi * i / (grid_points - 1))));
  const double sampled = g + 0.5 * pi / (grid_points - 1) * derivative_bound();
  const double amin = closed_form_amin(pole_moduli);
  return amin > 0 ? std::min(b.cwiseAbs().sum() / amin, sampled) : sampled;
}

std::string TransferFunction::to_string() const {
  auto poly = [](const Eigen::VectorXd& c) {
    std::ostringstream p;
    p.precision(6);
    for (Eigen::Index k = 0; k < c.size(); ++k) {
      if (k) p << (c[k] < 0 ? " - " : " + ") << std::abs(c[k]) << " z^-" << k;
      else p << c[k];
    }
    return p.str();
  };
  std::ostringstream os;
  os << "(" << poly(b) << ") / (" << poly(a) << ")";
  return os.str();
}

}  // namespace sets
