#pragma once
// Screening of catalogue hypotheses: which effects, where, could explain the residual of the
// current (calibrated) model, with starting values for their output-error refinement.
//
// Output error, linearised (every hypothesis, wherever it enters): the residual r = y - yhat of
// the current model is regressed on the sensitivities of the outputs to the current model's free
// parameters and to the hypothesis' new parameters, by least squares, so no scale of any
// parameter is assumed. Nonlinear parameters (thresholds, play, Stribeck velocity, yield, delay)
// are taken from grids in units of the data (fractions of a signal's range or RMS, samples): each
// grid point is simulated, the residual change it causes is subtracted first. Consistency with the
// noise bound: the FPS of the linearised strips |r_t - a_t^T x| <= delta_j (sets::find_conflict)
// is not empty. Equation error (where the effect's state equation can be reconstructed from the
// data, sets/diagnosis/equation_error.hpp): least squares of the integrated equation with the new
// term, independent of the current model's parameter values, as a second ranking and a start.
// Two effects at once: pairs of the best single hypotheses, screened by the same least squares with
// both sets of columns (no new simulation). Ranked by the sparsest explanation: misfit x
// tolerance^(number of new parameters).

#include <Eigen/Core>

#include <limits>
#include <string>
#include <vector>

#include "sets/diagnosis/physics_catalogue.hpp"
#include "sets/data/recording.hpp"

namespace sets {

struct ScreeningOptions {
  int substeps = 2;                  // RK4 substeps of the screening simulations
  int threads = 2;
  double sparsity_tolerance = 1.25;  // the misfit a new parameter must buy: factor per parameter
  std::vector<double> noise_bound;   // per output, for the consistency test (empty: not tested)
  bool equation_error = true;        // also screen by equation error where possible
  int pairs = 6;                     // two effects at once: every compatible pair of the best this
                                     // many single hypotheses (0: none)
};

struct ScreenedHypothesis {
  Candidate candidate;                  // its model holds the best start's values
  std::vector<Eigen::VectorXd> starts;  // parameter vectors (candidate model order), best first
  double cost = 0;       // linearised misfit after the least-squares step (sum over outputs of
                         // ||r_j||^2 / ||y_j - mean y_j||^2, the calibration's cost)
  double gain = 0;       // 1 - cost / baseline
  double score = 0;      // cost * sparsity_tolerance^new_parameters
  int new_parameters = 0;
  bool consistent = false;  // the linearised strips under the noise bound have a common point
  double ee_gain = std::numeric_limits<double>::quiet_NaN();  // equation-error gain, NaN: not built
  std::string note;
  // Its least-squares step at its best grid point (weighted outputs), kept to screen pairs: the
  // sensitivity columns of its new parameters, the output change of the grid point, their bounds.
  Eigen::MatrixXd columns;
  Eigen::VectorXd shift, lower, upper;
};

struct Screening {
  double baseline = 0;  // the current model's linearised misfit (its own parameters re-fitted)
  std::vector<ScreenedHypothesis> ranked;  // best score first
  int simulations = 0;
};

/// Screens every candidate against `data` around the current model's parameter values.
Screening screen_hypotheses(const ModelFile& current, const Recording& data, const std::vector<Candidate>& candidates,
                            const ScreeningOptions& options = {});

/// Least squares min ||b - A x|| with some coefficients bounded (lo <= x <= hi; +-inf: free), by
/// fixing violated ones at their bound and solving again (columns are scaled to unit norm first).
Eigen::VectorXd bounded_least_squares(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::VectorXd>& b,
                                      const Eigen::Ref<const Eigen::VectorXd>& lo, const Eigen::Ref<const Eigen::VectorXd>& hi);

}  // namespace sets
