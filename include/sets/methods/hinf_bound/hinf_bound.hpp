#pragma once
// Hakvoort & Van den Hof, "A practically feasible procedure for identification of H-infinity error
// bounds": from time-domain data to an uncertainty set G(Ghat, W, b) = {G : ||W (Ghat - G)||_inf <= b}.
//
//   1. uncertainty_set  : per-frequency regions P(w_j) (rectangle or ellipse) that contain G0(w_j),
//                         from a high-order basis model and the four terms of eq. (11), or (worst
//                         case, |v| <= vbar) from LPs over the feasible parameter set; beta1 (12).
//   2. fit_nominal      : Chebyshev centres (16), then a stable low-order model minimising the
//                         weighted maximum amplitude error on the grid (17), as a sequence of LPs.
//   3. fit_weight       : |W^-1|^2 as a positive trigonometric polynomial >= delta^2 (LP), then a
//                         spectral factor: W^-1 stable and minimum phase.
//   4. error_bound      : b = max_j [delta_u(w_j) + lambda_j beta_j].
//                         b_data: the same with the between-grid term from the set's coefficient
//                         box and the tail prior (shrinks with N; for G0, not every G in S).
//
// Every bound is derived in docs/methods/hinf-bound.md. The stochastic variant holds with the
// stated probability only asymptotically (Gaussian limit, estimated noise covariance); the
// worst-case variant is guaranteed given its priors.

#include <Eigen/Core>

#include <complex>
#include <functional>
#include <string>
#include <vector>

#include "sets/fps/falsification.hpp"
#include "sets/models/orthonormal_basis.hpp"
#include "sets/models/transfer_function.hpp"

namespace sets {

/// Priors on the true system G0 = sum_k g0(k) F_k.
struct HinfPriors {
  double M = 1;        // |g0(k)| <= M rho^k  (basis coefficients; eqs. 4-5 with k* = 0)
  double rho = 0.9;
  double u_bar = 1;    // |u(t)| <= u_bar for t <= 0 (before the data)
  // Impulse-response envelope for the initial-condition term: |h0(s)| <= M_ic rho_ic^s, s >= 1.
  // For the FIR basis h0(s) = g0(s-1), so the defaults (<= 0: derive) are M/rho and rho.
  double M_ic = -1;
  double rho_ic = -1;
};

enum class NoiseModel { stochastic, bounded };
enum class RegionShape { rectangle, ellipse };

struct UncertaintyOptions {
  NoiseModel noise = NoiseModel::stochastic;
  RegionShape shape = RegionShape::rectangle;  // bounded noise always gives rectangles
  double alpha = 0.95;       // probability that G0 lies in S (stochastic)
  bool simultaneous = true;  // Bonferroni over the grid; false: alpha per frequency (the paper's)
  double v_bar = 0;          // |v(t)| <= v_bar (bounded)
  int max_lag = -1;          // noise covariance lags (<0: min(100, rows/10))
  int first_sample = -1;     // first regression row (<0: where the initial-condition bound is small)
  int tail_terms = -1;       // basis functions of the tail evaluated exactly (<0: automatic)
  // Stochastic: the failure probability 1 - alpha of the full-band bound b is split between the
  // regions, (1 - alpha) / (1 + share), and the coefficient set of theta0 that b_data uses,
  // share (1 - alpha) / (1 + share), so that b holds with probability >= alpha (union bound).
  // With simultaneous = false (the paper's per-frequency alpha) the regions keep alpha per
  // frequency and the coefficient set gets share (1 - alpha).
  double coefficient_share = 0.1;
};

/// A convex region of the complex plane: a rectangle (centre +- half widths) or an ellipse
/// {centre + x : x^T Q^-1 x <= 1} in (Re, Im) coordinates.
struct FrequencyRegion {
  RegionShape shape = RegionShape::rectangle;
  std::complex<double> centre;
  double half_re = 0, half_im = 0;  // rectangle half widths; for an ellipse, its bounding box
  Eigen::Matrix2d Q = Eigen::Matrix2d::Zero();

  bool contains(std::complex<double> g, double tolerance = 0) const;
  /// An upper bound on max_{g in region} |g - p| (exact for rectangles; for ellipses the
  /// sampled maximum plus a certified Lipschitz remainder, below 1e-9 relative).
  double max_distance(std::complex<double> p) const;
  /// Points on the boundary (for plots).
  std::vector<std::complex<double>> boundary(int points = 64) const;
};

/// The four terms of eq. (11) at one frequency, for the real and the imaginary part.
struct ErrorTerms {
  double noise_re = 0, noise_im = 0;        // f1 (already scaled by the quantile)
  double tail_est_re = 0, tail_est_im = 0;  // f2: tail through the estimate
  double ic_re = 0, ic_im = 0;              // f3: unknown initial conditions
  double tail_re = 0, tail_im = 0;          // f4: the tail itself
};

struct UncertaintySet {
  Eigen::VectorXd frequencies;
  std::vector<FrequencyRegion> regions;
  Eigen::VectorXcd estimate;   // Gbar(w_j) of the high-order model (LS/IV)
  std::vector<ErrorTerms> terms;
  Eigen::VectorXd theta;       // estimated basis coefficients
  double beta1 = 0;            // sup |dG/dw| over G in S, eq. (12)
  // For the data-based interpolation (b_data): |theta0_k - theta_ref_k| <= theta_radius_k
  // (bounded noise: the certified PUI box; stochastic: at level coefficient_level, Bonferroni over
  // k) and tail_beta >= sup|dT/dw| for the tail T = sum_{k>=n} g0(k) F_k (prior only).
  // Stochastic, tighter and used by b_data instead of the box: theta_ref - theta0 = e + d with the
  // noise part e in the ellipsoid {e : e^T P^-1 e <= theta_scale^2} (P = theta_covariance,
  // theta_scale^2 the chi^2_n quantile at coefficient_level) and |d_k| <= theta_offset_k (the
  // tail-through-estimate and initial-condition parts, worst case).
  OrthonormalBasis basis = OrthonormalBasis::fir();
  Eigen::VectorXd theta_ref, theta_radius;
  Eigen::MatrixXd theta_covariance;
  Eigen::VectorXd theta_offset;
  double theta_scale = 0;
  double tail_beta = 0;
  Eigen::VectorXd tail_coefficients;  // M rho^k, k = n .. n+K-1 (tail terms evaluated exactly)
  double tail_remainder = 0;          // >= sup|sum_{k>=n+K} g0(k) F_k|
  double coefficient_level = 0;
  double level = 0;            // probability level used at each frequency (stochastic)
  double noise_variance = 0;   // R_v(0) estimate (stochastic)
  int first_sample = 0, tail_terms = 0, rows = 0;
  /// Bounded noise: do the data falsify the priors? (the verdict of the FPS's support LPs; `yes`
  /// only with an exact certificate). Stochastic noise: `unknown`, not asked.
  ConsistencyVerdict consistency;
  bool empty() const { return consistency.certified_falsified(); }
  int lp_solves = 0;
};

/// Checks a frequency grid: finite, strictly increasing, inside [0, pi]; throws InputError.
void check_frequency_grid(const Eigen::Ref<const Eigen::VectorXd>& grid);
/// Checks the priors (0 < rho < 1, M > 0, u_bar >= 0, ...); throws InputError naming the field.
void check_priors(const HinfPriors& priors);

/// Step 1. u, y: data; instrument (empty, or of the same length): reference for instrumental
/// variables (closed loop); order: number of basis functions n.
UncertaintySet uncertainty_set(const Eigen::Ref<const Eigen::VectorXd>& u,
                               const Eigen::Ref<const Eigen::VectorXd>& y, const OrthonormalBasis& basis,
                               int order, const Eigen::Ref<const Eigen::VectorXd>& grid,
                               const HinfPriors& priors, const UncertaintyOptions& options = {},
                               const Eigen::Ref<const Eigen::VectorXd>& instrument = Eigen::VectorXd());

/// The former name of TransferFunction in this method (kept for source compatibility).
using RationalModel = TransferFunction;

struct NominalOptions {
  int order = 2;                // denominator and numerator degree
  int polygon_sides = 16;       // K: |z| <= t replaced by K half-planes
  int iterations = 20;
  Eigen::VectorXd weight;       // W1(w_j) >= 0; empty: 1
};

struct NominalFit {
  TransferFunction model;
  Eigen::VectorXcd centres;     // Chebyshev centres (16)
  double max_error = 0;         // max_j W1 |Gc - Ghat| (true modulus)
  int polygon_sides = 0;
  int iterations = 0;
};

/// Step 2. Throws InputError if the order cannot be met on this grid (too few frequencies).
NominalFit fit_nominal(const UncertaintySet& set, const NominalOptions& options = {});
/// delta(w_j) = max_{G in P(w_j)} |G - Ghat(w_j)|.
Eigen::VectorXd additive_error(const UncertaintySet& set, const TransferFunction& nominal);

struct WeightOptions {
  int degree = 12;        // degree m of the trigonometric polynomial |W^-1|^2
  Eigen::VectorXd weight; // W1(w_j); empty: 1
};

struct WeightFit {
  Eigen::VectorXd trig;   // |W^-1(e^iw)|^2 = c0 + sum_k c_k cos(k w)
  Eigen::VectorXd h;      // W^-1(z) = sum_k h_k z^-k, minimum phase
  double max_gap = 0;     // max_j W1^2 (|W^-1|^2 - delta^2)
  std::complex<double> inverse(double w) const;  // W^-1(e^iw)
};

/// Step 3. W^-1 stays above delta on the grid.
WeightFit fit_weight(const Eigen::Ref<const Eigen::VectorXd>& grid, const Eigen::Ref<const Eigen::VectorXd>& delta,
                     const WeightOptions& options = {});

struct BoundResult {
  // The full-band bound: ||W (G0 - Ghat)||_inf <= b on [0, pi], min(b_prior, b_data) (both hold
  // on the event that b_data holds: guaranteed for bounded noise, probability >= alpha otherwise).
  double b = 0;
  double b_prior = 0;     // max_j [delta_u + lambda_j beta_j]: the paper's bound, slope from the prior (12)
  double b_grid = 0;      // max_j delta_u(w_j): the bound on the grid only
  // Data-based bound on [0, pi]: the between-grid term from the coefficient set of theta0
  // (ellipsoid + offsets, or the box) and the tail prior only, certified on a sub-grid of every
  // cell (docs/methods/hinf-bound.md, section 6). Infinite if the set carries no coefficient set.
  double b_data = 0;
  double kappa = 0;       // sum_k theta_radius_k sup|F_k'| + tail_beta: slope of the unknown part
  Eigen::VectorXd delta_u, lambda, beta;
};

/// Step 4. weight: W^-1 as an FIR (WeightFit::h); pass h = [1] for W = 1.
BoundResult error_bound(const UncertaintySet& set, const TransferFunction& nominal, const Eigen::Ref<const Eigen::VectorXd>& h);

struct HinfBoundOptions {
  UncertaintyOptions uncertainty;
  NominalOptions nominal;
  WeightOptions weight;
};

struct HinfBoundResult {
  UncertaintySet set;
  NominalFit nominal;
  Eigen::VectorXd delta;
  WeightFit weight;
  BoundResult bound;
  BoundResult unweighted;  // W = 1: an additive H-infinity bound
};

/// Time-domain data of one experiment: u and y; r (empty, or of the same length) is a reference
/// signal used as instrumental variables (closed-loop data).
struct HinfData {
  Eigen::VectorXd u, y, r;
};

/// What is assumed of the true system: the basis and its number of functions n, the priors, and
/// the frequency grid of the per-frequency regions (inside [0, pi], increasing).
struct HinfStructure {
  OrthonormalBasis basis = OrthonormalBasis::fir();
  int order = 0;
  HinfPriors priors;
  Eigen::VectorXd grid;
};

/// `points` frequencies at the midpoints of equal cells of [w_min, w_max].
Eigen::VectorXd midpoint_grid(int points, double w_min, double w_max);

/// The method's entry point: all four steps on one data set. If the bounded-noise data falsify
/// the priors, result.set.empty is true and the later steps are skipped.
HinfBoundResult hinf_bound(const HinfData& data, const HinfStructure& structure, const HinfBoundOptions& options = {});

/// max over the dense grid of |W(e^iw) (G(e^iw) - Ghat(e^iw))|, W = 1/h.
double weighted_error(const std::function<std::complex<double>(double)>& G, const TransferFunction& nominal,
                      const Eigen::Ref<const Eigen::VectorXd>& h, int dense_points = 4096);

}  // namespace sets
