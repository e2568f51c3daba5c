#pragma once
// Guaranteed parameter intervals from an equation-error regression of one state equation of a
// model file, for parameters that enter it linearly (after multiplying by at most one "inertia"
// parameter, e.g. the mass in v' = (F - Fc*sign(v) - offset)/M). The equation is integrated
// once (state measured) or twice (state = derivative of a measured state) over a sliding window,
// which turns the derivative into differences of measurements and averages out what the model
// leaves out at high frequency. Regressors that depend on a differentiated state are intervals
// (the state's noise bound); the equation error is bounded by a stated delta. The result is the
// PUI box of that FPS (sets/feasible_parameter_set.hpp). See docs/methods/diagnosis.md.

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

/// PUIs of the free parameters of the equation of `state`, with the model's parameter values as
/// the estimate the bound is measured at. Never throws for a model it cannot handle: `built` is
/// then false and `note` says why (an unmeasured state, prev(), a parameter entering nonlinearly).
EquationErrorResult equation_error_pui(const ModelFile& model, const Recording& data, const std::string& state,
                                       const EquationErrorOptions& options = {});

}  // namespace sets
