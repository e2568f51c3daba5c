#include "sets/methods/hinf_bound/hinf_bound.hpp"

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>

#include <algorithm>
#include <iterator>
#include <cmath>
#include <numbers>
#include <sstream>

#include "sets/core/error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/linear_program.hpp"

namespace sets {

namespace {
constexpr double pi = std::numbers::pi;

std::string num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

// sum_k k^2 |c_k| >= sup_w |d^2/dw^2 c(e^{iw})|.
double polynomial_second_derivative_bound(const Eigen::VectorXd& c) {
  double s = 0;
  for (Eigen::Index k = 0; k < c.size(); ++k) s += double(k) * k * std::abs(c[k]);
  return s;
}
// Rigorous lower bound on min_w |c(e^{-iw})| over [0, pi] (real coefficients: |c| is even in w):
// g = |c|^2 has |g''| <= 2((sum k|c_k|)^2 + sum|c_k| sum k^2|c_k|), and between two grid points
// g >= min(ends) - spacing^2/8 sup|g''|.
double poly_min_modulus(const Eigen::Ref<const Eigen::VectorXd>& c) {
  const double l1 = polynomial_derivative_bound(c), g2 = 2 * (l1 * l1 + c.cwiseAbs().sum() * polynomial_second_derivative_bound(c));
  for (int points = 8192; points <= (1 << 19); points *= 8) {  // refine until certified
    double m = inf;
    for (int i = 0; i < points; ++i) m = std::min(m, std::norm(polynomial_at(c, pi * i / (points - 1))));
    const double d = pi / (points - 1), lo = m - d * d / 8 * g2;
    if (lo > 0) return std::sqrt(lo);
  }
  return 0;
}

}  // namespace

// ------------------------------------------------------------------ checks
void check_frequency_grid(const Eigen::Ref<const Eigen::VectorXd>& grid) {
  if (grid.size() < 2) throw InputError("frequency grid: needs at least 2 frequencies, got " + num(grid.size()));
  for (Eigen::Index j = 0; j < grid.size(); ++j) {
    if (!std::isfinite(grid[j]) || grid[j] < 0 || grid[j] > pi)
      throw InputError("frequency grid: w[" + num(j) + "] = " + num(grid[j]) +
                       " rad/sample is outside [0, pi]");
    if (j > 0 && !(grid[j] > grid[j - 1]))
      throw InputError("frequency grid: w[" + num(j) + "] = " + num(grid[j]) +
                       " is not larger than w[" + num(j - 1) + "] (the grid must increase strictly)");
  }
}

void check_priors(const HinfPriors& p) {
  if (!(p.rho > 0 && p.rho < 1)) throw InputError("prior rho = " + num(p.rho) + ": the tail decay rate must satisfy 0 < rho < 1");
  if (!(p.M > 0 && std::isfinite(p.M))) throw InputError("prior M = " + num(p.M) + " must be positive and finite");
  if (!(p.u_bar >= 0 && std::isfinite(p.u_bar))) throw InputError("prior u_bar = " + num(p.u_bar) + " must be >= 0");
  if (p.rho_ic > 0 && !(p.rho_ic < 1))
    throw InputError("prior rho_ic = " + num(p.rho_ic) + ": the impulse-response decay rate must satisfy 0 < rho_ic < 1");
  if (p.M_ic > 0 && !std::isfinite(p.M_ic)) throw InputError("prior M_ic must be finite");
}

// ------------------------------------------------------------------ regions
bool FrequencyRegion::contains(std::complex<double> g, double tol) const {
  const std::complex<double> d = g - centre;
  if (shape == RegionShape::rectangle)
    return std::abs(d.real()) <= half_re * (1 + tol) + tol && std::abs(d.imag()) <= half_im * (1 + tol) + tol;
  const Eigen::Vector2d x(d.real(), d.imag());
  return x.dot(Q.ldlt().solve(x)) <= 1 + tol;
}

double FrequencyRegion::max_distance(std::complex<double> p) const {
  const std::complex<double> d = centre - p;
  if (shape == RegionShape::rectangle) {
    // The farthest point of a rectangle from p is a vertex.
    const double re = std::abs(d.real()) + half_re, im = std::abs(d.imag()) + half_im;
    return std::hypot(re, im);
  }
  // max |L u + d| over |u| = 1 with Q = L L^T. g(t) = |L u(t) + d|^2 is smooth with
  // |g''| <= C := 4 ||L^T L||_F + 2 |d| ||L||_F, so max g <= max over samples (spacing s) + C s^2/8.
  Eigen::LLT<Eigen::Matrix2d> llt(Q + 1e-300 * Eigen::Matrix2d::Identity());
  const Eigen::Matrix2d L = llt.matrixL();
  const Eigen::Vector2d dv(d.real(), d.imag());
  const int n = 2048;
  double g = 0;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * pi * i / n;
    g = std::max(g, (L * Eigen::Vector2d(std::cos(t), std::sin(t)) + dv).squaredNorm());
  }
  const double s = 2 * pi / n;
  const double C = 4 * (L.transpose() * L).norm() + 2 * dv.norm() * L.norm();
  return std::sqrt(g + C * s * s / 8);
}

std::vector<std::complex<double>> FrequencyRegion::boundary(int points) const {
  std::vector<std::complex<double>> out;
  if (shape == RegionShape::rectangle) {
    const double r[5][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}, {1, 1}};
    for (auto& c : r) out.push_back(centre + std::complex<double>(c[0] * half_re, c[1] * half_im));
    return out;
  }
  Eigen::LLT<Eigen::Matrix2d> llt(Q + 1e-300 * Eigen::Matrix2d::Identity());
  const Eigen::Matrix2d L = llt.matrixL();
  for (int i = 0; i <= points; ++i) {
    const double t = 2 * pi * i / points;
    const Eigen::Vector2d x = L * Eigen::Vector2d(std::cos(t), std::sin(t));
    out.push_back(centre + std::complex<double>(x[0], x[1]));
  }
  return out;
}

// ------------------------------------------------------------------ step 1
namespace {

void check_step1_inputs(const Eigen::Ref<const Eigen::VectorXd>& u, const Eigen::Ref<const Eigen::VectorXd>& y,
                        const Eigen::Ref<const Eigen::VectorXd>& instrument, int order,
                        const Eigen::Ref<const Eigen::VectorXd>& grid, const HinfPriors& priors,
                        const UncertaintyOptions& opt) {
  check_frequency_grid(grid);
  check_priors(priors);
  const Eigen::Index N = u.size();
  if (y.size() != N) throw InputError("data: u has " + num(N) + " samples but y has " + num(y.size()));
  if (instrument.size() != 0 && instrument.size() != N)
    throw InputError("data: the instrument (reference) has " + num(instrument.size()) + " samples, u has " + num(N));
  if (order < 1) throw InputError("basis order n = " + num(order) + " must be at least 1");
  for (Eigen::Index t = 0; t < N; ++t)
    if (!std::isfinite(u[t]) || !std::isfinite(y[t])) throw InputError("data: sample " + num(t + 1) + " is not finite");
  if (opt.noise == NoiseModel::stochastic && !(opt.alpha > 0 && opt.alpha < 1))
    throw InputError("alpha = " + num(opt.alpha) + " must satisfy 0 < alpha < 1");
  if (opt.noise == NoiseModel::bounded && !(opt.v_bar >= 0 && std::isfinite(opt.v_bar)))
    throw InputError("v_bar = " + num(opt.v_bar) + " must be >= 0");
}

// Impulse-response envelope |h0(s)| <= M rho^s of the initial-condition term.
struct IcEnvelope {
  double M = 0, rho = 0;
};

IcEnvelope ic_envelope(const OrthonormalBasis& basis, const HinfPriors& priors) {
  if (basis.kind() != BasisKind::fir && priors.u_bar > 0 && (priors.rho_ic <= 0 || priors.M_ic <= 0))
    throw InputError("priors M_ic and rho_ic (impulse-response envelope for the initial conditions) must be given "
                     "for the " + std::string(to_string(basis.kind())) + " basis when u_bar > 0");
  return {priors.M_ic > 0 ? priors.M_ic : priors.M / priors.rho, priors.rho_ic > 0 ? priors.rho_ic : priors.rho};
}

// sup|T'| for the tail T = sum_{k>=n} g0(k) F_k: sum_{k>=n} M rho^k (D0 + floor(k/m) H0 L'),
// floor(k/m) <= k/m, in closed form.
double tail_slope(const OrthonormalBasis& basis, const HinfPriors& priors, int order) {
  const double r = priors.rho, rn = priors.M * std::pow(r, order);
  return rn * (basis.front_derivative_bound() / (1 - r) +
               basis.hinf_bound() * basis.allpass_derivative_bound() / basis.block() *
                   (order / (1 - r) + r / ((1 - r) * (1 - r))));
}

// The regression of step 1 on rows t0 .. N-1: y = Phi theta0 + Xt g0_tail + (remainder) + ic + v.
struct Regression {
  int n = 0, K = 0, t0 = 0, R = 0;
  Eigen::MatrixXd Phi, Xt, Z, Smat;  // model part, evaluated tail, instruments (or Phi), Z^T Phi
  Eigen::VectorXd yr;
  Eigen::VectorXd tailcoef;  // M rho^k, k = n .. n+K-1
  double rem = 0;            // sum_{k>=n+K} M rho^k
  Eigen::VectorXd ic;        // bound on the initial-condition term of each row
};

Regression build_regression(const Eigen::Ref<const Eigen::VectorXd>& u, const Eigen::Ref<const Eigen::VectorXd>& y,
                            const Eigen::Ref<const Eigen::VectorXd>& instrument, const OrthonormalBasis& basis,
                            int order, const HinfPriors& priors, const IcEnvelope& env,
                            const UncertaintyOptions& opt) {
  const int N = static_cast<int>(u.size());
  Regression g;
  g.n = order;
  g.t0 = opt.first_sample;
  if (g.t0 < 0)
    g.t0 = priors.u_bar > 0 ? std::min(N / 4, static_cast<int>(std::ceil(std::log(1e-3) / std::log(env.rho)))) : 0;
  g.R = N - g.t0;
  if (g.R < 2 * order + 10)
    throw InputError("data: " + num(g.R) + " usable samples (after skipping " + num(g.t0) + ") are too few for " +
                     num(order) + " basis functions");
  g.K = opt.tail_terms;
  if (g.K < 0) {
    const double need = std::log(1e-9 * (1 - priors.rho)) / std::log(priors.rho);
    g.K = std::clamp(static_cast<int>(std::ceil(need)) - order, 0, 400);
  }
  const int n = g.n, K = g.K, t0 = g.t0, R = g.R;
  const Eigen::MatrixXd X = basis.responses(u, n + K);
  g.Phi = X.block(t0, 0, R, n);
  g.Xt = X.block(t0, n, R, K);
  g.yr = y.segment(t0, R);
  g.Z = instrument.size() ? Eigen::MatrixXd(basis.responses(instrument, n).block(t0, 0, R, n)) : g.Phi;
  g.Smat = g.Z.transpose() * g.Phi;
  g.rem = priors.M * std::pow(priors.rho, n + K) / (1 - priors.rho);
  g.tailcoef.resize(K);
  for (int k = 0; k < K; ++k) g.tailcoef[k] = priors.M * std::pow(priors.rho, n + k);
  g.ic.resize(R);  // |sum_{s>=t} h0(s) u(t-s)| <= u_bar M_ic rho_ic^t / (1 - rho_ic), t 1-based
  for (int i = 0; i < R; ++i) g.ic[i] = priors.u_bar * env.M * std::pow(env.rho, t0 + i + 1) / (1 - env.rho);
  return g;
}

// Re and Im of the model part's frequency responses (n x nw each) and the evaluated tail (K x nw).
struct GridResponses {
  Eigen::MatrixXcd model, tail;
  Eigen::MatrixXd re, im;
};

GridResponses grid_responses(const OrthonormalBasis& basis, const Eigen::Ref<const Eigen::VectorXd>& grid, int n, int K) {
  const int nw = static_cast<int>(grid.size());
  GridResponses G{Eigen::MatrixXcd(n, nw), Eigen::MatrixXcd(K, nw), Eigen::MatrixXd(), Eigen::MatrixXd()};
  for (int j = 0; j < nw; ++j) {
    const Eigen::VectorXcd F = basis.frequency_responses(grid[j], n + K);
    G.model.col(j) = F.head(n);
    G.tail.col(j) = F.tail(K);
  }
  G.re = G.model.real();
  G.im = G.model.imag();
  return G;
}

// f4, the tail itself: sum_k M rho^k |Re/Im F_k| plus the remainder beyond the evaluated terms.
void set_tail_terms(UncertaintySet& S, const Regression& g, const GridResponses& G) {
  const double rem = S.tail_remainder;
  for (Eigen::Index j = 0; j < G.tail.cols(); ++j) {
    double re = rem, im = rem;
    for (int k = 0; k < g.K; ++k) {
      re += g.tailcoef[k] * std::abs(G.tail(k, j).real());
      im += g.tailcoef[k] * std::abs(G.tail(k, j).imag());
    }
    S.terms[j].tail_re = re;
    S.terms[j].tail_im = im;
  }
}

// Bounded noise: strips |y(t) - phi(t)^T theta| <= v_bar + e_ic(t) + e_tail(t), with
// |x_k(t)| <= ||u_{1..t}||_2 for the remainder of the tail.
Eigen::VectorXd strip_widths(const Eigen::Ref<const Eigen::VectorXd>& u, const Regression& g, double v_bar) {
  Eigen::VectorXd delta(g.R);
  double usq = 0;
  for (int t = 0; t < g.t0; ++t) usq += u[t] * u[t];
  for (int i = 0; i < g.R; ++i) {
    usq += u[g.t0 + i] * u[g.t0 + i];
    delta[i] = v_bar + g.ic[i] + g.tailcoef.dot(g.Xt.row(i).cwiseAbs().transpose()) + g.rem * std::sqrt(usq);
  }
  return delta;
}

// The PUI box contains the FPS, hence theta0: its centre and radius (rounded up) for b_data.
void set_coefficient_box(UncertaintySet& S, const FpsSupport& sup, int n) {
  for (int l = 0; l < n; ++l)
    if (!std::isfinite(sup.box[l].lower()) || !std::isfinite(sup.box[l].upper()))
      throw NumericalError("bounded noise: parameter " + num(l) + " is unbounded (input not exciting enough)");
  S.theta_ref.resize(n);
  S.theta_radius.resize(n);
  for (int l = 0; l < n; ++l) {
    const double lo = sup.box[l].lower(), hi = sup.box[l].upper(), c = 0.5 * (lo + hi);
    S.theta_ref[l] = c;
    S.theta_radius[l] = std::nextafter(std::max(hi - c, c - lo) * (1 + 1e-15), inf);
  }
}

// Bounded noise: each region is the rectangle of the extremes of Re and Im Gamma(w_j)^T theta
// over the FPS (certified LP bounds), widened by the tail term f4.
void bounded_regions(UncertaintySet& S, const Eigen::Ref<const Eigen::VectorXd>& u, const Regression& g,
                     const GridResponses& G, double v_bar) {
  const auto fps = FeasibleParameterSet::from_data(g.Phi, g.yr, strip_widths(u, g, v_bar));
  // 4 directions per frequency, all from one working-set LP (row generation) with safe bounds, as
  // for the PUIs. Ordered as four sweeps along the grid (max Re, min Re, max Im, min Im):
  // neighbouring frequencies have nearby optima, so each LP starts close to its optimal basis.
  const int nw = static_cast<int>(S.frequencies.size());
  std::vector<Eigen::VectorXd> dirs;
  dirs.reserve(static_cast<std::size_t>(4 * nw));
  for (const Eigen::MatrixXd* M : {&G.re, &G.im})
    for (double sign : {1.0, -1.0})
      for (int j = 0; j < nw; ++j) dirs.push_back(sign * M->col(j));
  const FpsSupport sup = support(fps, dirs);
  S.lp_solves += sup.lp_solves;
  S.consistency = sup.consistency;
  if (sup.empty()) return;  // certified only: an undecided verdict goes on (and fails below if unbounded)
  set_coefficient_box(S, sup, g.n);
  auto extreme = [&](int k) {  // the maximum in direction k, or minus it for the mirrored one
    const double v = sup.maxima[static_cast<std::size_t>(k)];
    if (!std::isfinite(v)) throw NumericalError("bounded noise: could not certify an LP bound");
    return v;
  };
  for (int j = 0; j < nw; ++j) {
    const double re_hi = extreme(j), re_lo = -extreme(nw + j);
    const double im_hi = extreme(2 * nw + j), im_lo = -extreme(3 * nw + j);
    FrequencyRegion& P = S.regions[j];
    P.shape = RegionShape::rectangle;
    P.centre = {0.5 * (re_lo + re_hi), 0.5 * (im_lo + im_hi)};
    // Half widths rounded up: the centre is a rounded midpoint.
    P.half_re = std::nextafter(0.5 * (re_hi - re_lo) + std::abs(P.centre.real()) * 4e-16, inf) + S.terms[j].tail_re;
    P.half_im = std::nextafter(0.5 * (im_hi - im_lo) + std::abs(P.centre.imag()) * 4e-16, inf) + S.terms[j].tail_im;
  }
}

// Noise covariance lags R_v(0..L) from the residuals: Bartlett window, degrees-of-freedom correction.
struct NoiseCovariance {
  Eigen::VectorXd Rv;
  int L = 0, R = 0;
  // a^T Sigma_v b.
  double quad(const Eigen::Ref<const Eigen::VectorXd>& a, const Eigen::Ref<const Eigen::VectorXd>& b) const {
    double s = Rv[0] * a.dot(b);
    for (int tau = 1; tau <= L; ++tau)
      s += Rv[tau] * (a.head(R - tau).dot(b.tail(R - tau)) + b.head(R - tau).dot(a.tail(R - tau)));
    return s;
  }
  // Sigma_v C, column by column (R L per column).
  Eigen::MatrixXd apply(const Eigen::MatrixXd& C) const {
    Eigen::MatrixXd SC = Rv[0] * C;
    for (int tau = 1; tau <= L; ++tau) {
      SC.bottomRows(R - tau) += Rv[tau] * C.topRows(R - tau);
      SC.topRows(R - tau) += Rv[tau] * C.bottomRows(R - tau);
    }
    return SC;
  }
};

NoiseCovariance noise_covariance(const Eigen::VectorXd& res, int n, int max_lag) {
  NoiseCovariance c;
  c.R = static_cast<int>(res.size());
  const int R = c.R;
  c.L = max_lag >= 0 ? max_lag : std::min(100, R / 10);
  c.Rv.resize(c.L + 1);
  for (int tau = 0; tau <= c.L; ++tau)
    c.Rv[tau] = res.head(R - tau).dot(res.tail(R - tau)) / R * R / (R - n) * (1.0 - double(tau) / (c.L + 1));
  return c;
}

// Stochastic coefficient set for b_data: theta_hat_k - theta0_k = c_k^T (tail + ic + v),
// c_k = Z S^-T e_k. Box: each c_k bounded like a frequency row, Bonferroni over k. Ellipsoid
// (used by b_data): the noise part c^T v is asymptotically N(0, P), P_kl = c_k^T Sigma_v c_l,
// inside {e^T P^-1 e <= chi2_n} at the same failure probability; the rest is worst case per k.
void stochastic_coefficient_set(UncertaintySet& S, const Regression& g, const NoiseCovariance& cov, double fail,
                                double unorm) {
  const int n = g.n;
  S.coefficient_level = std::max(0.0, 1 - fail);
  const boost::math::normal normal01;
  const double zt = boost::math::quantile(normal01, 1 - fail / (2 * n));
  const Eigen::MatrixXd Ct = g.Z * g.Smat.transpose().colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(n, n));
  const Eigen::MatrixXd XtCt = g.Xt.transpose() * Ct;
  S.theta_covariance = Ct.transpose() * cov.apply(Ct);
  S.theta_covariance = 0.5 * (S.theta_covariance + S.theta_covariance.transpose()).eval();
  S.theta_scale = std::sqrt(boost::math::quantile(boost::math::chi_squared(n), 1 - fail));
  S.theta_ref = S.theta;
  S.theta_radius.resize(n);
  S.theta_offset.resize(n);
  const double H0 = S.basis.hinf_bound();
  for (int k = 0; k < n; ++k) {
    const auto c = Ct.col(k);
    S.theta_offset[k] = g.tailcoef.dot(XtCt.col(k).cwiseAbs()) + g.rem * c.norm() * H0 * unorm + c.cwiseAbs().dot(g.ic);
    S.theta_radius[k] = zt * std::sqrt(std::max(0.0, S.theta_covariance(k, k))) + S.theta_offset[k];
  }
}

// The noise ellipse chi2 [Pre Pri; Pri Pim] plus the box [+-dre] x [+-dim], the box itself inside
// the ellipse with Q2 = 2 diag(dre^2, dim^2); Minkowski sum of two ellipses inside
// (1+1/p) Q1 + (1+p) Q2.
Eigen::Matrix2d ellipse_shape(double Pre, double Pim, double Pri, double chi2, double dre, double dim) {
  Pri = std::clamp(Pri, -std::sqrt(Pre * Pim), std::sqrt(Pre * Pim));
  Eigen::Matrix2d Q1;
  Q1 << Pre, Pri, Pri, Pim;
  Q1 *= chi2;
  const Eigen::Matrix2d Q2 = Eigen::Vector2d(2 * dre * dre, 2 * dim * dim).asDiagonal();
  Eigen::Matrix2d Q;
  if (Q2.trace() == 0)
    Q = Q1;
  else if (Q1.trace() == 0)
    Q = Q2;
  else {
    const double p = std::sqrt(Q1.trace() / Q2.trace());
    Q = (1 + 1 / p) * Q1 + (1 + p) * Q2;
  }
  Q += 1e-15 * Q.trace() * Eigen::Matrix2d::Identity();  // keep it positive definite
  return Q;
}

// Stochastic: sensitivity vectors c with Re/Im(Gbar - G0 model part) = c^T (tail + ic + v); the
// noise part at level S.level per frequency, the other three terms of (11) worst case.
void stochastic_regions(UncertaintySet& S, const Regression& g, const GridResponses& G, const NoiseCovariance& cov,
                        RegionShape shape, double unorm) {
  const int nw = static_cast<int>(S.frequencies.size());
  Eigen::MatrixXd G2(g.n, 2 * nw);
  G2 << G.re, G.im;
  const Eigen::MatrixXd C = g.Z * g.Smat.transpose().colPivHouseholderQr().solve(G2);  // R x 2nw
  const Eigen::MatrixXd XtC = g.Xt.transpose() * C;
  const double H0 = S.basis.hinf_bound();
  const boost::math::normal normal;
  const double zq = boost::math::quantile(normal, 1 - (1 - S.level) / 4);  // two-sided, Re and Im
  const double chi2 = -2 * std::log(1 - S.level);                          // chi^2_2 quantile
  for (int j = 0; j < nw; ++j) {
    const auto cre = C.col(j), cim = C.col(nw + j);
    const double Pre = std::max(0.0, cov.quad(cre, cre)), Pim = std::max(0.0, cov.quad(cim, cim));
    ErrorTerms& T = S.terms[j];
    const double sc = shape == RegionShape::rectangle ? zq : std::sqrt(chi2);
    T.noise_re = sc * std::sqrt(Pre);
    T.noise_im = sc * std::sqrt(Pim);
    T.tail_est_re = g.tailcoef.dot(XtC.col(j).cwiseAbs()) + g.rem * cre.norm() * H0 * unorm;
    T.tail_est_im = g.tailcoef.dot(XtC.col(nw + j).cwiseAbs()) + g.rem * cim.norm() * H0 * unorm;
    T.ic_re = cre.cwiseAbs().dot(g.ic);
    T.ic_im = cim.cwiseAbs().dot(g.ic);
    const double dre = T.tail_est_re + T.ic_re + T.tail_re, dim = T.tail_est_im + T.ic_im + T.tail_im;
    FrequencyRegion& P = S.regions[j];
    P.centre = S.estimate[j];
    P.shape = shape;
    if (shape == RegionShape::rectangle) {
      P.half_re = T.noise_re + dre;
      P.half_im = T.noise_im + dim;
    } else {
      P.Q = ellipse_shape(Pre, Pim, cov.quad(cre, cim), chi2, dre, dim);
      P.half_re = std::sqrt(P.Q(0, 0));
      P.half_im = std::sqrt(P.Q(1, 1));
    }
  }
}

}  // namespace

UncertaintySet uncertainty_set(const Eigen::Ref<const Eigen::VectorXd>& u, const Eigen::Ref<const Eigen::VectorXd>& y,
                               const OrthonormalBasis& basis, int order, const Eigen::Ref<const Eigen::VectorXd>& grid,
                               const HinfPriors& priors, const UncertaintyOptions& opt,
                               const Eigen::Ref<const Eigen::VectorXd>& instrument) {
  check_step1_inputs(u, y, instrument, order, grid, priors, opt);
  const Regression g = build_regression(u, y, instrument, basis, order, priors, ic_envelope(basis, priors), opt);
  const int n = g.n, nw = static_cast<int>(grid.size());
  UncertaintySet S;
  S.frequencies = grid;
  S.first_sample = g.t0;
  S.tail_terms = g.K;
  S.rows = g.R;
  S.beta1 = basis.beta1(priors.M, priors.rho);
  S.basis = basis;
  S.tail_beta = tail_slope(basis, priors, order);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(g.Smat);
  if (qr.rank() < n)
    throw InputError("data: the input is not persistently exciting for " + num(n) + " basis functions (rank " +
                     num(qr.rank()) + ")");
  S.theta = qr.solve(g.Z.transpose() * g.yr);

  const GridResponses G = grid_responses(basis, grid, n, g.K);
  S.estimate.resize(nw);
  for (int j = 0; j < nw; ++j) S.estimate[j] = G.model.col(j).transpose() * S.theta.cast<std::complex<double>>();
  S.tail_coefficients = g.tailcoef;
  S.tail_remainder = g.rem * basis.hinf_bound();
  S.terms.resize(nw);
  S.regions.resize(nw);
  set_tail_terms(S, g, G);
  if (opt.noise == NoiseModel::bounded) {
    bounded_regions(S, u, g, G, opt.v_bar);
    return S;
  }
  if (!(opt.coefficient_share > 0)) throw InputError("coefficient_share must be > 0");
  const NoiseCovariance cov = noise_covariance(g.yr - g.Phi * S.theta, n, opt.max_lag);
  S.noise_variance = cov.Rv[0];
  // Failure budget: regions (1 - alpha) / (1 + share), coefficient set the rest (simultaneous).
  const double share = opt.coefficient_share;
  S.level = opt.simultaneous ? 1 - (1 - opt.alpha) / ((1 + share) * nw) : opt.alpha;
  const double fail = opt.simultaneous ? share * (1 - opt.alpha) / (1 + share) : share * (1 - opt.alpha);
  stochastic_coefficient_set(S, g, cov, fail, u.norm());
  stochastic_regions(S, g, G, cov, opt.shape, u.norm());
  return S;
}

// ------------------------------------------------------------------ step 2
NominalFit fit_nominal(const UncertaintySet& S, const NominalOptions& o) {
  if (S.empty()) throw InputError("nominal model: the uncertainty set is empty (data falsify the priors)");
  const int nw = static_cast<int>(S.frequencies.size());
  const int ng = o.order;
  if (ng < 0) throw InputError("nominal order " + num(ng) + " must be >= 0");
  if (2 * ng + 1 > 2 * nw)
    throw InputError("nominal order " + num(ng) + " cannot be met: " + num(2 * ng + 1) +
                     " coefficients but only " + num(nw) + " frequencies (" + num(2 * nw) + " real equations)");
  if (ng > 30) throw InputError("nominal order " + num(ng) + " is above the supported 30 (stability check by roots)");
  if (o.polygon_sides < 3) throw InputError("polygon sides K = " + num(o.polygon_sides) + " must be >= 3");
  Eigen::VectorXd W1 = o.weight.size() ? o.weight : Eigen::VectorXd::Ones(nw);
  if (W1.size() != nw) throw InputError("nominal weight: " + num(W1.size()) + " values for " + num(nw) + " frequencies");

  NominalFit fit;
  fit.polygon_sides = o.polygon_sides;
  fit.centres.resize(nw);
  for (int j = 0; j < nw; ++j) fit.centres[j] = S.regions[j].centre;  // Chebyshev centres (16)
  const auto& w = S.frequencies;
  const int K = o.polygon_sides, nv = 2 * ng + 2, it_max = std::max(1, o.iterations);
  const int nd = 256;  // dense grid for the stability (positive-real) constraint
  auto true_error = [&](const TransferFunction& m) {
    double e = 0;
    for (int j = 0; j < nw; ++j) e = std::max(e, W1[j] * std::abs(fit.centres[j] - m(w[j])));
    return e;
  };
  Eigen::VectorXd aprev = Eigen::VectorXd::Ones(1);
  aprev.conservativeResize(ng + 1);
  aprev.tail(ng).setZero();
  double best = inf;
  for (int it = 0; it < it_max; ++it) {
    LinearProgram lp(nv);
    lp.set_variable_bounds(nv - 1, 0, inf);
    for (int i = 1; i <= ng; ++i) {  // coefficients of a stable monic polynomial: |a_i| <= C(ng, i)
      double binom = 1;
      for (int r = 0; r < i; ++r) binom = binom * (ng - r) / (r + 1);
      lp.set_variable_bounds(i - 1, -binom, binom);
    }
    for (int j = 0; j < nw; ++j) {
      const double s = W1[j] / std::abs(polynomial_at(aprev, w[j]));
      for (int k = 0; k < K; ++k) {
        const std::complex<double> rot = std::polar(1.0, -2 * pi * k / K);
        Eigen::VectorXd row = Eigen::VectorXd::Zero(nv);
        for (int i = 1; i <= ng; ++i) row[i - 1] = s * (std::polar(1.0, -i * w[j]) * fit.centres[j] * rot).real();
        for (int i = 0; i <= ng; ++i) row[ng + i] = -s * (std::polar(1.0, -i * w[j]) * rot).real();
        row[nv - 1] = -1;
        lp.add_row(row, -inf, -s * (fit.centres[j] * rot).real());
      }
    }
    for (int d = 0; d < nd && ng > 0; ++d) {  // Re(A / A_prev) >= 0.01 keeps the winding number
      const double wd = pi * d / (nd - 1);
      const std::complex<double> ap = std::conj(polynomial_at(aprev, wd));
      Eigen::VectorXd row = Eigen::VectorXd::Zero(nv);
      for (int i = 1; i <= ng; ++i) row[i - 1] = (std::polar(1.0, -i * wd) * ap).real();
      lp.add_row(row, 0.01 * std::norm(ap) - ap.real(), inf);
    }
    lp.set_objective_coordinate(nv - 1, Sense::minimize);
    const LpSolution sol = lp.solve();
    if (sol.status != LpStatus::optimal) break;
    TransferFunction m;
    m.a = Eigen::VectorXd::Ones(ng + 1);
    m.a.tail(ng) = sol.x.head(ng);
    m.b = sol.x.segment(ng, ng + 1);
    fit.iterations = it + 1;
    if (!m.stable(1e-4)) break;  // the positive-real constraint held only on the dense grid
    const double e = true_error(m);
    const bool improved = e < best;
    if (improved) {
      const double old = best;
      best = e;
      fit.model = m;
      fit.max_error = e;
      if (old - e < 1e-7 * e) break;
    }
    aprev = m.a;
  }
  if (!std::isfinite(best))
    throw NumericalError("nominal model: no stable model of order " + num(ng) + " was found");
  return fit;
}

Eigen::VectorXd additive_error(const UncertaintySet& S, const TransferFunction& m) {
  Eigen::VectorXd d(S.frequencies.size());
  for (Eigen::Index j = 0; j < d.size(); ++j) d[j] = S.regions[j].max_distance(m(S.frequencies[j]));
  return d;
}

// ------------------------------------------------------------------ step 3
namespace {
double trig_at(const Eigen::VectorXd& c, double w) {  // c0 + sum_k c_k cos(k w)
  double s = 0;
  for (Eigen::Index k = 0; k < c.size(); ++k) s += c[k] * std::cos(k * w);
  return s;
}

// Certified lower bound on min over [0, pi] of the cosine polynomial c: the minimum over a grid of
// spacing d less d^2/8 sup|c''| (sup|c''| <= sum k^2 |c_k|), the grid refined until it is positive
// or 2^20 points; returns that bound (<= 0: not certified).
double certified_trig_minimum(const Eigen::VectorXd& c) {
  const double curvature = polynomial_second_derivative_bound(c);
  double lower = -inf;
  for (int points = 16384; points <= (1 << 20); points *= 4) {
    double m = inf;
    for (int i = 0; i < points; ++i) m = std::min(m, trig_at(c, pi * i / (points - 1)));
    const double d = pi / (points - 1);
    lower = m - d * d / 8 * curvature;
    if (lower > 0) break;
  }
  return lower;
}

// Solves the LP for |W^-1|^2 and, where its solution dips below `floor` between the LP's rows,
// adds the local minima as rows and solves again (cutting planes; at most 8 rounds).
Eigen::VectorXd floored_trig_solution(LinearProgram& lp, const std::function<Eigen::VectorXd(double)>& cosrow, int m,
                                      double floor) {
  const int nc = 16384;
  for (int round = 0;; ++round) {
    const LpSolution sol = lp.solve();
    if (sol.status != LpStatus::optimal) throw NumericalError("weight: the LP for |W^-1|^2 has no optimum");
    const Eigen::VectorXd c = sol.x.head(m + 1);
    Eigen::VectorXd v(nc);
    for (int i = 0; i < nc; ++i) v[i] = trig_at(c, pi * i / (nc - 1));
    int cuts = 0;
    for (int i = 0; i < nc; ++i)
      if (v[i] < floor && (i == 0 || v[i] <= v[i - 1]) && (i == nc - 1 || v[i] <= v[i + 1])) {
        lp.add_row(cosrow(pi * i / (nc - 1)), floor, inf);
        ++cuts;
      }
    if (cuts == 0 || round == 8) return c;
  }
}

// The LP for |W^-1|^2 = unit * (x_0 + sum_k x_k cos kw): minimise t subject to
// |W^-1|^2 >= delta^2 and W1^2 (|W^-1|^2 - delta^2) <= t on the grid, >= floor on 2048 points
// (and at the cutting planes); returns the coefficients c = unit * x.
Eigen::VectorXd weight_lp_solution(const Eigen::Ref<const Eigen::VectorXd>& grid,
                                   const Eigen::Ref<const Eigen::VectorXd>& delta, const Eigen::VectorXd& W1, int m,
                                   double floor, double unit) {
  const int nv = m + 2;
  LinearProgram lp(nv);
  const std::function<Eigen::VectorXd(double)> cosrow = [&](double w) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(nv);
    for (int k = 0; k <= m; ++k) r[k] = std::cos(k * w);
    return r;
  };
  for (Eigen::Index j = 0; j < grid.size(); ++j) {
    const double d2 = delta[j] * delta[j];
    lp.add_row(cosrow(grid[j]), d2 / unit, inf);
    Eigen::VectorXd r = W1[j] * W1[j] * unit * cosrow(grid[j]);
    r[nv - 1] = -1;
    lp.add_row(r, -inf, W1[j] * W1[j] * d2);
  }
  const int nd = 2048;
  for (int d = 0; d < nd; ++d) lp.add_row(cosrow(pi * d / (nd - 1)), floor / unit, inf);
  lp.set_objective_coordinate(nv - 1, Sense::minimize);
  return unit * floored_trig_solution(lp, cosrow, m, floor / unit);
}
}  // namespace

std::complex<double> WeightFit::inverse(double w) const { return polynomial_at(h, w); }

WeightFit fit_weight(const Eigen::Ref<const Eigen::VectorXd>& grid, const Eigen::Ref<const Eigen::VectorXd>& delta,
                     const WeightOptions& o) {
  check_frequency_grid(grid);
  const int nw = static_cast<int>(grid.size());
  if (delta.size() != nw) throw InputError("weight: " + num(delta.size()) + " error bounds for " + num(nw) + " frequencies");
  if (o.degree < 0 || o.degree > 60) throw InputError("weight degree " + num(o.degree) + " must be in [0, 60]");
  for (int j = 0; j < nw; ++j)
    if (!(delta[j] >= 0 && std::isfinite(delta[j]))) throw InputError("weight: delta[" + num(j) + "] is not a finite value >= 0");
  Eigen::VectorXd W1 = o.weight.size() ? o.weight : Eigen::VectorXd::Ones(nw);
  if (W1.size() != nw) throw InputError("weight W1: " + num(W1.size()) + " values for " + num(nw) + " frequencies");
  const int m = o.degree;
  const double dmax = delta.maxCoeff();
  if (!(dmax > 0)) throw InputError("weight: every delta is zero");
  // |W^-1|^2 >= a quarter of the smallest delta^2 between grid points too: W stays bounded.
  const double floor = 0.25 * delta.minCoeff() * delta.minCoeff() + 1e-8 * dmax * dmax;
  // The same LP in three units of |W^-1|^2: GLPK fails (glp_simplex code 5, or a wrong
  // "optimum") on some runs in one unit and not in another when delta spans decades.
  WeightFit fit;
  const double units[] = {dmax * std::max(delta.minCoeff(), 1e-4 * dmax), dmax * dmax, 1.0};
  for (std::size_t i = 0; i < std::size(units); ++i) {
    try {
      fit.trig = weight_lp_solution(grid, delta, W1, m, floor, units[i]);
      break;
    } catch (const NumericalError&) {
      if (i + 1 == std::size(units)) throw;
    }
  }
  const double pmin = certified_trig_minimum(fit.trig);
  if (!(pmin > 0))
    throw NumericalError("weight: |W^-1|^2 is not certified positive (curvature bound " +
                         num(polynomial_second_derivative_bound(fit.trig)) + "); lower the weight degree");
  // Spectral factor: z^m P(z) has roots in pairs (r, 1/conj r); keep those inside the circle.
  int mm = m;
  while (mm > 0 && std::abs(fit.trig[mm]) < 1e-13 * std::abs(fit.trig[0])) --mm;
  Eigen::VectorXcd inside;
  if (mm > 0) {
    Eigen::VectorXd desc(2 * mm + 1);  // descending powers of z
    for (int k = 0; k <= mm; ++k) desc[mm - k] = desc[mm + k] = k == 0 ? fit.trig[0] : fit.trig[k] / 2;
    // Its roots are the poles of 1 / (desc / desc[0]) read as a polynomial in z^-1 (palindromic).
    const Eigen::VectorXcd r = TransferFunction{Eigen::VectorXd::Ones(1), desc / desc[0], {}}.poles();
    std::vector<std::complex<double>> v(r.data(), r.data() + r.size());
    std::sort(v.begin(), v.end(), [](auto x, auto y) { return std::abs(x) < std::abs(y); });
    inside.resize(mm);
    for (int i = 0; i < mm; ++i) inside[i] = v[i];
    if (!(std::abs(v[mm - 1]) < 1)) throw NumericalError("weight: spectral factor has a zero on the unit circle");
  }
  Eigen::VectorXcd hc = Eigen::VectorXcd::Zero(mm + 1);
  hc[0] = 1;
  for (int i = 0; i < mm; ++i)  // multiply by (1 - r z^-1)
    for (int k = i + 1; k >= 1; --k) hc[k] -= inside[i] * hc[k - 1];
  fit.h = hc.real();
  // Gain: match P in the mean, then scale so |W^-1| >= delta holds on the grid.
  double num_ = 0, den = 0;
  for (int i = 0; i < 512; ++i) {
    const double w = pi * i / 511;
    num_ += trig_at(fit.trig, w);
    den += std::norm(polynomial_at(fit.h, w));
  }
  fit.h *= std::sqrt(num_ / den);
  double scale = 1;
  for (int j = 0; j < nw; ++j) scale = std::max(scale, delta[j] / std::abs(polynomial_at(fit.h, grid[j])));
  fit.h *= scale * (1 + 1e-12);
  fit.max_gap = 0;
  for (int j = 0; j < nw; ++j)
    fit.max_gap = std::max(fit.max_gap, W1[j] * W1[j] * (std::norm(polynomial_at(fit.h, grid[j])) - delta[j] * delta[j]));
  return fit;
}

// ------------------------------------------------------------------ step 4
namespace {
// min over w in [lo, hi] of |e^{iw} - p| (|1 - p e^{-iw}|): at the arc point nearest to arg p.
double arc_distance(std::complex<double> p, double lo, double hi) {
  const double r = std::abs(p), phi = std::arg(p);
  double d = 0;  // angular distance from phi (or -phi: real coefficients, conjugate poles) to [lo, hi]
  for (double f : {phi, -phi}) {
    const double a = f < lo ? lo - f : (f > hi ? f - hi : 0);
    d = f == phi ? a : std::min(d, a);
  }
  d = std::min(d, pi);
  return std::max(0.0, std::sqrt(std::max(0.0, 1 + r * r - 2 * r * std::cos(d))) - 1e-12);
}
// Local bounds on [lo, hi] for b(z^-1)/a(z^-1) with roots `poles` of a: |a| >= prod dist(p_i, arc).
struct LocalTf {
  double sup = inf, der = inf;
};
LocalTf local_tf(const Eigen::VectorXd& b, const Eigen::VectorXd& a, const Eigen::VectorXcd& poles, double lo, double hi) {
  double amin = 1;
  for (Eigen::Index i = 0; i < poles.size(); ++i) amin *= arc_distance(poles[i], lo, hi);
  LocalTf t;
  if (!(amin > 0)) return t;
  t.sup = b.cwiseAbs().sum() / amin;
  t.der = polynomial_derivative_bound(b) / amin + b.cwiseAbs().sum() * polynomial_derivative_bound(a) / (amin * amin);
  return t;
}

// b_data (docs/methods/hinf-bound.md, section 6). For w in cell_j two bounds on |G0(w) - Ghat(w)|
// hold on the event that the regions and the coefficient set hold:
//  (a) from the region at w_j:  G0(w) - Ghat(w) = [G0(w_j) - Ghat(w_j)] + Delta(w) + r(w),
//      Delta(w) = (Gamma(w) - Gamma(w_j))^T theta_ref - Ghat(w) + Ghat(w_j)   (known),
//      |r(w)| <= g(w) = sum_{k<n} radius_k |F_k(w) - F_k(w_j)| + sum_{k>=n} M rho^k |F_k(w) - F_k(w_j)|,
//      so |G0 - Ghat| <= maxdist_{P(w_j)}(Ghat(w_j) - Delta(w)) + g(w);
//  (b) direct, from the coefficient set alone: |G0(w) - Ghat(w)| <= |Gamma(w)^T theta_ref - Ghat(w)|
//      + sum_{k<n} radius_k |F_k(w)| + sum_{k>=n} M rho^k |F_k(w)| (+ the tail remainder).
// Both are Lipschitz in w with constant <= L_Delta + L_g on a piece, so on a piece of half width
// eta around w_i their minimum is bounded by its value at w_i plus eta (L_Delta + L_g), the local
// constants from the distance of the poles to the piece's arc. The pieces are refined where they
// set the maximum (section 6, "adaptive pieces").

// What every piece of the band shares.
struct BandContext {
  const UncertaintySet& S;
  const TransferFunction& nominal;
  Eigen::VectorXd h;  // a copy: callers pass an Eigen::Ref, which may own a temporary that dies before the context
  double Wder = 0, Gder = 0, hder = 0;
  int n = 0, K = 0, m = 1;
  double D0 = 0, H0 = 0, L0 = 0;
  std::vector<Eigen::VectorXcd> front_poles{};
  Eigen::VectorXcd ap_poles{}, nom_poles{};
  // Weights of |F_k(w) - F_k(w_j)| (and |F_k(w)|) in g and of the slopes. With the ellipsoid
  // (stochastic), the first n weights are the worst-case offsets and the noise part is bounded
  // in the direction itself: sup_{e^T P^-1 e <= s^2} |a^T e| = s sqrt(a^H P a).
  bool ellipsoid = false;
  Eigen::MatrixXd Pabs{};
  Eigen::VectorXd wg{}, wd{};
  Eigen::VectorXcd th{};
};

// The cell of grid point j: [lo, hi] and what its pieces share.
struct Cell {
  int j = 0;
  double lo = 0, hi = 0;
  Eigen::VectorXcd Fj;
  std::complex<double> Gr, Gh;  // Gamma(w_j)^T theta_ref, Ghat(w_j)
};

struct Piece {
  double bound = 0;  // >= |W (G0 - Ghat)| on the piece
  double point = 0;  // the bound's value at the centre (its limit as the piece shrinks)
  int cell = 0;
  double centre = 0, eta = 0;
  bool operator<(const Piece& o) const { return bound < o.bound; }
};

double ellipsoid_term(const BandContext& c, const Eigen::Ref<const Eigen::VectorXcd>& a) {
  const Eigen::VectorXd are = a.real(), aim = a.imag();
  const Eigen::MatrixXd& P = c.S.theta_covariance;
  return c.S.theta_scale * std::sqrt(std::max(0.0, are.dot(P * are) + aim.dot(P * aim)));
}

// Local sup|F_k'| on the arc [lo, hi]: min(global, Dc + floor(k/m) Hc Lc), for k < n + K.
Eigen::VectorXd local_slopes(const BandContext& c, double lo, double hi) {
  const OrthonormalBasis& basis = c.S.basis;
  double Hc = 0, Dc = 0, Lc = 0;
  for (std::size_t f = 0; f < c.front_poles.size(); ++f) {
    const LocalTf t = local_tf(basis.fronts()[f].b, basis.fronts()[f].a, c.front_poles[f], lo, hi);
    Hc = std::max(Hc, t.sup);
    Dc = std::max(Dc, t.der);
  }
  for (Eigen::Index q = 0; q < c.ap_poles.size(); ++q) {
    const double d = arc_distance(c.ap_poles[q], lo, hi), r = std::abs(c.ap_poles[q]);
    Lc += d > 0 ? (1 - r * r) / (d * d) : inf;
  }
  Eigen::VectorXd d(c.n + c.K);
  for (int k = 0; k < c.n + c.K; ++k)
    d[k] = std::min(c.D0 + double(k / c.m) * c.H0 * c.L0, Dc + double(k / c.m) * Hc * Lc);
  return d;
}

Piece evaluate_piece(const BandContext& c, const Cell& cell, double wi, double eta) {
  const UncertaintySet& S = c.S;
  const int n = c.n;
  const double plo = wi - eta, phi = wi + eta;
  const Eigen::VectorXd dk = local_slopes(c, plo, phi);
  const LocalTf nom = local_tf(c.nominal.b, c.nominal.a, c.nom_poles, plo, phi);
  const Eigen::VectorXcd Fi = S.basis.frequency_responses(wi, n + c.K);
  const Eigen::VectorXcd dF = Fi - cell.Fj;
  double g = 2 * S.tail_remainder, direct = S.tail_remainder;
  double lipg = c.wg.dot(dk), lipd = std::min(c.Gder, nom.der) + c.wd.dot(dk);
  for (int k = 0; k < n + c.K; ++k) {
    g += c.wg[k] * std::abs(dF[k]);
    direct += c.wg[k] * std::abs(Fi[k]);
  }
  if (c.ellipsoid) {  // slope: |F'^T e| <= s sqrt(d^T |P| d), |F_k'| <= d_k
    g += ellipsoid_term(c, dF.head(n));
    direct += ellipsoid_term(c, Fi.head(n));
    lipg += S.theta_scale * std::sqrt(std::max(0.0, dk.head(n).dot(c.Pabs * dk.head(n))));
  }
  const std::complex<double> Gi = Fi.head(n).transpose() * c.th, Ghi = c.nominal(wi);
  const std::complex<double> delta = (Gi - cell.Gr) - (Ghi - cell.Gh);
  direct += std::abs(Gi - Ghi);
  const double value = std::min(S.regions[cell.j].max_distance(cell.Gh - delta) + g, direct);
  // |W| on the piece: 1 / (|h(w_i)| - eta sup|h'|) where positive (local), else the global slope.
  const double hi_abs = std::abs(polynomial_at(c.h, wi)), hlo = hi_abs - eta * c.hder;
  const double Wi = std::min(1 / hi_abs + eta * c.Wder, hlo > 0 ? 1 / hlo : inf);
  return {Wi * (value + eta * (lipd + lipg)), value / hi_abs, cell.j, wi, eta};
}

BandContext band_context(const UncertaintySet& S, const TransferFunction& nominal, const Eigen::Ref<const Eigen::VectorXd>& h,
                         double Wder, double Gder) {
  BandContext c{S, nominal, h};
  const OrthonormalBasis& basis = S.basis;
  c.Wder = Wder;
  c.Gder = Gder;
  c.hder = polynomial_derivative_bound(h);  // >= sup|h'|
  c.n = static_cast<int>(S.theta_ref.size());
  c.K = static_cast<int>(S.tail_coefficients.size());
  c.m = basis.block();
  c.D0 = basis.front_derivative_bound();
  c.H0 = basis.hinf_bound();
  c.L0 = basis.allpass_derivative_bound();
  for (const auto& f : basis.fronts()) c.front_poles.push_back(f.poles());
  c.ap_poles = basis.allpass().poles();
  c.nom_poles = nominal.poles();
  c.ellipsoid = S.theta_covariance.rows() == c.n && S.theta_offset.size() == c.n && c.n > 0;
  if (c.ellipsoid) c.Pabs = S.theta_covariance.cwiseAbs();
  c.wg.resize(c.n + c.K);
  c.wd.resize(c.n + c.K);
  if (c.ellipsoid)
    c.wg << S.theta_offset, S.tail_coefficients;
  else
    c.wg << S.theta_radius, S.tail_coefficients;
  c.wd << S.theta_ref.cwiseAbs(), Eigen::VectorXd::Zero(c.K);
  c.th = S.theta_ref.cast<std::complex<double>>();
  return c;
}

// Adaptive pieces: start with `initial` pieces per cell, then halve the piece with the largest
// bound until that bound is within `tolerance` (relative) of the largest value at a centre (no
// refinement can go below it), or `budget` more pieces have been evaluated. The answer is the
// largest bound over a partition of [0, pi], whichever piece stops the refinement.
double data_bound(const UncertaintySet& S, const TransferFunction& nominal, const Eigen::Ref<const Eigen::VectorXd>& h, double Wder,
                  double Gder, double& kappa) {
  const int n = static_cast<int>(S.theta_ref.size());
  if (n == 0 || S.theta_radius.size() != n) {
    kappa = inf;
    return inf;
  }
  const BandContext c = band_context(S, nominal, h, Wder, Gder);
  // Global slope kappa (reported): sum_k radius_k sup|F_k'| + sup|T'|.
  kappa = S.tail_beta;
  for (int k = 0; k < n; ++k) kappa += S.theta_radius[k] * (c.D0 + double(k / c.m) * c.H0 * c.L0);
  const auto& w = S.frequencies;
  const int nw = static_cast<int>(w.size()), initial = 16, budget = 64 * nw;
  const double tolerance = 0.01;
  std::vector<Cell> cells(nw);
  std::vector<Piece> heap;
  double best_point = 0;
  for (int j = 0; j < nw; ++j) {
    Cell& cell = cells[j];
    cell.j = j;
    cell.lo = j == 0 ? 0 : 0.5 * (w[j - 1] + w[j]);
    cell.hi = j == nw - 1 ? pi : 0.5 * (w[j] + w[j + 1]);
    cell.Fj = S.basis.frequency_responses(w[j], c.n + c.K);
    cell.Gr = cell.Fj.head(n).transpose() * c.th;
    cell.Gh = nominal(w[j]);
    const double eta = (cell.hi - cell.lo) / (2 * initial);
    for (int i = 0; i < initial; ++i) {
      heap.push_back(evaluate_piece(c, cell, cell.lo + (2 * i + 1) * eta, eta));
      best_point = std::max(best_point, heap.back().point);
    }
  }
  std::make_heap(heap.begin(), heap.end());
  for (int spent = 0; spent < budget && heap.front().bound > (1 + tolerance) * best_point; spent += 2) {
    std::pop_heap(heap.begin(), heap.end());
    const Piece p = heap.back();
    heap.pop_back();
    for (double side : {-0.5, 0.5}) {
      heap.push_back(evaluate_piece(c, cells[p.cell], p.centre + side * p.eta, 0.5 * p.eta));
      best_point = std::max(best_point, heap.back().point);
      std::push_heap(heap.begin(), heap.end());
    }
  }
  return heap.front().bound;
}
}  // namespace

BoundResult error_bound(const UncertaintySet& S, const TransferFunction& nominal, const Eigen::Ref<const Eigen::VectorXd>& h) {
  const auto& w = S.frequencies;
  const int nw = static_cast<int>(w.size());
  BoundResult B;
  B.delta_u.resize(nw);
  B.lambda.resize(nw);
  B.beta.resize(nw);
  // sup-norm bounds (rigorous: grid minimum less a Lipschitz remainder, see poly_min_modulus).
  const double hmin = poly_min_modulus(h), amin = poly_min_modulus(nominal.a);
  if (!(hmin > 0)) throw NumericalError("bound: |W^-1| is not certified away from zero");
  if (!(amin > 0)) throw NumericalError("bound: the nominal denominator is not certified away from zero");
  const double Wmax = 1 / hmin, Wder = polynomial_derivative_bound(h) / (hmin * hmin);
  const double Gder = polynomial_derivative_bound(nominal.b) / amin + nominal.b.cwiseAbs().sum() * polynomial_derivative_bound(nominal.a) / (amin * amin);
  const double s = S.beta1 + Gder;  // sup |d/dw (G - Ghat)|
  B.b_prior = 0;
  B.b_grid = 0;
  B.b_data = data_bound(S, nominal, h, Wder, Gder, B.kappa);
  for (int j = 0; j < nw; ++j) {
    const double lo = j == 0 ? 0 : 0.5 * (w[j - 1] + w[j]), hi = j == nw - 1 ? pi : 0.5 * (w[j] + w[j + 1]);
    B.lambda[j] = std::max(w[j] - lo, hi - w[j]);
    const double delta = S.regions[j].max_distance(nominal(w[j]));
    B.delta_u[j] = delta / std::abs(polynomial_at(h, w[j]));
    // |d/dw W(G - Ghat)| <= |W'| |G - Ghat| + |W| |G' - Ghat'| in the cell of w_j.
    B.beta[j] = Wder * (delta + B.lambda[j] * s) + Wmax * s;
    B.b_prior = std::max(B.b_prior, B.delta_u[j] + B.lambda[j] * B.beta[j]);
    B.b_grid = std::max(B.b_grid, B.delta_u[j]);
  }
  B.b = std::min(B.b_prior, B.b_data);
  return B;
}

HinfBoundResult hinf_bound(const HinfData& data, const HinfStructure& structure, const HinfBoundOptions& o) {
  HinfBoundResult r;
  r.set = uncertainty_set(data.u, data.y, structure.basis, structure.order, structure.grid, structure.priors,
                          o.uncertainty, data.r);
  if (r.set.empty()) return r;
  r.nominal = fit_nominal(r.set, o.nominal);
  r.delta = additive_error(r.set, r.nominal.model);
  // Default W1 = 1/delta: minimise the largest relative over-bound |W^-1|^2/delta^2 - 1, so the
  // bound follows delta at every level rather than only near its peak.
  WeightOptions wo = o.weight;
  if (wo.weight.size() == 0) wo.weight = r.delta.cwiseMax(1e-12 * r.delta.maxCoeff()).cwiseInverse();
  r.weight = fit_weight(structure.grid, r.delta, wo);
  r.bound = error_bound(r.set, r.nominal.model, r.weight.h);
  r.unweighted = error_bound(r.set, r.nominal.model, Eigen::VectorXd::Ones(1));
  return r;
}

Eigen::VectorXd midpoint_grid(int points, double w_min, double w_max) {
  Eigen::VectorXd grid(points);
  for (int j = 0; j < points; ++j) grid[j] = w_min + (w_max - w_min) * (j + 0.5) / points;
  return grid;
}

double weighted_error(const std::function<std::complex<double>(double)>& G, const TransferFunction& nominal,
                      const Eigen::Ref<const Eigen::VectorXd>& h, int dense_points) {
  double e = 0;
  for (int i = 0; i < dense_points; ++i) {
    const double w = pi * i / (dense_points - 1);
    e = std::max(e, std::abs(G(w) - nominal(w)) / std::abs(polynomial_at(h, w)));
  }
  return e;
}

}  // namespace sets
