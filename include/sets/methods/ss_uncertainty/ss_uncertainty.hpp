#pragma once
// The entry point of Farah, Mercère, Poinot, van Wingerden, "Quantification of model uncertainty
// for a state-space system": one call from input/output data to the identified canonical model
// and its uncertainty domains (docs/methods/propagator_level_sets.md).
//
//   1. propagator subspace least squares (Section III)       -> identification
//   2. the paper's level-set ellipsoid (Section IV)            -> estimate_level_set
//   3. the feasible parameter set of the same regression with |eps| <= l, l read from the
//      least-squares residuals, and its PUIs                   -> estimate_fps, estimate_fps_pui
//   4. with assumptions (a noise bound, and a tail bound or a state-error bound): enclosures of
//      the true states and the feasible parameter set with them as interval regressors, which
//      contains the true parameters whenever the assumptions hold -> guaranteed_fps, guaranteed_pui
//
// Steps 2 and 3 are estimates, not guarantees: l is a statistic of the residuals, not a noise
// bound, and the error of the estimated state is ignored (the paper's footnote 2).

#include <Eigen/Core>

#include <optional>

#include "sets/methods/ss_uncertainty/canonical_fps.hpp"
#include "sets/methods/ss_uncertainty/level_set_uncertainty.hpp"
#include "sets/methods/ss_uncertainty/propagator_identification.hpp"
#include "sets/methods/ss_uncertainty/state_enclosure.hpp"

namespace sets {

struct SsUncertaintyOptions {
  PropagatorOptions identification;
  LevelSetOptions level;
  bool estimate_fps_pui = true;  // PUIs of estimate_fps by LP (the costly part)
  /// Compute the guaranteed set under these assumptions (state_enclosure.hpp); none: skip it.
  std::optional<GuaranteedSetAssumptions> guaranteed;
  bool guaranteed_pui = true;     // its PUIs by LP
};

struct SsUncertaintyResult {
  PropagatorResult identification;
  LevelSetDomain estimate_level_set;      // the paper's ellipsoid (not guaranteed)
  CanonicalFps estimate_fps;              // |y_M - Psi theta| <= l per equation (not guaranteed)
  std::optional<PuiResult> estimate_fps_pui;
  // With options.guaranteed:
  std::optional<StateEnclosure> state_enclosure;  // its contradictions: the data falsify the assumptions
  std::optional<CanonicalFps> guaranteed_fps;
  std::optional<PuiResult> guaranteed_pui;        // empty: the data falsify the assumptions
};

/// Identifies a canonical model from u (N x nu) and y (N x ny), time along rows, and computes
/// its uncertainty domains. Throws InputError for data or options the method cannot use (see
/// identify_propagator and level_set_domain).
SsUncertaintyResult ss_uncertainty(const Eigen::Ref<const Eigen::MatrixXd>& u,
                                   const Eigen::Ref<const Eigen::MatrixXd>& y, const SsUncertaintyOptions& options);

}  // namespace sets
