#pragma once
// Guaranteed parameter intervals from an equation-error regression of one state equation of a
// model file, for parameters that enter it linearly (after multiplying by at most one "inertia"
// parameter, e.g. the mass in v' = (F - Fc*sign(v) - offset)/M). The equation is integrated
// once (state measured) or twice (state = derivative of a measured state) over a sliding window,
// which turns the derivative into differences of measurements and averages out what the model
// leaves out at high frequency. Regressors that depend on a differentiated state are intervals
// (the state's noise bound); the equation error is bounded by a stated delta. The result is the
// PUI box of that FPS (sets/feasible_parameter_set.hpp). See docs/methods/diagnosis.md.

#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

#include "sets/numeric/interval_matrix.hpp"
#include "sets/models/model_file.hpp"
#include "sets/data/recording.hpp"

namespace sets {

struct EquationErrorOptions {
  int window = 0;             // integration window in samples; 0: N/500 within [4, 100]
  double bound_factor = 1.5;  // delta = this x the largest equation error at the model's values
};

struct EquationErrorResult {
  bool built = false;
  std::string note;                     // why it was not built, or the assumptions it rests on
  std::vector<std::string> parameters;  // the regression's unknowns (free parameters of the equation)
  IntervalVector box;                   // their PUIs (parameter units)
  bool guaranteed = false;              // every finite end certified by a safe bound
  double delta = 0;                     // equation-error bound used (units of the integrated equation)
  int rows = 0, window = 0, order = 0;  // strips, window (samples), 1 or 2 integrations
};

/// The noise level (standard deviation, column units) of measured columns, by column name. The
/// noise of a column is a property of the data alone (sets/data/noise_level.hpp, estimated from
/// the column without a model), so a caller that builds many regressions on the same recording
/// (screening: one per hypothesis) estimates it once and passes it in; the results are the same.
using ColumnNoise = std::map<std::string, double>;
/// The noise level of every output column of `model` in `data` (the columns a regression may
/// differentiate), each estimated once.
ColumnNoise measured_noise(const ModelFile& model, const Recording& data);

/// The regression of one window: theta (the free parameters acting on the equation, the inertia
/// first when there is one) satisfies Phi theta in Y + [-delta, delta] at every strip when the
/// integrated equation error is below delta. Phi_mid, Y_mid: the central values (estimates of the
/// differentiated states, no radius); residual: Y_mid - Phi_mid theta at the model's values.
struct EquationErrorRegression {
  bool built = false;
  std::string note;                     // why not, or how it was built
  std::vector<std::string> parameters;  // the unknowns
  std::vector<double> scale;            // a typical size of each (|model value| or 1)
  bool has_inertia = false;             // parameters[0] multiplies the derivative
  IntervalMatrix Phi;
  IntervalVector Y;
  Eigen::MatrixXd Phi_mid;
  Eigen::VectorXd Y_mid, residual;
  int rows = 0, window = 0, order = 0;
  bool from_samples = false;  // sampled signals or prev() evaluated from the measurements at the samples
};
/// One regression per window (samples). Never throws for a model it cannot handle.
/// `noise`: the columns' noise levels when the caller has them (a column missing from it is
/// estimated here).
std::vector<EquationErrorRegression> equation_error_regressions(const ModelFile& model, const Recording& data,
                                                               const std::string& state, const std::vector<int>& windows,
                                                               const ColumnNoise& noise = {});
/// The windows tried by default: N/500 .. N/25 samples within [4, 500], N >= 8 w.
std::vector<int> equation_error_windows(int samples);

/// Least-squares estimates from the equation error (central regressors, one window, default
/// N/200): a starting point, no guarantee (an estimate: errors in the differentiated states bias it).
struct EquationErrorFit {
  bool built = false;
  std::string note;
  std::vector<std::string> parameters;
  std::vector<double> estimate;
  double relative_residual = 1;  // ||Y - Phi theta|| / ||Y - mean Y|| (0: exact)
  bool from_samples = false;     // as EquationErrorRegression::from_samples
};
EquationErrorFit equation_error_fit(const ModelFile& model, const Recording& data, const std::string& state, int window = 0,
                                    const ColumnNoise& noise = {});

/// PUIs of the free parameters of the equation of `state`, with the model's parameter values as
/// the estimate the bound is measured at. Never throws for a model it cannot handle: `built` is
/// then false and `note` says why (an unmeasured state, prev(), a parameter entering nonlinearly).
EquationErrorResult equation_error_pui(const ModelFile& model, const Recording& data, const std::string& state,
                                       const EquationErrorOptions& options = {});

}  // namespace sets
