#pragma once
// Re-linearised l-infinity method (an extension of Salehpour & Johansson, not in the paper).
//
// The biaffine approximation (2) expands (1) around pi = 0; with large perturbations its error
// r dominates nu = r + eta, and the true trajectory no longer fits the window-norm ball of (8) or
// (14). The sequential LP below re-expands (1) around the current estimate and solves (8) again:
//
//   Pi_0 = argmin (8) on linearised_regression(pi_bar = 0)          (= linf_bound on (2))
//   Pi_m = argmin (8) on linearised_regression(pi_bar = Pi_{m-1}),   m = 1..K
//
// with the weights F, G and h held fixed (h from the nominal model, 1/||y_m - C zeta||_w, so the
// objective means the same in every step). The last linearisation is returned with its estimate so
// that the MILP (14) can be solved on it with the same eps (the l-inf estimate stays feasible).

#include <Eigen/Core>

#include <vector>

#include "sets/models/time_varying_model.hpp"
#include "sets/methods/tv_bound/tv_bound.hpp"

namespace sets {

/// One LP of the sequence.
struct TvRelinearisationStep {
  double objective = 0;           // of (8) on this step's linearisation
  Eigen::VectorXd epsilon;        // eps-hat per output
  Eigen::VectorXd bound;          // rho-hat = max_k |pi-hat(k)|
  double max_change = 0;          // max_{k,i} |pi-hat_i(k) - pi_bar_i(k)| (pi_bar: the linearisation point)
  /// Window norm per output of y_m - C x(pi-hat), x simulated with the exact model (1): how well the
  /// estimate explains the data without any approximation.
  Eigen::VectorXd exact_residual;
};

struct TvRelinearisedResult {
  TvBoundResult linf;  // the estimate of the last LP
  TvBoundData data;    // the linearisation the last LP used (around the previous estimate)
  std::vector<TvRelinearisationStep> steps;  // iterations + 1 entries, the first on (2)
};

/// Runs 1 + iterations LPs as above on the measured outputs y ((N+1) x l) of the model with
/// x(0) = x0 and input u (N x p). iterations = 0 is linf_bound on (2). options.h empty = the
/// paper's h from the nominal model, kept for every step. Throws InputError on bad input
/// (including iterations < 0) and NumericalError if an LP fails.
TvRelinearisedResult relinearised_linf_bound(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                                             const Eigen::Ref<const Eigen::MatrixXd>& u,
                                             const Eigen::Ref<const Eigen::MatrixXd>& y,
                                             const std::vector<WindowNorm>& windows, int iterations,
                                             LinfBoundOptions options = {});

}  // namespace sets
