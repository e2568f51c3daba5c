#pragma once
// A zonotope that contains a feasible parameter set (exact regressors), strip by strip.

#include <optional>

#include "sets/domains/zonotope.hpp"
#include "sets/fps/feasible_parameter_set.hpp"

namespace sets {

struct FpsZonotopeOptions {
  double max_order = 10;                     // reduce after each strip when exceeded
  ReductionMethod reduction = ReductionMethod::girard;
  std::optional<Zonotope> initial;           // default: the zonotope of the PUI box
};

/// Outer approximation of a feasible parameter set with exact regressors by a zonotope,
/// processing its strips one by one with the Alamo–Bravo–Camacho update. Throws
/// UnsupportedError for interval regressors, EmptySetError when the data provably falsify the
/// model (or the initial set), InputError if no initial set is given and the PUIs are unbounded.
Zonotope outer_zonotope(const FeasibleParameterSet& fps, const FpsZonotopeOptions& options = {});

}  // namespace sets
