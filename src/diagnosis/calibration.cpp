#include "sets/diagnosis/calibration.hpp"

#include <unsupported/Eigen/NonLinearOptimization>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

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

  // The residual of a simulation: weighted output error, or a large finite one where it blew up
  // (which sends LM back).
  void residual_of(const Simulated& s, Eigen::VectorXd& f) const {
    const auto& y = sim->measured();
    if (!s.ok) {
      f = Eigen::VectorXd::Constant(values(), 1e3 / std::sqrt(static_cast<double>(values())));
      return;
    }
    f.resize(values());
    const Eigen::Index N = y.rows();
    for (Eigen::Index j = 0; j < y.cols(); ++j) f.segment(j * N, N) = (y.col(j) - s.yhat.col(j)) * weight[j];
  }

  int operator()(const Eigen::VectorXd& z, Eigen::VectorXd& f) const {
    residual_of(simulated(parameters(z)), f);
    return 0;
  }

  // Eigen::NumericalDiff's forward differences, bit for bit: f(z) (simulated already: the cache),
  // then column j from z + h_j e_j, h_j = sqrt(epsfcn) |z_j| (sqrt(epsfcn) at 0). The columns'
  // simulations that the cache of the last two does not serve run side by side
  // (Simulator::simulate_outputs_each); the cache, the count and the progress calls end as the
  // columns one after the other would leave them. Returns NumericalDiff's count for maxfev.
  double epsfcn = 0;
  int df(const Eigen::VectorXd& z, Eigen::MatrixXd& jac) const {
    const Eigen::Index n = z.size();
    const double eps = std::sqrt(std::max(epsfcn, Eigen::NumTraits<double>::epsilon()));
    Eigen::VectorXd f0(values()), f1(values());
    (*this)(z, f0);
    std::vector<Eigen::VectorXd> p(static_cast<std::size_t>(n));
    std::vector<double> h(static_cast<std::size_t>(n));
    for (Eigen::Index j = 0; j < n; ++j) {
      const auto jj = static_cast<std::size_t>(j);
      h[jj] = eps * std::abs(z[j]);
      if (h[jj] == 0.) h[jj] = eps;
      Eigen::VectorXd zj = z;
      zj[j] += h[jj];
      p[jj] = parameters(zj);
    }
    // The cache replayed in column order: held[r] is -1 - r for recent[r] as it is now, or the
    // column whose simulation took that place.
    std::array<int, 2> held{-1, -2};
    std::size_t at = next;
    std::vector<int> source(static_cast<std::size_t>(n));
    std::vector<int> to_run;
    for (std::size_t j = 0; j < p.size(); ++j) {
      int found = 0;
      bool hit = false;
      for (int r : held) {
        const Eigen::VectorXd& q = r < 0 ? recent[static_cast<std::size_t>(-1 - r)].p : p[static_cast<std::size_t>(r)];
        if (!hit && q.size() == p[j].size() && q == p[j]) hit = true, found = r;
      }
      if (!hit) {
        found = static_cast<int>(j);
        to_run.push_back(found);
        held[at] = found;
        at = (at + 1) % held.size();
        ++*evaluations;
        if (*progress && *progress) (*progress)(*evaluations);
      }
      source[j] = found;
    }
    Eigen::MatrixXd columns(base.size(), static_cast<Eigen::Index>(to_run.size()));
    for (std::size_t i = 0; i < to_run.size(); ++i) columns.col(static_cast<Eigen::Index>(i)) = p[static_cast<std::size_t>(to_run[i])];
    std::vector<Eigen::MatrixXd> outputs;
    std::vector<bool> ok;
    if (!to_run.empty()) sim->simulate_outputs_each(columns, outputs, ok);
    std::vector<Simulated> ran(p.size());
    for (std::size_t i = 0; i < to_run.size(); ++i) {
      Simulated& r = ran[static_cast<std::size_t>(to_run[i])];
      r.p = p[static_cast<std::size_t>(to_run[i])];
      r.yhat = std::move(outputs[i]);
      r.ok = ok[i] && r.yhat.allFinite();
    }
    const auto simulation = [&](int r) -> const Simulated& {
      return r < 0 ? recent[static_cast<std::size_t>(-1 - r)] : ran[static_cast<std::size_t>(r)];
    };
    for (Eigen::Index j = 0; j < n; ++j) {
      residual_of(simulation(source[static_cast<std::size_t>(j)]), f1);
      jac.col(j) = (f1 - f0) / h[static_cast<std::size_t>(j)];
    }
    const std::array<Simulated, 2> kept{simulation(held[0]), simulation(held[1])};
    recent = kept;
    next = at;
    return static_cast<int>(n) + 1;
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
  res.epsfcn = 1e-6;
  Eigen::LevenbergMarquardt<Residual> lm(res);
  lm.parameters.maxfev = std::max(1, options.max_evaluations / static_cast<int>(n + 1));
  lm.parameters.ftol = options.tolerance;
  lm.parameters.xtol = options.tolerance;
  lm.parameters.factor = 10;
  const auto status = lm.minimize(z);
  const Eigen::VectorXd best = res.parameters(z);
  const auto& at_best = res.simulated(best);  // LM's last accepted point: simulated already
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
