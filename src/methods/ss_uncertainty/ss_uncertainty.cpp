#include "sets/methods/ss_uncertainty/ss_uncertainty.hpp"

namespace sets {

SsUncertaintyResult ss_uncertainty(const Eigen::Ref<const Eigen::MatrixXd>& u,
                                   const Eigen::Ref<const Eigen::MatrixXd>& y, const SsUncertaintyOptions& options) {
  SsUncertaintyResult r;
  r.identification = identify_propagator(u, y, options.identification);
  r.estimate_level_set = level_set_domain(r.identification, options.level);  // reuses its least squares
  r.estimate_fps = regression_fps(r.identification.regression, r.estimate_level_set.ell_per_equation);
  if (options.estimate_fps_pui) r.estimate_fps_pui = pui(r.estimate_fps);
  if (options.guaranteed) {
    r.state_enclosure = enclose_states(r.identification, u, y, *options.guaranteed);
    r.guaranteed_fps = guaranteed_fps(r.identification, u, y, *r.state_enclosure, options.guaranteed->noise_bound);
    if (options.guaranteed_pui) r.guaranteed_pui = pui(*r.guaranteed_fps);
  }
  return r;
}

}  // namespace sets
