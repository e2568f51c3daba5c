// Helpers shared by the stages of the diagnosis.

#include <cmath>

#include "diagnosis/stages.hpp"
#include "sets/core/error.hpp"

namespace sets::diagnosis_stage {

double cost_of(const std::vector<double>& fit) {
  double c = 0;
  for (double f : fit) c += (1 - f / 100) * (1 - f / 100);
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
  // From a nearby start Levenberg-Marquardt needs a few Jacobians: at most 6, each n + 1 simulations.
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

Eigen::MatrixXd output_jacobian(const Simulator& sim, const Eigen::VectorXd& p, const std::vector<int>& free,
                                const std::vector<double>& scale, const Eigen::MatrixXd& y0) {
  const Eigen::Index N = y0.rows(), ny = y0.cols();
  Eigen::MatrixXd J(N * ny, static_cast<Eigen::Index>(free.size()));
  for (std::size_t i = 0; i < free.size(); ++i) {
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
  return J;
}

std::string fmt(double x, int prec) {
  std::ostringstream os;
  os << std::setprecision(prec) << x;
  return os.str();
}
std::string fixed1(double x) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << x;
  return os.str();
}

}  // namespace sets::diagnosis_stage
