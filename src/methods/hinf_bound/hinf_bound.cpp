// Hakvoort-Van den Hof: input checks, the entry point (steps 1-4 in order) and the dense-grid check.
// The steps: uncertainty_set.cpp, nominal_fit.cpp, weight_fit.cpp, error_bound.cpp.
#include "sets/methods/hinf_bound/hinf_bound.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "sets/core/error.hpp"
#include "hinf_common.hpp"

namespace sets {

using namespace hinf_detail;

// ------------------------------------------------------------------ checks
void check_frequency_grid(const Eigen::Ref<const Eigen::VectorXd>& grid) {
  if (grid.size() < 2) throw InputError("frequency grid: needs at least 2 frequencies, got " + num(grid.size()));
  for (Eigen::Index j = 0; j < grid.size(); ++j) {
    if (!std::isfinite(grid[j]) || grid[j] < 0 || grid[j] > pi)
      throw InputError("frequency grid: w[" + num(j) + "] = " + num(grid[j]) +
                       " rad/sample is outside [0, pi]");
    if (j > 0 && !(grid[j] > grid[j - 1]))
      throw InputError("frequency grid: w[" + num(j) + "] = " + num(grid[j]) +
                       " is not larger than w[" + num(j - 1) + "] (the grid must increase strictly)");
  }
}

void check_priors(const HinfPriors& p) {
  if (!(p.rho > 0 && p.rho < 1)) throw InputError("prior rho = " + num(p.rho) + ": the tail decay rate must satisfy 0 < rho < 1");
  if (!(p.M > 0 && std::isfinite(p.M))) throw InputError("prior M = " + num(p.M) + " must be positive and finite");
  if (!(p.u_bar >= 0 && std::isfinite(p.u_bar))) throw InputError("prior u_bar = " + num(p.u_bar) + " must be >= 0");
  if (p.rho_ic > 0 && !(p.rho_ic < 1))
    throw InputError("prior rho_ic = " + num(p.rho_ic) + ": the impulse-response decay rate must satisfy 0 < rho_ic < 1");
  if (p.M_ic > 0 && !std::isfinite(p.M_ic)) throw InputError("prior M_ic must be finite");
}

HinfBoundResult hinf_bound(const HinfData& data, const HinfStructure& structure, const HinfBoundOptions& o) {
  HinfBoundResult r;
  r.set = uncertainty_set(data.u, data.y, structure.basis, structure.order, structure.grid, structure.priors,
                          o.uncertainty, data.r);
  if (r.set.empty()) return r;
  r.nominal = fit_nominal(r.set, o.nominal);
  r.delta = additive_error(r.set, r.nominal.model);
  // Default W1 = 1/delta: minimise the largest relative over-bound |W^-1|^2/delta^2 - 1, so the
  // bound follows delta at every level rather than only near its peak.
  WeightOptions wo = o.weight;
  if (wo.weight.size() == 0) wo.weight = r.delta.cwiseMax(1e-12 * r.delta.maxCoeff()).cwiseInverse();
  r.weight = fit_weight(structure.grid, r.delta, wo);
  r.bound = error_bound(r.set, r.nominal.model, r.weight.h);
  r.unweighted = error_bound(r.set, r.nominal.model, Eigen::VectorXd::Ones(1));
  return r;
}

Eigen::VectorXd midpoint_grid(int points, double w_min, double w_max) {
  Eigen::VectorXd grid(points);
  for (int j = 0; j < points; ++j) grid[j] = w_min + (w_max - w_min) * (j + 0.5) / points;
  return grid;
}

double weighted_error(const std::function<std::complex<double>(double)>& G, const TransferFunction& nominal,
                      const Eigen::Ref<const Eigen::VectorXd>& h, int dense_points) {
  double e = 0;
  for (int i = 0; i < dense_points; ++i) {
    const double w = pi * i / (dense_points - 1);
    e = std::max(e, std::abs(G(w) - nominal(w)) / std::abs(polynomial_at(h, w)));
  }
  return e;
}

}  // namespace sets
