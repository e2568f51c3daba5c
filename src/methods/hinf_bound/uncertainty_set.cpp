// Step 1 of Hakvoort-Van den Hof: the per-frequency regions that contain G0 (bounded or stochastic noise).
#include "sets/methods/hinf_bound/hinf_bound.hpp"

#include <Eigen/Dense>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>

#include <algorithm>
#include <iterator>
#include <cmath>

#include "sets/core/error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/linear_program.hpp"
#include "hinf_common.hpp"

namespace sets {

using namespace hinf_detail;

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

}  // namespace sets
