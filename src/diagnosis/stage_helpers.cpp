// Helpers shared by the stages of the diagnosis.

#include <algorithm>
#include <memory>
#include <cmath>

#include "diagnosis/stages.hpp"
#include "sets/core/error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/interval.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets::diagnosis_stage {

std::vector<double> output_costs(const std::vector<double>& fit) {
  std::vector<double> c;
  for (double f : fit) c.push_back((1 - f / 100) * (1 - f / 100));
  return c;
}

double cost_of(const std::vector<double>& fit) {
  double c = 0;
  for (double x : output_costs(fit)) c += x;
  return c;
}

Eigen::VectorXd values_of(const ModelFile& m) {
  Eigen::VectorXd p(static_cast<Eigen::Index>(m.parameters.size()));
  for (std::size_t i = 0; i < m.parameters.size(); ++i) p[static_cast<Eigen::Index>(i)] = m.parameters[i].value;
  return p;
}

void store_values(ModelFile& m, const Eigen::VectorXd& p) {
  for (std::size_t i = 0; i < m.parameters.size(); ++i) m.parameters[i].value = p[static_cast<Eigen::Index>(i)];
}

CalibrationResult refine_with_final_substeps(const Context& c, const Simulator& exact, const Eigen::VectorXd& coarse,
                                             const std::vector<int>& free, const CalibrationOptions& options) {
  if (c.options.screening_substeps >= c.options.final_substeps) return evaluate(exact, coarse);
  // From a nearby start Levenberg-Marquardt needs few steps: 6 (n + 1) evaluations are Eigen's maxfev
  // = 6 simulations, Jacobians included, so one iteration (see calibrate()).
  CalibrationOptions o = options;
  o.max_evaluations = 6 * (static_cast<int>(free.size()) + 1);
  return calibrate(exact, coarse, free, o);
}

std::vector<double> scales_for(const ModelFile& m, const std::vector<int>& free,
                               const std::vector<std::pair<std::string, double>>& known) {
  std::vector<double> s;
  for (int i : free) {
    const auto& p = m.parameters[static_cast<std::size_t>(i)];
    double v = std::abs(p.value);
    for (const auto& [n, sc] : known)
      if (n == p.name) v = sc;
    s.push_back(v > 0 ? v : 1.0);
  }
  return s;
}

namespace {

// Column i of output_jacobian: the outputs' forward difference in free parameter i.
void jacobian_column(const Simulator& sim, const Eigen::VectorXd& p, const std::vector<int>& free,
                     const std::vector<double>& scale, const Eigen::MatrixXd& y0, std::size_t i, Eigen::MatrixXd& J) {
  const Eigen::Index N = y0.rows(), ny = y0.cols();
  Eigen::VectorXd q = p;
  const double h = 1e-4 * scale[i];
  q[free[i]] += h;
  Eigen::MatrixXd y1;
  if (!sim.simulate_outputs(q, y1)) {
    q[free[i]] = p[free[i]] - h;
    if (!sim.simulate_outputs(q, y1)) throw NumericalError("sensitivity simulation blew up");
    y1 = 2 * y0 - y1;
  }
  for (Eigen::Index j = 0; j < ny; ++j) J.col(static_cast<Eigen::Index>(i)).segment(j * N, N) = (y1.col(j) - y0.col(j)) / h;
}

}  // namespace

Eigen::MatrixXd output_jacobian(const Simulator& sim, const Eigen::VectorXd& p, const std::vector<int>& free,
                                const std::vector<double>& scale, const Eigen::MatrixXd& y0) {
  Eigen::MatrixXd J(y0.size(), static_cast<Eigen::Index>(free.size()));
  for (std::size_t i = 0; i < free.size(); ++i) jacobian_column(sim, p, free, scale, y0, i, J);
  return J;
}

Eigen::MatrixXd output_jacobian(const ModelFile& model, const Recording& data, int substeps, int threads, const Eigen::VectorXd& p,
                                const std::vector<int>& free, const std::vector<double>& scale, const Eigen::MatrixXd& y0) {
  Eigen::MatrixXd J(y0.size(), static_cast<Eigen::Index>(free.size()));
  run_jobs_with(
      threads, free.size(), [&] { return std::make_unique<Simulator>(model, data, SimulationOptions{substeps}); },
      [&](const std::unique_ptr<Simulator>& sim, std::size_t i) { jacobian_column(*sim, p, free, scale, y0, i, J); });
  return J;
}

namespace {

// The strips |r_t - J_t dtheta| <= delta_j on every stride-th sample, rows in units of the bound
// and columns in units of each parameter's scale: this keeps the LP well conditioned (position
// residuals of 1e-6 m next to forces of 1e2 N otherwise). `delta` empty: 1.5 x the largest
// |residual| of each output there; filled with the bounds used.
FeasibleParameterSet linearised_strips(const Eigen::MatrixXd& J, const Eigen::MatrixXd& R, const std::vector<double>& scale,
                                       Eigen::Index stride, std::vector<double>& delta) {
  const Eigen::Index N = R.rows(), ny = R.cols(), m = (N + stride - 1) / stride;
  const bool given = !delta.empty();
  Eigen::MatrixXd Phi(m * ny, J.cols());
  Eigen::VectorXd yy(m * ny), dd = Eigen::VectorXd::Ones(m * ny);
  for (Eigen::Index j = 0; j < ny; ++j) {
    double d = 0;
    for (Eigen::Index i = 0; i < m; ++i) d = std::max(d, std::abs(R(i * stride, j)));
    d = given ? delta[static_cast<std::size_t>(j)] : 1.5 * d + 1e-300;
    if (!given) delta.push_back(d);
    for (Eigen::Index i = 0; i < m; ++i) {
      for (Eigen::Index c = 0; c < J.cols(); ++c) Phi(j * m + i, c) = J(j * N + i * stride, c) * scale[static_cast<std::size_t>(c)] / d;
      yy[j * m + i] = R(i * stride, j) / d;
    }
  }
  return FeasibleParameterSet::from_data(Phi, yy, dd);
}

Eigen::Index strip_stride(Eigen::Index N) { return std::max<Eigen::Index>(1, N / 1500); }

}  // namespace

OutputErrorIntervals output_error_intervals(const Eigen::MatrixXd& J, const Eigen::MatrixXd& R,
                                            const Eigen::VectorXd& estimate, const std::vector<int>& free,
                                            const std::vector<double>& scale, const std::vector<double>* given_delta) {
  OutputErrorIntervals out;
  out.stride = static_cast<int>(strip_stride(R.rows()));
  if (given_delta) out.delta = *given_delta;
  try {
    const PuiResult pr = pui(linearised_strips(J, R, scale, out.stride, out.delta));
    if (pr.empty()) {
      out.note = "the linearised strips were found inconsistent, no PUI";
      return out;
    }
    out.built = true;
    out.guaranteed = pr.guaranteed;
    for (std::size_t i = 0; i < free.size(); ++i) {
      const Interval theta = Interval(estimate[free[i]]) + pr.box[static_cast<Eigen::Index>(i)] * scale[i];  // outward rounded
      out.lo.push_back(theta.lower());
      out.hi.push_back(theta.upper());
    }
  } catch (const std::exception& e) {
    out.note = std::string("PUI computation failed: ") + e.what();
  }
  return out;
}

bool linearised_strips_falsified(const Eigen::MatrixXd& J, const Eigen::MatrixXd& R, const std::vector<double>& scale,
                                 std::vector<double> delta) {
  try {
    return check_consistency(linearised_strips(J, R, scale, strip_stride(R.rows()), delta)).certified_falsified();
  } catch (const std::exception&) {
    return false;  // not decided: not falsified
  }
}

std::string fmt(double x, int prec) {
  std::ostringstream os;
  os << std::setprecision(prec) << x;
  return os.str();
}
std::string fixed1(double x) {
  std::ostringstream os;
  // A model far off can fit at -1e44 %: its 45 digits say nothing more than three do.
  if (std::abs(x) >= 1e6) os << std::setprecision(3) << x;
  else os << std::fixed << std::setprecision(1) << x;
  return os.str();
}

std::string equally_good_text(const EquallyGood& e) {
  std::string t;
  for (std::size_t k = 0; k < e.effects.size(); ++k) t += (k ? " + " : "") + e.effects[k] + " in " + e.equations[k];
  t += " (removes " + fixed1(100 * (1 - e.misfit)) + " % of the squared misfit";
  if (std::isfinite(e.misfit_validation)) t += ", " + fixed1(100 * (1 - e.misfit_validation)) + " % on validation";
  return t + ")";
}

}  // namespace sets::diagnosis_stage
