#pragma once
// Ellipsoidal uncertainty domains from the level sets of the least-squares criterion
// (Farah et al., Section IV), and the guaranteed feasible-parameter-set alternative.
//
// For the regression y_M = Psi theta + eps, J(theta) = 1/2 eps^T eps = J_min + 1/2 dtheta^T R dtheta
// with R = Psi^T Psi. The domain is {theta : J(theta) <= J_D}, J_D = J_min + l^2, i.e. the
// ellipsoid dtheta^T R dtheta <= 2 l^2 around theta_ls, with l = max |eps(t)| read from the
// residuals of the fit. The paper does not say which residuals eps(t) are, so it is an option:
//   ResidualSelection: all rows of y_M (state and output equations; the paper's y_M), only the
//     output equations (the rows that carry the measurement noise), or only the state equations;
//   ResidualNorm: |eps(t)| as the absolute value of each entry, as the Euclidean norm of the
//     vector eps(t) of one sample (all selected equations at time t), or per equation: every
//     equation e gets its own l_e = max_t |eps_e(t)| and the criterion is normalised,
//     J_w = 1/2 sum (eps/l_e)^2 <= J_w,min + 1 (the selection is then ignored; an equation with
//     l_e = 0 is clamped to 1e-12 max l_e, which makes the domain flat in its parameters).
// The level set is NOT a guaranteed bound: l is a statistic of the residuals, not a noise bound.
// The feasible parameter set {theta : |y_M - Psi theta| <= l entrywise} (strips) of the same
// regression is what a guaranteed statement needs; its PUIs come from `pui()` by LP.

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "sets/domains/ellipsoid.hpp"
#include "sets/methods/ss_uncertainty/canonical_fps.hpp"
#include "sets/methods/ss_uncertainty/propagator_identification.hpp"

namespace sets {

enum class ResidualSelection { all, outputs, states };
enum class ResidualNorm { entrywise, sample_euclidean, per_equation };

struct LevelSetOptions {
  ResidualSelection residuals = ResidualSelection::all;
  ResidualNorm norm = ResidualNorm::entrywise;
  // The domain is dtheta^T R dtheta <= level_factor l^2. 2 is the paper's J = 1/2 eps^T eps with
  // J_D - J_min = l^2; 1 is the reading that drops the 1/2 (axes shorter by sqrt 2).
  double level_factor = 2.0;
};

struct LevelSetDomain {
  Ellipsoid ellipsoid;          // {theta : 1/2 (theta-theta_ls)^T R (theta-theta_ls) <= l^2}
  Eigen::VectorXd theta;        // theta_ls, the centre
  Eigen::MatrixXd R;            // Psi^T Psi
  Eigen::VectorXd residuals;    // eps = y_M - Psi theta_ls (every row)
  double j_min = 0;             // 1/2 eps^T eps over every row
  double ell = 0;               // l
  double j_d = 0;               // J_min + l^2
  int ell_row = -1;             // the row (entrywise) or first row of the sample that attains l
  Eigen::VectorXd ell_per_equation;  // l_e (per_equation; otherwise l for every equation)
};

/// Least squares and the level-set ellipsoid of a regression. Throws InputError when R is
/// singular (the parameters are not identifiable) or no residual row is selected.
LevelSetDomain level_set_domain(const CanonicalRegression& regression, const LevelSetOptions& options = {});
/// The same for id.regression, starting from id.theta: identify_propagator has already solved
/// this least-squares problem (same QR, same threshold) and checked its rank, so the domain is
/// the same to the last bit without factorising Psi again. Throws InputError when id has no theta.
LevelSetDomain level_set_domain(const PropagatorResult& id, const LevelSetOptions& options = {});

/// l of a residual vector under the options, and the row (entrywise, per_equation) or first row
/// of the sample that attains it.
struct ResidualBound {
  double ell = 0;
  int attaining_row = -1;
};
/// Exposed for tests and for the FPS bound.
ResidualBound residual_bound(const CanonicalRegression& regression, const Eigen::Ref<const Eigen::VectorXd>& residuals,
                             const LevelSetOptions& options);

/// The feasible parameter set of the same regression with |y_M - Psi theta| <= bound on every
/// row. Rows whose regressor is zero do not constrain theta; those whose |y| exceeds the bound
/// are CanonicalFps::falsified_rows() (the set is then empty). It holds the true theta~ only if
/// the bound holds at the truth: with l read from the residuals it is an estimate.
CanonicalFps regression_fps(const CanonicalRegression& regression, double bound);
/// The same with a bound per equation (bounds[e] for the rows of equation e).
CanonicalFps regression_fps(const CanonicalRegression& regression, const Eigen::Ref<const Eigen::VectorXd>& bounds);

/// The 2-D views of an ellipsoid for the parameters (i, j): the exact projection (shadow) and
/// the exact slice through the centre (every other parameter at its estimate).
struct PairView {
  Ellipsoid projection;
  std::optional<Ellipsoid> slice;
};
PairView pair_view(const Ellipsoid& E, int i, int j);

const char* to_string(ResidualSelection s);
const char* to_string(ResidualNorm n);

}  // namespace sets
