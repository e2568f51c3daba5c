#pragma once
// Cerone & Regruto's method: the interval regression of the LPV model (sets/models/lpv_model.hpp)
// goes into a FeasibleParameterSet, whose orthant rows use the exact interval ends: that is
// eqs. 27–39 (centre +- radius, sign-selected), and `pui()` gives the PUIs (eq. 40) and the
// central estimate (41–42).

#include <vector>

#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/models/lpv_model.hpp"

namespace sets {

struct LpvPuiResult {
  LpvRegression regression;
  PuiResult pui;
  std::vector<int> falsifying_times;  // sample indices t of pui.consistency.conflict
};

/// PUIs and central estimate of the LPV model's (outer-approximated) feasible parameter set.
LpvPuiResult lpv_pui(const LpvModelStructure& model, const LpvMeasurements& data, const PuiOptions& options = {},
                     const RangeOptions& range = {});

}  // namespace sets
