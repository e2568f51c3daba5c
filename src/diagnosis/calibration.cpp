#include "sets/diagnosis/calibration.hpp"

#include <unsupported/Eigen/NonLinearOptimization>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
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
  class Recent {
   public:
    std::shared_ptr<Simulated> find(const Eigen::VectorXd& p) const {
      for (const auto& r : kept_)
        if (r && r->p.size() == p.size() && r->p == p) return r;
      return nullptr;
    }
    void keep(std::shared_ptr<Simulated> s) {  // in place of the older one
      kept_[next_] = std::move(s);
      next_ = (next_ + 1) % kept_.size();
    }

   private:
    std::array<std::shared_ptr<Simulated>, 2> kept_;
    std::size_t next_ = 0;
  };
  mutable Recent recent;

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

  // A simulation not in `recent` yet, counted (its outputs still to come) and kept there.
  std::shared_ptr<Simulated> counted(const Eigen::VectorXd& p) const {
    auto s = std::make_shared<Simulated>();
    s->p = p;
    recent.keep(s);
    ++*evaluations;
    if (*progress && *progress) (*progress)(*evaluations);
    return s;
  }

  std::shared_ptr<Simulated> simulated(const Eigen::VectorXd& p) const {
    if (auto s = recent.find(p)) return s;
    auto s = counted(p);
    s->ok = sim->simulate_outputs(p, s->yhat) && s->yhat.allFinite();
    return s;
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
    residual_of(*simulated(parameters(z)), f);
    return 0;
  }

  // Eigen::NumericalDiff's forward differences, bit for bit: f(z) (simulated already: the cache),
  // then column j from z + h_j e_j, h_j = sqrt(epsfcn) |z_j| (sqrt(epsfcn) at 0). The columns are
  // looked up and kept in the cache in column order, as one after the other would be, and those it
  // does not serve run side by side (Simulator::simulate_outputs_each). Returns NumericalDiff's
  // count for maxfev.
  double epsfcn = 0;
  int df(const Eigen::VectorXd& z, Eigen::MatrixXd& jac) const {
    const Eigen::Index n = z.size();
    const double eps = std::sqrt(std::max(epsfcn, Eigen::NumTraits<double>::epsilon()));
    Eigen::VectorXd f0(values()), f1(values());
    (*this)(z, f0);
    std::vector<double> h(static_cast<std::size_t>(n));
    std::vector<std::shared_ptr<Simulated>> column(h.size()), to_run;
    for (Eigen::Index j = 0; j < n; ++j) {
      const auto jj = static_cast<std::size_t>(j);
      h[jj] = eps * std::abs(z[j]);
      if (h[jj] == 0.) h[jj] = eps;
      Eigen::VectorXd zj = z;
      zj[j] += h[jj];
      const Eigen::VectorXd p = parameters(zj);
      column[jj] = recent.find(p);
      if (!column[jj]) to_run.push_back(column[jj] = counted(p));
    }
    simulate_side_by_side(to_run);
    for (Eigen::Index j = 0; j < n; ++j) {
      residual_of(*column[static_cast<std::size_t>(j)], f1);
      jac.col(j) = (f1 - f0) / h[static_cast<std::size_t>(j)];
    }
    return static_cast<int>(n) + 1;
  }

  void simulate_side_by_side(const std::vector<std::shared_ptr<Simulated>>& runs) const {
    if (runs.empty()) return;
    Eigen::MatrixXd columns(base.size(), static_cast<Eigen::Index>(runs.size()));
    for (std::size_t i = 0; i < runs.size(); ++i) columns.col(static_cast<Eigen::Index>(i)) = runs[i]->p;
    std::vector<Eigen::MatrixXd> outputs;
    std::vector<bool> ok;
    sim->simulate_outputs_each(columns, outputs, ok);
    for (std::size_t i = 0; i < runs.size(); ++i) {
      runs[i]->yhat = std::move(outputs[i]);
      runs[i]->ok = ok[i] && runs[i]->yhat.allFinite();
    }
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
  // LM starts where `r` was simulated (when z * scale rounds back to it).
  res.recent.keep(std::make_shared<Residual::Simulated>(Residual::Simulated{start, r.outputs, true}));
  // Step 1e-3 of each scaled parameter: friction signs make the cost rough at the 1e-8 level.
  res.epsfcn = 1e-6;
  Eigen::LevenbergMarquardt<Residual> lm(res);
  lm.parameters.maxfev = std::max(1, options.max_evaluations / static_cast<int>(n + 1));
  lm.parameters.ftol = options.tolerance;
  lm.parameters.xtol = options.tolerance;
  lm.parameters.factor = 10;
  const auto status = lm.minimize(z);
  const Eigen::VectorXd best = res.parameters(z);
  const auto at_best = res.simulated(best);  // LM's last accepted point: simulated already
  CalibrationResult out = result_of(sim, best, at_best->yhat, at_best->ok);
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
