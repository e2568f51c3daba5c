#pragma once
// NOT guaranteed: Cerone & Regruto's PUIs with regressor boxes that leave out some of the
// measurement errors. A diagnostic for docs/reproduction/cerone.md (e.g. `scheduling` is eq. 25
// read literally: min/max over eps only, w_{t-i} taken as y_{t-i}); lpv_pui() is the method.

#include "sets/methods/lpv_pui/lpv_pui.hpp"

namespace sets {

/// Which measurement errors widen the regressor boxes (eqs. 18-26). `both` is the paper's method
/// and the only guaranteed choice.
enum class RegressorErrors { both, scheduling, output, none };

const char* to_string(RegressorErrors e);

/// PUIs with the regressor boxes of `which`; the output strips keep the full Delta eta. With
/// `both` this is lpv_pui(). Not guaranteed otherwise: the true theta may lie outside.
LpvPuiResult unreliable_lpv_pui(const LpvModelStructure& model, const LpvMeasurements& data, RegressorErrors which,
                                const PuiOptions& options = {});

}  // namespace sets
