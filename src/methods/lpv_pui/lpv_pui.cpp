#include "sets/methods/lpv_pui/lpv_pui.hpp"

namespace sets {

LpvPuiResult lpv_pui(const LpvModelStructure& model, const LpvMeasurements& data, const PuiOptions& options,
                     const RangeOptions& range) {
  LpvPuiResult r;
  r.regression = lpv_regression(model, data, range);
  const FeasibleParameterSet fps = FeasibleParameterSet::from_interval_data(r.regression.Phi, r.regression.Y);
  r.pui = pui(fps, options);
  for (int row : r.pui.consistency.conflict.samples) r.falsifying_times.push_back(r.regression.time[static_cast<std::size_t>(row)]);
  return r;
}

}  // namespace sets
