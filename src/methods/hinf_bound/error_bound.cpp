// Step 4 of Hakvoort-Van den Hof: the bound on ||W (G0 - Ghat)||_inf over all of [0, pi].
#include "sets/methods/hinf_bound/hinf_bound.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"
#include "hinf_common.hpp"

namespace sets {

using namespace hinf_detail;

namespace {
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

}  // namespace sets
