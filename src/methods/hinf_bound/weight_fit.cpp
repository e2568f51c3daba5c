// Step 3 of Hakvoort-Van den Hof: the weight W whose inverse bounds the additive error, certified positive.
#include "sets/methods/hinf_bound/hinf_bound.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"
#include "hinf_common.hpp"

namespace sets {

using namespace hinf_detail;

// ------------------------------------------------------------------ step 3
namespace {
double trig_at(const Eigen::VectorXd& c, double w) {  // c0 + sum_k c_k cos(k w)
  double s = 0;
  for (Eigen::Index k = 0; k < c.size(); ++k) s += c[k] * std::cos(k * w);
  return s;
}

// Certified lower bound on min over [0, pi] of the cosine polynomial c: the minimum over a grid of
// spacing d less d^2/8 sup|c''| (sup|c''| <= sum k^2 |c_k|), the grid refined until it is positive
// or 2^20 points; returns that bound (<= 0: not certified).
double certified_trig_minimum(const Eigen::VectorXd& c) {
  const double curvature = polynomial_second_derivative_bound(c);
  double lower = -inf;
  for (int points = 16384; points <= (1 << 20); points *= 4) {
    double m = inf;
    for (int i = 0; i < points; ++i) m = std::min(m, trig_at(c, pi * i / (points - 1)));
    const double d = pi / (points - 1);
    lower = m - d * d / 8 * curvature;
    if (lower > 0) break;
  }
  return lower;
}

// Solves the LP for |W^-1|^2 and, where its solution dips below `floor` between the LP's rows,
// adds the local minima as rows and solves again (cutting planes; at most 8 rounds).
Eigen::VectorXd floored_trig_solution(LinearProgram& lp, const std::function<Eigen::VectorXd(double)>& cosrow, int m,
                                      double floor) {
  const int nc = 16384;
  for (int round = 0;; ++round) {
    const LpSolution sol = lp.solve();
    if (sol.status != LpStatus::optimal) throw NumericalError("weight: the LP for |W^-1|^2 has no optimum");
    const Eigen::VectorXd c = sol.x.head(m + 1);
    Eigen::VectorXd v(nc);
    for (int i = 0; i < nc; ++i) v[i] = trig_at(c, pi * i / (nc - 1));
    int cuts = 0;
    for (int i = 0; i < nc; ++i)
      if (v[i] < floor && (i == 0 || v[i] <= v[i - 1]) && (i == nc - 1 || v[i] <= v[i + 1])) {
        lp.add_row(cosrow(pi * i / (nc - 1)), floor, inf);
        ++cuts;
      }
    if (cuts == 0 || round == 8) return c;
  }
}

// The LP for |W^-1|^2 = unit * (x_0 + sum_k x_k cos kw): minimise t subject to
// |W^-1|^2 >= delta^2 and W1^2 (|W^-1|^2 - delta^2) <= t on the grid, >= floor on 2048 points
// (and at the cutting planes); returns the coefficients c = unit * x.
Eigen::VectorXd weight_lp_solution(const Eigen::Ref<const Eigen::VectorXd>& grid,
                                   const Eigen::Ref<const Eigen::VectorXd>& delta, const Eigen::VectorXd& W1, int m,
                                   double floor, double unit) {
  const int nv = m + 2;
  LinearProgram lp(nv);
  const std::function<Eigen::VectorXd(double)> cosrow = [&](double w) {
    Eigen::VectorXd r = Eigen::VectorXd::Zero(nv);
    for (int k = 0; k <= m; ++k) r[k] = std::cos(k * w);
    return r;
  };
  for (Eigen::Index j = 0; j < grid.size(); ++j) {
    const double d2 = delta[j] * delta[j];
    lp.add_row(cosrow(grid[j]), d2 / unit, inf);
    Eigen::VectorXd r = W1[j] * W1[j] * unit * cosrow(grid[j]);
    r[nv - 1] = -1;
    lp.add_row(r, -inf, W1[j] * W1[j] * d2);
  }
  const int nd = 2048;
  for (int d = 0; d < nd; ++d) lp.add_row(cosrow(pi * d / (nd - 1)), floor / unit, inf);
  lp.set_objective_coordinate(nv - 1, Sense::minimize);
  return unit * floored_trig_solution(lp, cosrow, m, floor / unit);
}
}  // namespace

std::complex<double> WeightFit::inverse(double w) const { return polynomial_at(h, w); }

WeightFit fit_weight(const Eigen::Ref<const Eigen::VectorXd>& grid, const Eigen::Ref<const Eigen::VectorXd>& delta,
                     const WeightOptions& o) {
  check_frequency_grid(grid);
  const int nw = static_cast<int>(grid.size());
  if (delta.size() != nw) throw InputError("weight: " + num(delta.size()) + " error bounds for " + num(nw) + " frequencies");
  if (o.degree < 0 || o.degree > 60) throw InputError("weight degree " + num(o.degree) + " must be in [0, 60]");
  for (int j = 0; j < nw; ++j)
    if (!(delta[j] >= 0 && std::isfinite(delta[j]))) throw InputError("weight: delta[" + num(j) + "] is not a finite value >= 0");
  Eigen::VectorXd W1 = o.weight.size() ? o.weight : Eigen::VectorXd::Ones(nw);
  if (W1.size() != nw) throw InputError("weight W1: " + num(W1.size()) + " values for " + num(nw) + " frequencies");
  const int m = o.degree;
  const double dmax = delta.maxCoeff();
  if (!(dmax > 0)) throw InputError("weight: every delta is zero");
  // |W^-1|^2 >= a quarter of the smallest delta^2 between grid points too: W stays bounded.
  const double floor = 0.25 * delta.minCoeff() * delta.minCoeff() + 1e-8 * dmax * dmax;
  // The same LP in three units of |W^-1|^2: GLPK fails (glp_simplex code 5, or a wrong
  // "optimum") on some runs in one unit and not in another when delta spans decades.
  WeightFit fit;
  const double units[] = {dmax * std::max(delta.minCoeff(), 1e-4 * dmax), dmax * dmax, 1.0};
  for (std::size_t i = 0; i < std::size(units); ++i) {
    try {
      fit.trig = weight_lp_solution(grid, delta, W1, m, floor, units[i]);
      break;
    } catch (const NumericalError&) {
      if (i + 1 == std::size(units)) throw;
    }
  }
  const double pmin = certified_trig_minimum(fit.trig);
  if (!(pmin > 0))
    throw NumericalError("weight: |W^-1|^2 is not certified positive (curvature bound " +
                         num(polynomial_second_derivative_bound(fit.trig)) + "); lower the weight degree");
  // Spectral factor: z^m P(z) has roots in pairs (r, 1/conj r); keep those inside the circle.
  int mm = m;
  while (mm > 0 && std::abs(fit.trig[mm]) < 1e-13 * std::abs(fit.trig[0])) --mm;
  Eigen::VectorXcd inside;
  if (mm > 0) {
    Eigen::VectorXd desc(2 * mm + 1);  // descending powers of z
    for (int k = 0; k <= mm; ++k) desc[mm - k] = desc[mm + k] = k == 0 ? fit.trig[0] : fit.trig[k] / 2;
    // Its roots are the poles of 1 / (desc / desc[0]) read as a polynomial in z^-1 (palindromic).
    const Eigen::VectorXcd r = TransferFunction{Eigen::VectorXd::Ones(1), desc / desc[0], {}}.poles();
    std::vector<std::complex<double>> v(r.data(), r.data() + r.size());
    std::sort(v.begin(), v.end(), [](auto x, auto y) { return std::abs(x) < std::abs(y); });
    inside.resize(mm);
    for (int i = 0; i < mm; ++i) inside[i] = v[i];
    if (!(std::abs(v[mm - 1]) < 1)) throw NumericalError("weight: spectral factor has a zero on the unit circle");
  }
  Eigen::VectorXcd hc = Eigen::VectorXcd::Zero(mm + 1);
  hc[0] = 1;
  for (int i = 0; i < mm; ++i)  // multiply by (1 - r z^-1)
    for (int k = i + 1; k >= 1; --k) hc[k] -= inside[i] * hc[k - 1];
  fit.h = hc.real();
  // Gain: match P in the mean, then scale so |W^-1| >= delta holds on the grid.
  double num_ = 0, den = 0;
  for (int i = 0; i < 512; ++i) {
    const double w = pi * i / 511;
    num_ += trig_at(fit.trig, w);
    den += std::norm(polynomial_at(fit.h, w));
  }
  fit.h *= std::sqrt(num_ / den);
  double scale = 1;
  for (int j = 0; j < nw; ++j) scale = std::max(scale, delta[j] / std::abs(polynomial_at(fit.h, grid[j])));
  fit.h *= scale * (1 + 1e-12);
  fit.max_gap = 0;
  for (int j = 0; j < nw; ++j)
    fit.max_gap = std::max(fit.max_gap, W1[j] * W1[j] * (std::norm(polynomial_at(fit.h, grid[j])) - delta[j] * delta[j]));
  return fit;
}

}  // namespace sets
