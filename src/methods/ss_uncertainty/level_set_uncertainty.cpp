#include "sets/methods/ss_uncertainty/level_set_uncertainty.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>

#include "sets/core/error.hpp"

namespace sets {
namespace {

bool selected(const CanonicalRegression& r, int row, ResidualSelection s) {
  const bool state = r.equation[row] < r.state_equations;
  switch (s) {
    case ResidualSelection::all: return true;
    case ResidualSelection::outputs: return !state;
    case ResidualSelection::states: return state;
  }
  return true;
}

}  // namespace

const char* to_string(ResidualSelection s) {
  switch (s) {
    case ResidualSelection::all: return "all";
    case ResidualSelection::outputs: return "outputs";
    case ResidualSelection::states: return "states";
  }
  return "?";
}

const char* to_string(ResidualNorm n) {
  switch (n) {
    case ResidualNorm::entrywise: return "entrywise";
    case ResidualNorm::sample_euclidean: return "sample-euclidean";
    case ResidualNorm::per_equation: return "per-equation";
  }
  return "?";
}

ResidualBound residual_bound(const CanonicalRegression& r, const Eigen::Ref<const Eigen::VectorXd>& eps,
                             const LevelSetOptions& o) {
  if (eps.size() != r.y.size()) throw InputError("residual_bound: residual vector has the wrong length");
  double ell = -1;
  int arg = -1;
  if (o.norm == ResidualNorm::per_equation) {
    for (int k = 0; k < eps.size(); ++k)
      if (std::abs(eps[k]) > ell) {
        ell = std::abs(eps[k]);
        arg = k;
      }
  } else if (o.norm == ResidualNorm::entrywise) {
    for (int k = 0; k < eps.size(); ++k)
      if (selected(r, k, o.residuals) && std::abs(eps[k]) > ell) {
        ell = std::abs(eps[k]);
        arg = k;
      }
  } else {
    // Rows of one sample are consecutive (canonical_regression writes them so).
    for (int k = 0; k < eps.size();) {
      int end = k;
      double s2 = 0;
      bool any = false;
      while (end < eps.size() && r.sample[end] == r.sample[k]) {
        if (selected(r, end, o.residuals)) {
          s2 += eps[end] * eps[end];
          any = true;
        }
        ++end;
      }
      if (any && std::sqrt(s2) > ell) {
        ell = std::sqrt(s2);
        arg = k;
      }
      k = end;
    }
  }
  if (arg < 0) throw InputError("residual_bound: no residual row is selected");
  return {ell, arg};
}

namespace {

// The domain from theta0, the unweighted least-squares solution of the regression (its rank
// already checked).
LevelSetDomain level_set_from(const CanonicalRegression& r, const Eigen::VectorXd& theta0, const LevelSetOptions& o) {
  if (!(o.level_factor > 0) || !std::isfinite(o.level_factor))
    throw InputError("level_set_domain: level_factor must be finite and > 0");
  LevelSetDomain d;
  if (o.norm != ResidualNorm::per_equation) {
    d.theta = theta0;
    d.R = r.Psi.transpose() * r.Psi;
    d.residuals = r.y - r.Psi * d.theta;
    d.j_min = 0.5 * d.residuals.squaredNorm();
    const ResidualBound bound = residual_bound(r, d.residuals, o);
    d.ell = bound.ell;
    d.ell_row = bound.attaining_row;
    d.ell_per_equation = Eigen::VectorXd::Constant(r.equations, d.ell);
    d.j_d = d.j_min + 0.5 * o.level_factor * d.ell * d.ell;
    // 1/2 dtheta^T R dtheta <= l^2  <=>  dtheta^T R dtheta <= 2 l^2 (level_factor 2).
    d.ellipsoid = Ellipsoid::from_level_set(d.theta, d.R, o.level_factor * d.ell * d.ell);
    return d;
  }
  // Per equation: l_e from the unweighted fit, then the normalised (weighted) criterion.
  const Eigen::VectorXd eps0 = r.y - r.Psi * theta0;
  d.ell_per_equation = Eigen::VectorXd::Zero(r.equations);
  for (int k = 0; k < eps0.size(); ++k)
    d.ell_per_equation[r.equation[k]] = std::max(d.ell_per_equation[r.equation[k]], std::abs(eps0[k]));
  const ResidualBound bound = residual_bound(r, eps0, o);
  d.ell = bound.ell;
  d.ell_row = bound.attaining_row;
  const double floor = 1e-12 * d.ell;
  Eigen::VectorXd w(eps0.size());
  for (int k = 0; k < eps0.size(); ++k) w[k] = 1.0 / std::max(d.ell_per_equation[r.equation[k]], floor);
  const Eigen::MatrixXd Pw = w.asDiagonal() * r.Psi;
  const Eigen::VectorXd yw = w.asDiagonal() * r.y;
  d.theta = Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(Pw).solve(yw);
  d.R = Pw.transpose() * Pw;
  d.residuals = r.y - r.Psi * d.theta;
  d.j_min = 0.5 * (yw - Pw * d.theta).squaredNorm();
  d.j_d = d.j_min + 0.5 * o.level_factor;
  d.ellipsoid = Ellipsoid::from_level_set(d.theta, d.R, o.level_factor);
  return d;
}

}  // namespace

LevelSetDomain level_set_domain(const CanonicalRegression& r, const LevelSetOptions& o) {
  const int m = static_cast<int>(r.Psi.cols());
  const RegressionLeastSquares ls = regression_least_squares(r);  // as identify_propagator
  if (ls.rank < m)
    throw InputError("level_set_domain: Psi^T Psi is singular (rank " + std::to_string(ls.rank) + " < " +
                     std::to_string(m) + "); the parameters are not identifiable");
  return level_set_from(r, ls.theta, o);
}

LevelSetDomain level_set_domain(const PropagatorResult& id, const LevelSetOptions& o) {
  if (id.theta.size() != id.regression.Psi.cols() || id.theta.size() == 0)
    throw InputError("level_set_domain: the identification result has no least-squares estimate");
  return level_set_from(id.regression, id.theta, o);
}

CanonicalFps regression_fps(const CanonicalRegression& r, double bound) {
  return regression_fps(r, Eigen::VectorXd::Constant(r.equations, bound));
}

CanonicalFps regression_fps(const CanonicalRegression& r, const Eigen::Ref<const Eigen::VectorXd>& bounds) {
  if (bounds.size() != r.equations) throw InputError("regression_fps: one bound per equation is needed");
  for (int e = 0; e < bounds.size(); ++e)
    if (!(bounds[e] >= 0) || !std::isfinite(bounds[e]))
      throw InputError("regression_fps: the bound of equation " + std::to_string(e) + " must be finite and >= 0");
  IntervalVector Y(r.y.size());
  {
    // interval_around(y, bound) for every row, with one rounding-mode switch for all of them.
    RoundingScope upward;
    using I = UnprotectedInterval;
    for (Eigen::Index k = 0; k < r.y.size(); ++k) {
      const double b = bounds[r.equation[k]];
      Y[k] = I(r.y[k]) + I(-b, b);
    }
  }
  return CanonicalFps(r.Psi, Y);
}

PairView pair_view(const Ellipsoid& E, int i, int j) {
  const int n = E.dimension();
  if (i < 0 || j < 0 || i >= n || j >= n || i == j)
    throw InputError("pair_view: need two different parameter indices in 0.." + std::to_string(n - 1));
  Eigen::VectorXd rest(n - 2);
  for (int k = 0, q = 0; k < n; ++k)
    if (k != i && k != j) rest[q++] = E.center()[k];
  // slice() orders the kept coordinates as listed and takes the others in increasing order.
  return {project(E, {i, j}), slice(E, {i, j}, rest)};
}

}  // namespace sets
