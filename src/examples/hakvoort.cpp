#include "sets/examples/hakvoort.hpp"

#include <cmath>
#include <numbers>

namespace sets::hakvoort {

TransferFunction system() {
  const double r1 = 0.97, w1 = 0.6, r2 = 0.8, w2 = 0.9;
  const Eigen::Vector3d d1(1, -2 * r1 * std::cos(w1), r1 * r1), d2(1, -2 * r2 * std::cos(w2), r2 * r2);
  TransferFunction G;
  G.a = Eigen::VectorXd::Zero(5);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) G.a[i + k] += d1[i] * d2[k];  // the product of the two quadratics
  G.b = Eigen::VectorXd::Zero(3);
  G.b << 0, 0.05, 0.025;
  return G;
}

namespace {

Eigen::VectorXd lfilter(const Eigen::VectorXd& b, const Eigen::VectorXd& a, const Eigen::VectorXd& x) {
  TransferFunction f{b, a, {}};
  return f.filter(x);
}

// Coefficients g0(k) = <G0, F_k> by the trapezoid rule on a dense grid (G0 and F_k are smooth).
Eigen::VectorXd basis_coefficients(const TransferFunction& G, const OrthonormalBasis& B, int count) {
  const int P = 1 << 14;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(count);
  for (int i = 0; i < P; ++i) {
    const double w = 2 * std::numbers::pi * i / P;
    const Eigen::VectorXcd F = B.frequency_responses(w, count);
    const std::complex<double> Gw = G(w);
    for (int k = 0; k < count; ++k) g[k] += (Gw * std::conj(F[k])).real() / P;
  }
  return g;
}

}  // namespace

Data simulate(const TransferFunction& G, int N, double noise, bool bounded, std::mt19937_64& rng) {
  const int pre = 3000, T = N + pre;
  std::uniform_real_distribution<double> U(-1, 1);
  std::normal_distribution<double> Nn(0, 1);
  Eigen::VectorXd u(T), e(T);
  for (int t = 0; t < T; ++t) u[t] = U(rng);
  for (int t = 0; t < T; ++t) e[t] = bounded ? noise * U(rng) : noise * Nn(rng);
  const Eigen::VectorXd y0 = lfilter(G.b, G.a, u);
  const Eigen::VectorXd v = lfilter(Eigen::VectorXd::Ones(1), Eigen::Vector2d(1, -0.7), e);
  return {u.tail(N), (y0 + v).tail(N)};
}

HinfPriors priors_for(const TransferFunction& G, const OrthonormalBasis& basis, HinfPriors p, std::string& note) {
  const Eigen::VectorXd g = basis_coefficients(G, basis, 200);
  double Mneed = 0;
  for (int k = 0; k < g.size(); ++k) Mneed = std::max(Mneed, std::abs(g[k]) / std::pow(p.rho, k));
  if (p.M <= 0) p.M = 1.2 * Mneed;
  const bool given_rho_ic = p.rho_ic > 0;
  if (!given_rho_ic) p.rho_ic = 0.975;
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(3000);
  delta[0] = 1;
  const Eigen::VectorXd imp = lfilter(G.b, G.a, delta);
  double Mic = 0;
  for (int s = 1; s < imp.size(); ++s) Mic = std::max(Mic, std::abs(imp[s]) / std::pow(p.rho_ic, s));
  if (p.M_ic <= 0) p.M_ic = 1.2 * Mic;
  note = "prior check on the true system: max_k |g0(k)|/rho^k = " + std::to_string(Mneed) +
         (Mneed <= p.M ? " <= M (holds)" : " > M (VIOLATED)");
  return p;
}

}  // namespace sets::hakvoort
