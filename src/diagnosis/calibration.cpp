#include "sets/diagnosis/calibration.hpp"

#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include <algorithm>
#include <array>
#include <cmath>

namespace sets {

std::vector<double> fits(const Eigen::Ref<const Eigen::MatrixXd>& measured, const Eigen::Ref<const Eigen::MatrixXd>& simulated) {
  std::vector<double> f;
  for (Eigen::Index j = 0; j < measured.cols(); ++j) f.push_back(fit_percent(measured.col(j), simulated.col(j)));
  return f;
}

namespace {

struct Residual {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  const Simulator* sim;
  Eigen::VectorXd base;   // all parameters
  std::vector<int> free;
  Eigen::VectorXd scale;  // theta_free = scale .* z
  Eigen::VectorXd lo, hi;
  Eigen::VectorXd weight; // 1 / ||y_j - mean||
  int* evaluations;
  const std::function<void(int)>* progress;
  // The last two simulations: NumericalDiff simulates the accepted point again at the start of
  // every Jacobian, and calibrate() once more at the end. The simulation is deterministic, so a
  // repeated parameter vector gets the same outputs without simulating.
  struct Simulated {
    Eigen::VectorXd p;
    Eigen::MatrixXd yhat;
    bool ok = false;
  };
  mutable std::array<Simulated, 2> recent;
  mutable std::size_t next = 0;

  int inputs() const { return static_cast<int>(free.size()); }
  int values() const { return static_cast<int>(sim->measured().size()); }

  Eigen::VectorXd parameters(const Eigen::VectorXd& z) const {
    Eigen::VectorXd p = base;
    for (std::size_t i = 0; i < free.size(); ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      p[free[i]] = std::clamp(scale[ii] * z[ii], lo[ii], hi[ii]);
    }
    return p;
  }

  const Simulated& simulated(const Eigen::VectorXd& p) const {
    for (const auto& r : recent)
      if (r.p.size() == p.size() && r.p == p) return r;
    Simulated& r = recent[next];
    next = (next + 1) % recent.size();
    ++*evaluations;
    if (*progress && *progress) (*progress)(*evaluations);
    r.p = p;
    r.ok = sim->simulate_outputs(p, r.yhat) && r.yhat.allFinite();
    return r;
  }

  int operator()(const Eigen::VectorXd& z, Eigen::VectorXd& f) const {
    const auto& y = sim->measured();
    const Simulated& s = simulated(parameters(z));
    const Eigen::MatrixXd& yhat = s.yhat;
    if (!s.ok) {
      // A trial step that blows up: a large, finite residual sends LM back.
      f = Eigen::VectorXd::Constant(values(), 1e3 / std::sqrt(static_cast<double>(values())));
      return 0;
    }
    f.resize(values());
    const Eigen::Index N = y.rows();
    for (Eigen::Index j = 0; j < y.cols(); ++j) f.segment(j * N, N) = (y.col(j) - yhat.col(j)) * weight[j];
    return 0;
  }
};

}  // namespace

namespace {

CalibrationResult result_of(const Simulator& sim, const Eigen::VectorXd& parameters, Eigen::MatrixXd outputs, bool ok) {
  CalibrationResult r;
  r.parameters = parameters;
  r.evaluations = 1;
  r.outputs = std::move(outputs);
  r.ok = ok;
  if (r.ok) {
    r.fit = fits(sim.measured(), r.outputs);
    for (double f : r.fit) r.cost += (1 - f / 100) * (1 - f / 100);
  }
  return r;
}

}  // namespace

CalibrationResult evaluate(const Simulator& sim, const Eigen::Ref<const Eigen::VectorXd>& parameters) {
  Eigen::MatrixXd outputs;
  const bool ok = sim.simulate_outputs(parameters, outputs) && outputs.allFinite();
  return result_of(sim, parameters, std::move(outputs), ok);
}

CalibrationResult calibrate(const Simulator& sim, const Eigen::Ref<const Eigen::VectorXd>& start, const std::vector<int>& free,
                            const CalibrationOptions& options) {
  CalibrationResult r = evaluate(sim, start);
  r.free = free;
  if (free.empty() || !r.ok) {
    r.converged = r.ok;
    return r;
  }
  int evaluations = 1;
  Residual res;
  res.sim = &sim;
  res.base = start;
  res.free = free;
  const auto n = static_cast<Eigen::Index>(free.size());
  res.scale.resize(n);
  res.lo.resize(n);
  res.hi.resize(n);
  const auto& model = sim.model();
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& p = model.parameters[static_cast<std::size_t>(free[static_cast<std::size_t>(i)])];
    double s = static_cast<std::size_t>(i) < options.scale.size() ? options.scale[static_cast<std::size_t>(i)] : 0.0;
    if (!(s > 0)) s = std::abs(start[free[static_cast<std::size_t>(i)]]);
    if (!(s > 0)) s = 1.0;
    res.scale[i] = s;
    res.lo[i] = p.min;
    res.hi[i] = p.max;
  }
  const auto& y = sim.measured();
  res.weight.resize(y.cols());
  for (Eigen::Index j = 0; j < y.cols(); ++j) {
    const double d = (y.col(j).array() - y.col(j).mean()).matrix().norm();
    res.weight[j] = d > 0 ? 1.0 / d : 1.0;
  }
  res.evaluations = &evaluations;
  res.progress = &options.progress;
  Eigen::VectorXd z(n);
  for (Eigen::Index i = 0; i < n; ++i) z[i] = start[free[static_cast<std::size_t>(i)]] / res.scale[i];
  // Step 1e-3 of each scaled parameter: friction signs make the cost rough at the 1e-8 level.
  res.recent[0] = {start, r.outputs, true};  // LM starts where `r` was simulated (when z * scale rounds back to it)
  res.next = 1;
  Eigen::NumericalDiff<Residual> diff(res, 1e-6);  // a copy of res: its memory is diff's
  Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Residual>> lm(diff);
  lm.parameters.maxfev = std::max(1, options.max_evaluations / static_cast<int>(n + 1));
  lm.parameters.ftol = options.tolerance;
  lm.parameters.xtol = options.tolerance;
  lm.parameters.factor = 10;
  const auto status = lm.minimize(z);
  const Eigen::VectorXd best = res.parameters(z);
  const auto& at_best = diff.simulated(best);  // LM's last accepted point: simulated already
  CalibrationResult out = result_of(sim, best, at_best.yhat, at_best.ok);
  out.free = free;
  out.evaluations = evaluations;
  // Eigen counts the Jacobian's simulations in maxfev too: a budget of max_evaluations / (n + 1)
  // simulations in all, which a poorly excited model with several parameters can spend far from
  // its optimum.
  out.converged = status != Eigen::LevenbergMarquardtSpace::TooManyFunctionEvaluation &&
                  status != Eigen::LevenbergMarquardtSpace::UserAsked;
  if (!out.ok || out.cost > r.cost) {  // never return something worse than the start
    r.evaluations = out.evaluations;
    r.converged = out.converged;
    return r;
  }
  return out;
}

}  // namespace sets
