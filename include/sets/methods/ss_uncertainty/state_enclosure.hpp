#pragma once
// The guaranteed alternative to the paper's ellipsoid (docs/methods/propagator_level_sets.md,
// "The guaranteed set"): enclosures of the true canonical state x_c(t) around the propagator's
// estimate x^(t), carried into the regression of Remark 1 as interval regressors. The paper
// ignores the error of x^ (its footnote 2); this is what makes its sets miss the truth.
//
// Assumptions, stated by the caller (GuaranteedSetAssumptions):
//   noise  |v_j(t)| <= noise_bound[j] for every output j and sample t;
// and either
//   tail   |r_j(t)| <= tail_bound[j], r_j(t) = C_j A^p x(t-p): what the inputs older than p
//          samples and the initial state add to y_j(t) (the part step 1 truncates, A^p ~ 0),
//          from which the state error is bounded with the data and the propagator;
// or
//   state  |x_c,k(t) - x^_k(t)| <= state_error_bound[k], a deterministic bound the user gives.
//
// With the tail assumption every state gets two enclosures, both rigorous (outward rounding and
// a-priori bounds of the floating-point products, see enclose_states) and intersected:
//   propagator  x^_k(t) +- (tail + |a^T (g - g^)|): x^_k(t) = a^T g^ is linear in the step-1
//               least-squares estimate g^ of the Markov parameters, and the true g lies in the
//               ellipsoid ||Y - Z g||^2 <= M (noise + tail)^2 (the step-1 residuals are at most
//               noise + tail in every sample, M samples);
//   output      x_c,k(t) = C_o A^l x(t) = y_o(t+l) - v_o(t+l) - D_o u(t+l)
//                          - sum_{j<l} C_o A^j B u(t+l-1-j)   for row k = (lag l, output o),
//               bounded with the noise bound and the same ellipsoid for the few Markov
//               parameters it needs (none for lag 0 with D known).

#include <Eigen/Core>

#include <string>
#include <vector>

#include "sets/methods/ss_uncertainty/canonical_fps.hpp"
#include "sets/methods/ss_uncertainty/propagator_identification.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets {

struct GuaranteedSetAssumptions {
  Eigen::VectorXd noise_bound;        // per output, >= 0 (always needed)
  Eigen::VectorXd tail_bound;         // per output, >= 0: the data-based state bound
  Eigen::VectorXd state_error_bound;  // per state, >= 0: a user's bound instead of tail_bound
};

struct StateEnclosure {
  IntervalMatrix states;      // nx x K: encloses x_c(first + k), k = 0..K-1 (K = number of x^ samples)
  /// nx x (K-1): for a unit row i of A_c (x_c,i(t+1) = x_c,k(t) + B_c(i,:) u(t)), an enclosure of
  /// x_c,i(t+1) - x_c,k(t) at t = first + k; [0, 0] in the rows of free rows.
  IntervalMatrix unit_steps;
  int first = 0;              // the time of states.col(0)
  /// Per output: the level gamma of the Markov-parameter ellipsoid (g-g^)^T Z^T Z (g-g^) <= gamma
  /// (rounded up); empty for a user's state bound.
  Eigen::VectorXd markov_level;
  /// Data that contradict the assumptions (each a sentence naming output, sample or state);
  /// empty when none. When not empty the true system cannot satisfy the assumptions.
  std::vector<std::string> contradictions;
};

/// Encloses the true canonical states under the assumptions. u (N x nu), y (N x ny) are the data
/// id was identified from. Throws InputError for bounds of the wrong size, negative or not
/// finite, or neither tail_bound nor state_error_bound given.
StateEnclosure enclose_states(const PropagatorResult& id, const Eigen::Ref<const Eigen::MatrixXd>& u,
                              const Eigen::Ref<const Eigen::MatrixXd>& y, const GuaranteedSetAssumptions& assumptions);

/// The regression of Remark 1 with the states replaced by their enclosures (interval regressors),
/// the unit rows of A_c by the unit steps and the output rows bounded by the noise bound: the
/// feasible parameter set that contains the true theta~ whenever the assumptions hold (it is
/// empty, with falsified rows, when the data contradict them).
CanonicalFps guaranteed_fps(const PropagatorResult& id, const Eigen::Ref<const Eigen::MatrixXd>& u,
                            const Eigen::Ref<const Eigen::MatrixXd>& y, const StateEnclosure& states,
                            const Eigen::Ref<const Eigen::VectorXd>& noise_bound);

/// For a known system (simulation studies): an upper bound on |r_j(t)| for every output j when
/// x(0) = 0 and |u| <= input_bound: sum_{k >= p} ||C_j A^k B||_1 input_bound (summed until the
/// terms are negligible, then enlarged by a margin for the rest and for rounding).
Eigen::VectorXd fir_tail_bound(const StateSpaceModel& system, int past, double input_bound);

}  // namespace sets
