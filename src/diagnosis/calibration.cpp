#include "sets/diagnosis/calibration.hpp"

#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include <algorithm>
#include <cmath>

namespace sets {

std::vector<double> fits(const Eigen::MatrixXd& measured, const Eigen::MatrixXd& simulated) {
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
  mutable Eigen::MatrixXd yhat;

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

  int operator()(const Eigen::VectorXd& z, Eigen::VectorXd& f) const {
    const auto& y = sim->measured();
    ++*evaluations;
    if (*progress && *progress) (*progress)(*evaluations);
    if (!sim->simulate_outputs(parameters(z), yhat) || !yhat.allFinite()) {
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

CalibrationResult evaluate(const Simulator& sim, const Eigen::VectorXd& parameters) {
  CalibrationResult r;
  r.parameters = parameters;
  r.evaluations = 1;
  r.ok = sim.simulate_outputs(parameters, r.outputs) && r.outputs.allFinite();
  if (r.ok) {
    r.fit = fits(sim.measured(), r.outputs);
    for (double f : r.fit) r.cost += (1 - f / 100) * (1 - f / 100);
  }
  return r;
}

CalibrationResult calibrate(const Simulator& sim, const Eigen::VectorXd& start, const std::vector<int>& free,
                            const CalibrationOptions& options) {
  CalibrationResult r = evaluate(sim, start);
  r.free = free;
  if (free.empty() || !r.ok) return r;
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
  Eigen::NumericalDiff<Residual> diff(res, 1e-6);
  Eigen::LevenbergMarquardt<Eigen::NumericalDiff<Residual>> lm(diff);
  lm.parameters.maxfev = std::max(1, options.max_evaluations / static_cast<int>(n + 1));
  lm.parameters.ftol = options.tolerance;
  lm.parameters.xtol = options.tolerance;
  lm.parameters.factor = 10;
  lm.minimize(z);
  const Eigen::VectorXd best = res.parameters(z);
  CalibrationResult out = evaluate(sim, best);
  out.free = free;
  out.evaluations = evaluations + 1;
  if (!out.ok || out.cost > r.cost) {  // never return something worse than the start
    r.evaluations = out.evaluations;
    return r;
  }
  return out;
}

}  // namespace sets
