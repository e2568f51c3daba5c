#pragma once
// Bounds of time-varying parameter perturbations from input/output data (Salehpour & Johansson):
// the l-infinity method (equation 8, one LP) and the sparse-derivative method (equation 14, a
// MILP with the threshold form 12-13). Both return the estimated perturbation trajectory Pi-hat:
// *where in time, and in which parameter, the nominal model has to change to explain the data*.
//
// These are estimates, not guaranteed bounds: rho-hat = max_k |pi-hat(k)| is the smallest
// perturbation (in the method's sense) that explains the data with noise inside the window-norm
// ball; the true perturbation may be larger (the paper's Table I shows under-estimates).

#include <Eigen/Core>

#include <vector>

#include "sets/fps/falsification.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/models/time_varying_model.hpp"
#include "sets/methods/tv_bound/window_norm.hpp"

namespace sets {

/// The data of (8) and (14): measured outputs y_m (N+1 x l) against the regression of the model.
struct TvBoundData {
  BiaffineRegression regression;
  Eigen::MatrixXd y;                // measured outputs, (N+1) x l
  std::vector<WindowNorm> windows;  // one per output, or a single one used for every output

  /// Throws InputError on mismatched dimensions (naming them).
  void validate() const;
  int samples() const { return regression.samples(); }                       // N
  int outputs() const { return static_cast<int>(y.cols()); }                 // l
  int parameters() const;                                                    // q
  WindowNormBall ball() const;
};

/// A sample where the estimated trajectory jumps: |pi-hat_i(k) - pi-hat_i(k-1)| > threshold.
struct TvChange {
  int sample;     // k
  int parameter;  // i (0-based)
  double size;    // pi-hat_i(k) - pi-hat_i(k-1)
};

struct TvBoundResult {
  Eigen::MatrixXd pi;        // Pi-hat, N x q
  Eigen::VectorXd bound;     // rho-hat = max_k |pi-hat(k)|, q
  Eigen::VectorXd epsilon;   // window-norm bound of the residual (found by (8), given to (14))
  Eigen::MatrixXd residual;  // V-hat = y_m - Upsilon - Xi Pi-hat, (N+1) x l
  std::vector<TvChange> changes;  // jumps above the threshold mu (linf: of options.mu if set)
  double objective = 0;
  double seconds = 0;
  // MILP only (for the LP: status optimal, gap 0).
  MilpStatus status = MilpStatus::optimal;
  double best_bound = 0;  // jump_search: certified lower bound on the optimum; glpk_big_m: GLPK's
  double gap = 0;         // (objective - best_bound) / max(1, |objective|)
  long nodes = 0;         // branch-and-bound nodes (jump_search: LPs solved)
  /// linf_bound: do the data falsify the model with the given epsilon? `no` when eps is a variable
  /// of (8) (some eps always explains the data); with a fixed eps, `yes` only with an exactly
  /// verified Farkas certificate (then pi, bound, residual are empty), `unknown` when the LP found
  /// a trajectory in floating point (not verified). MILP: `unknown`.
  ConsistencyVerdict consistency;
  bool falsified() const { return consistency.certified_falsified(); }
};

struct LinfBoundOptions {
  Eigen::VectorXd F;  // diagonal of F (size q); empty = ones
  Eigen::VectorXd G;  // diagonal of G (size q); empty = ones
  /// Weight of eps (size l); empty = 1 / ||y_m - C zeta||_w per output, as in the paper.
  Eigen::VectorXd h;
  /// A known window-norm bound of the noise (size l, >= 0), e.g. from another method (the paper,
  /// end of Section VI). Empty = eps is a variable of (8), weighted by h (the paper's form). When
  /// given, (8) is solved with eps fixed and without the h^T eps term (h must then be empty).
  Eigen::VectorXd epsilon;
  /// Delta pi(0) = pi(0) - pi(-1) with pi(-1) = 0 (the model is nominal before the data) when
  /// true; Delta pi(0) is left out when false.
  bool initial_difference = true;
  /// Threshold used only to list `changes` (size q; empty = 1e-3 * max |pi-hat_i|).
  Eigen::VectorXd mu;
};

/// The paper's weight of eps in (8): h_j = 1 / ||y_m,j - (C zeta)_j||_w, the default of
/// LinfBoundOptions::h. Throws InputError if an output equals the nominal model exactly.
Eigen::VectorXd paper_epsilon_weight(const TvBoundData& data);

/// Equation (8): min ||(I (x) F) Pi||_inf + ||(I (x) G) Delta Pi||_inf + h^T eps
/// s.t. W |Y_m - Upsilon - Xi Pi| <= 1 (x) eps, as one LP (eps fixed and no h-term when
/// options.epsilon is given). Throws InputError on bad input and NumericalError if GLPK fails or
/// reports no perturbation within the given epsilon without a verifiable certificate; a certified
/// "no perturbation explains the data within epsilon" is the result's `consistency` (falsified()).
TvBoundResult linf_bound(const TvBoundData& data, const LinfBoundOptions& options = {});

/// How (14) is solved. Both solve the same problem (same optimum); they differ in whether they
/// can prove it.
enum class SparseSolver {
  /// Best-first branch and bound over sign-monotone jump patterns with certified LP bounds
  /// (docs/methods/tv-bound.md). `best_bound` is a rigorous lower bound on the optimum.
  jump_search,
  /// The big-M MILP handed to GLPK's branch and cut (`formulation` picks (12)-(13) as printed or
  /// one binary per jump). Kept for comparison: its relaxation is nearly empty, so it rarely
  /// closes the gap on the crane; its best bound is GLPK's floating-point one.
  glpk_big_m,
};

/// The binaries of the glpk_big_m solver.
enum class SparseFormulation {
  paper,          // two binaries per (sample, parameter): equations (12)-(13) as printed
  single_binary,  // one binary: -mu - M d <= Delta pi <= mu + M d (same optimum, no sign symmetry)
};

struct SparseBoundOptions {
  Eigen::VectorXd F;   // diagonal of F (size q); empty = ones
  Eigen::VectorXd mu;  // threshold per parameter (size q), > 0
  /// A-priori box |pi_i(k)| <= max_abs_i (size q, finite): gives the big-M of (12),
  /// M_i = 2 max_abs_i + mu_i (|Delta pi| <= 2 max_abs), instead of the unknown max |s_ij| + mu.
  Eigen::VectorXd max_abs;
  Eigen::VectorXd epsilon;  // window-norm bound per output (from linf_bound)
  /// eps is inflated by this relative amount so the l-inf optimum stays feasible despite rounding.
  double epsilon_slack = 1e-7;
  bool initial_difference = true;
  /// The paper's quantized approximation on a coarser time grid: jumps (|Delta pi| > mu) only at
  /// samples k that are multiples of `grid`; between them pi drifts by at most mu per sample.
  /// 1 = every sample, (14) as written. A coarser grid solves faster and its optimum is an upper
  /// bound of (14)'s (a restriction).
  int grid = 1;
  SparseSolver solver = SparseSolver::jump_search;
  /// jump_search only: first solve the problem on an 8x coarser grid (a quarter of the limits,
  /// to a 2 % gap) and start from its solution, which is feasible here. Upper bounds only; the
  /// certified lower bound never uses it. Applies when the coarse grid keeps >= 8 positions.
  bool coarse_start = true;
  SparseFormulation formulation = SparseFormulation::single_binary;  // glpk_big_m only
  /// Limits and tolerance. jump_search: node_limit counts LPs, relative_gap stops the search
  /// when (objective - bound) / max(1, objective) reaches it; the time limit is wall clock.
  MilpOptions milp{60, 1e-4, false};
  /// Warm start: a trajectory (N x q), e.g. the l-inf estimate; T, the binaries and the peak are
  /// completed from it. Empty = none. Ignored by GLPK if infeasible.
  Eigen::MatrixXd start;
};

/// Equation (14): min 1^T Sigma + ||(I (x) F) Pi||_inf s.t. (13) and the window-norm ball with
/// the given eps. Throws InputError on bad input, NumericalError if GLPK fails or no solution is
/// found within the limits; a run stopped by a limit returns its incumbent with status feasible,
/// the best lower bound and the gap.
TvBoundResult sparse_bound(const TvBoundData& data, const SparseBoundOptions& options);

/// sqrt(mean_k (est_i(k) - truth_i(k))^2) per column.
Eigen::VectorXd rms_tracking_error(const Eigen::Ref<const Eigen::MatrixXd>& estimate, const Eigen::Ref<const Eigen::MatrixXd>& truth);

}  // namespace sets
