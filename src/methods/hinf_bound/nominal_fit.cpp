// Step 2 of Hakvoort-Van den Hof: the nominal model fitted to the regions' centres, and the additive error.
#include "sets/methods/hinf_bound/hinf_bound.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"
#include "hinf_common.hpp"

namespace sets {

using namespace hinf_detail;

// ------------------------------------------------------------------ step 2
NominalFit fit_nominal(const UncertaintySet& S, const NominalOptions& o) {
  if (S.empty()) throw InputError("nominal model: the uncertainty set is empty (data falsify the priors)");
  const int nw = static_cast<int>(S.frequencies.size());
  const int ng = o.order;
  if (ng < 0) throw InputError("nominal order " + num(ng) + " must be >= 0");
  if (2 * ng + 1 > 2 * nw)
    throw InputError("nominal order " + num(ng) + " cannot be met: " + num(2 * ng + 1) +
                     " coefficients but only " + num(nw) + " frequencies (" + num(2 * nw) + " real equations)");
  if (ng > 30) throw InputError("nominal order " + num(ng) + " is above the supported 30 (stability check by roots)");
  if (o.polygon_sides < 3) throw InputError("polygon sides K = " + num(o.polygon_sides) + " must be >= 3");
  Eigen::VectorXd W1 = o.weight.size() ? o.weight : Eigen::VectorXd::Ones(nw);
  if (W1.size() != nw) throw InputError("nominal weight: " + num(W1.size()) + " values for " + num(nw) + " frequencies");

  NominalFit fit;
  fit.polygon_sides = o.polygon_sides;
  fit.centres.resize(nw);
  for (int j = 0; j < nw; ++j) fit.centres[j] = S.regions[j].centre;  // Chebyshev centres (16)
  const auto& w = S.frequencies;
  const int K = o.polygon_sides, nv = 2 * ng + 2, it_max = std::max(1, o.iterations);
  const int nd = 256;  // dense grid for the stability (positive-real) constraint
  auto true_error = [&](const TransferFunction& m) {
    double e = 0;
    for (int j = 0; j < nw; ++j) e = std::max(e, W1[j] * std::abs(fit.centres[j] - m(w[j])));
    return e;
  };
  Eigen::VectorXd aprev = Eigen::VectorXd::Ones(1);
  aprev.conservativeResize(ng + 1);
  aprev.tail(ng).setZero();
  double best = inf;
  for (int it = 0; it < it_max; ++it) {
    LinearProgram lp(nv);
    lp.set_variable_bounds(nv - 1, 0, inf);
    for (int i = 1; i <= ng; ++i) {  // coefficients of a stable monic polynomial: |a_i| <= C(ng, i)
      double binom = 1;
      for (int r = 0; r < i; ++r) binom = binom * (ng - r) / (r + 1);
      lp.set_variable_bounds(i - 1, -binom, binom);
    }
    for (int j = 0; j < nw; ++j) {
      const double s = W1[j] / std::abs(polynomial_at(aprev, w[j]));
      for (int k = 0; k < K; ++k) {
        const std::complex<double> rot = std::polar(1.0, -2 * pi * k / K);
        Eigen::VectorXd row = Eigen::VectorXd::Zero(nv);
        for (int i = 1; i <= ng; ++i) row[i - 1] = s * (std::polar(1.0, -i * w[j]) * fit.centres[j] * rot).real();
        for (int i = 0; i <= ng; ++i) row[ng + i] = -s * (std::polar(1.0, -i * w[j]) * rot).real();
        row[nv - 1] = -1;
        lp.add_row(row, -inf, -s * (fit.centres[j] * rot).real());
      }
    }
    for (int d = 0; d < nd && ng > 0; ++d) {  // Re(A / A_prev) >= 0.01 keeps the winding number
      const double wd = pi * d / (nd - 1);
      const std::complex<double> ap = std::conj(polynomial_at(aprev, wd));
      Eigen::VectorXd row = Eigen::VectorXd::Zero(nv);
      for (int i = 1; i <= ng; ++i) row[i - 1] = (std::polar(1.0, -i * wd) * ap).real();
      lp.add_row(row, 0.01 * std::norm(ap) - ap.real(), inf);
    }
    lp.set_objective_coordinate(nv - 1, Sense::minimize);
    const LpSolution sol = lp.solve();
    if (sol.status != LpStatus::optimal) break;
    TransferFunction m;
    m.a = Eigen::VectorXd::Ones(ng + 1);
    m.a.tail(ng) = sol.x.head(ng);
    m.b = sol.x.segment(ng, ng + 1);
    fit.iterations = it + 1;
    if (!m.stable(1e-4)) break;  // the positive-real constraint held only on the dense grid
    const double e = true_error(m);
    const bool improved = e < best;
    if (improved) {
      const double old = best;
      best = e;
      fit.model = m;
      fit.max_error = e;
      if (old - e < 1e-7 * e) break;
    }
    aprev = m.a;
  }
  if (!std::isfinite(best))
    throw NumericalError("nominal model: no stable model of order " + num(ng) + " was found");
  return fit;
}

Eigen::VectorXd additive_error(const UncertaintySet& S, const TransferFunction& m) {
  Eigen::VectorXd d(S.frequencies.size());
  for (Eigen::Index j = 0; j < d.size(); ++j) d[j] = S.regions[j].max_distance(m(S.frequencies[j]));
  return d;
}

}  // namespace sets
