#pragma once
// Random bounded-error regressions for the soundness campaign (tests/fps and
// bench/soundness_campaign_bench.cpp): a true parameter generates the data with noise strictly
// inside the bound, so the feasible parameter set contains it and a verdict "the data falsify
// the model" is always wrong. Deterministic in the seed on every platform (own uniform and
// normal draws from std::mt19937_64, no <random> distributions).
//
// Kinds (seed s has kind (s - 1) mod 5, so seeds 1..5k give k problems of each kind):
//   normal               p in 1..7, N in 2p..120, regressors and parameters O(1)
//   badly_scaled         column j scaled by 10^k_j, k_j in -10..10 (theta_j by 10^-k_j)
//   near_collinear       columns a_j c + eps_j z_j with eps_j = 10^-4 .. 10^-10, N = 80, p 2..7
//   errors_in_variables  interval regressors (true regressor inside, radius 0.1 %..5 %), p 1..4
//   tiny_n               N = p or p + 1
//
// The truth is checked: generation throws std::logic_error if theta is not proven to lie in
// the set (outward rounding), which would be a generator bug.

#include <Eigen/Core>

#include <string>

#include "sets/fps/feasible_parameter_set.hpp"

namespace sets {

enum class RegressionKind { normal, badly_scaled, near_collinear, errors_in_variables, tiny_n };
inline constexpr int regression_kind_count = 5;

struct BoundedErrorRegression {
  RegressionKind kind = RegressionKind::normal;
  unsigned long seed = 0;
  FeasibleParameterSet fps{1};
  Eigen::VectorXd theta;  // the true parameter (in the set)
  PuiOptions options;     // how the campaign computes the PUIs (all orthants for interval regressors)
};

RegressionKind regression_kind_of_seed(unsigned long seed);
/// The problem of this seed (its kind from regression_kind_of_seed).
BoundedErrorRegression bounded_error_regression(unsigned long seed);
const char* to_string(RegressionKind kind);

/// What pui() made of one problem, judged against the truth.
struct SoundnessOutcome {
  RegressionKind kind = RegressionKind::normal;
  unsigned long seed = 0;
  int parameters = 0, samples = 0;
  Falsified verdict = Falsified::unknown;  // any `yes` is a false "the data falsify the model"
  bool guaranteed = false;
  bool theta_in_box = false;
  bool box_finite = false;
  bool numerical_error = false;  // pui() threw NumericalError (an honest failure, exit 3)
  std::string error;
  double seconds = 0;
  int lp_solves = 0;

  bool false_empty() const { return verdict == Falsified::yes; }
  bool guaranteed_miss() const { return guaranteed && !theta_in_box; }
};

/// Runs pui() on the problem (NumericalError is caught and recorded; any other exception is a
/// bug and propagates).
SoundnessOutcome run_soundness_problem(const BoundedErrorRegression& problem);

}  // namespace sets
