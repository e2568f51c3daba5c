#pragma once
// The documented rules a hypothesis must pass before the diagnosis says "missing: X"
// (docs/methods/diagnosis.md, step 3). Every rule is a number compared with a threshold, so the
// report can show each one and a test can make each one fail.

#include <limits>
#include <string>
#include <vector>

namespace sets {

/// What the rules judge a refined hypothesis on. Costs are squared misfits summed over outputs,
/// sum_j ||y_j - yhat_j||^2 / ||y_j - mean y_j||^2.
struct HypothesisEvidence {
  double cost_null = 0;     // the current model re-calibrated (same budget): the baseline
  double cost = 0;          // with the effect, calibrated
  double cost_neutral = std::numeric_limits<double>::quiet_NaN();  // effect switched off at the
                                                                   // calibrated point (NaN: no neutral value)
  double cost_null_validation = std::numeric_limits<double>::quiet_NaN();  // NaN: no validation record
  double cost_validation = std::numeric_limits<double>::quiet_NaN();
  double noise_cost = 0;    // the misfit the measurement noise alone gives on the estimation record
  /// The same three per output (optional): when given, with every output's noise cost positive,
  /// the noise rule also weighs each output by its own noise (a quiet output's evidence is not
  /// drowned by a noisy output's noise) and takes the larger of that and the sums above; one
  /// output, or outputs equally noisy for their spread, give the same number both ways.
  std::vector<double> cost_null_outputs, cost_outputs, noise_cost_outputs;
  /// The noise's misfit on the validation record (summed over outputs); given (not NaN) only where a
  /// gain beyond the noise on either record counts: the nested rule, a richer law against its special case (judge_round.cpp).
  double noise_cost_validation = std::numeric_limits<double>::quiet_NaN();
};

struct AcceptanceRules {
  double min_gain = 0.10;             // share of the estimation misfit removed
  double min_validation_gain = 0.05;  // share of the validation misfit removed
  double min_own_term = 0.10;         // share lost when its own term is switched off
  double noise_multiple = 1.0;        // misfit removed / the noise's own misfit (per output or pooled, the larger)
};

struct RuleCheck {
  std::string name;         // stable: "estimation_gain", "beyond_noise", "own_term", "validation_gain"
  std::string description;  // the rule in words
  double value = 0, threshold = 0;
  bool applies = true;      // false: not applicable (no validation record, no neutral value)
  bool passed = true;
};

std::vector<RuleCheck> check_rules(const HypothesisEvidence& e, const AcceptanceRules& rules = {});
/// Every applicable rule passed.
bool passes(const std::vector<RuleCheck>& checks);
/// The applicable rules that failed, each with its value and threshold ("own_term 0.00123 < 0.1,
/// ..."), for a report that says why; empty when every one passed.
std::string failed_rules(const std::vector<RuleCheck>& checks);

}  // namespace sets
