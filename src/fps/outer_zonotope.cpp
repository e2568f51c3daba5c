#include "sets/fps/outer_zonotope.hpp"

#include <cmath>
#include <string>

#include "sets/core/error.hpp"

namespace sets {

Zonotope outer_zonotope(const FeasibleParameterSet& fps, const FpsZonotopeOptions& options) {
  if (fps.has_interval_regressors())
    throw UnsupportedError(
        "outer_zonotope: the FPS has interval regressors (not convex); use pui() or the orthant "
        "polytopes");
  Zonotope Z;
  if (options.initial) {
    Z = *options.initial;
    if (Z.dimension() != fps.dimension())
      throw InputError("outer_zonotope: initial zonotope has the wrong dimension");
  } else {
    const PuiResult r = pui(fps);
    if (r.empty()) throw EmptySetError("outer_zonotope: " + r.consistency.message());
    if (r.consistency.falsified == Falsified::unknown && !(lower(r.box).allFinite() && upper(r.box).allFinite()))
      throw NumericalError("outer_zonotope: " + r.consistency.message());
    for (int i = 0; i < fps.dimension(); ++i)
      if (!std::isfinite(r.box[i].lower()) || !std::isfinite(r.box[i].upper()))
        throw InputError("outer_zonotope: parameter " + std::to_string(i) +
                         " is unbounded by the data; give an initial zonotope");
    Z = Zonotope::from_box(r.box);
  }
  const auto Phi = fps.regressors();
  const auto Y = fps.outputs();
  for (int t = 0; t < fps.size(); ++t) {
    const Eigen::VectorXd phi = lower(IntervalVector(Phi.row(t).transpose()));
    const auto next = try_intersect_strip(Z, phi, midpoint(Y[t]), radius(Y[t]));
    if (!next)
      throw EmptySetError("outer_zonotope: sample " + std::to_string(t) +
                          " does not meet the zonotope of the previous samples (data falsify the model)");
    Z = *next;
    if (Z.order() > options.max_order) Z = reduce_order(Z, options.max_order, options.reduction);
  }
  return Z;
}

}  // namespace sets
