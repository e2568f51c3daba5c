#include "sets/methods/tv_bound/tv_relinearisation.hpp"

#include <string>

#include "sets/core/error.hpp"

namespace sets {

TvRelinearisedResult relinearised_linf_bound(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                                             const Eigen::Ref<const Eigen::MatrixXd>& u,
                                             const Eigen::Ref<const Eigen::MatrixXd>& y,
                                             const std::vector<WindowNorm>& windows, int iterations,
                                             LinfBoundOptions options) {
  if (iterations < 0)
    throw InputError("relinearised_linf_bound: iterations is " + std::to_string(iterations) + ", must be >= 0");
  TvRelinearisedResult r{{}, {biaffine_regression(model, x0, u), y, windows}, {}};
  r.data.validate();
  const WindowNormBall ball = r.data.ball();
  // The paper's h, from the nominal model, fixed for every step (not with a known eps, which
  // replaces the h-term).
  if (options.h.size() == 0 && options.epsilon.size() == 0) options.h = paper_epsilon_weight(r.data);
  for (int m = 0; m <= iterations; ++m) {
    if (m > 0) r.data.regression = linearised_regression(model, x0, u, r.linf.pi);
    r.linf = linf_bound(r.data, options);
    if (r.linf.falsified()) break;  // no trajectory to linearise around
    TvRelinearisationStep s;
    s.objective = r.linf.objective;
    s.epsilon = r.linf.epsilon;
    s.bound = r.linf.bound;
    s.max_change = (r.linf.pi - r.data.regression.pi_bar).cwiseAbs().maxCoeff();
    s.exact_residual = ball.norms(stack_samples(y - simulate(model, x0, u, r.linf.pi).y));
    r.steps.push_back(std::move(s));
  }
  return r;
}

}  // namespace sets
