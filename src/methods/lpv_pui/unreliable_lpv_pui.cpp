#include "sets/methods/lpv_pui/unreliable_lpv_pui.hpp"

namespace sets {

const char* to_string(RegressorErrors e) {
  switch (e) {
    case RegressorErrors::both: return "both";
    case RegressorErrors::scheduling: return "scheduling";
    case RegressorErrors::output: return "output";
    case RegressorErrors::none: return "none";
  }
  return "?";
}

LpvPuiResult unreliable_lpv_pui(const LpvModelStructure& model, const LpvMeasurements& data, RegressorErrors which,
                                const PuiOptions& options) {
  if (which == RegressorErrors::both) return lpv_pui(model, data, options);
  LpvMeasurements boxes = data;
  if (which != RegressorErrors::output) boxes.delta_eta.setZero();
  if (which != RegressorErrors::scheduling) boxes.delta_eps.setZero();
  LpvPuiResult res;
  res.regression = lpv_regression(model, boxes);
  for (Eigen::Index row = 0; row < res.regression.Y.size(); ++row) {
    const int t = res.regression.time[static_cast<std::size_t>(row)];
    const double bound = data.delta_eta.size() == 1 ? data.delta_eta[0] : data.delta_eta[t];
    res.regression.Y[row] = interval_around(data.y[t], bound);
  }
  res.pui = pui(FeasibleParameterSet::from_interval_data(res.regression.Phi, res.regression.Y), options);
  return res;
}

}  // namespace sets
