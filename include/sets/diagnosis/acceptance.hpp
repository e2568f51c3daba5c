#pragma once
// The documented rules a hypothesis must pass before the diagnosis says "missing: X"
// (docs/methods/diagnosis.md, step 3). Every rule is a number compared with a threshold, so the
// report can show each one and a test can make each one fail.

#include <Eigen/Core>

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
};

struct AcceptanceRules {
  double min_gain = 0.10;             // share of the estimation misfit removed
  double min_validation_gain = 0.05;  // share of the validation misfit removed
  double min_own_term = 0.10;         // share lost when its own term is switched off
  double noise_multiple = 1.0;        // misfit removed / the noise's own misfit
};

struct RuleCheck {
  std::string name;         // stable: "estimation_gain", "beyond_noise", "own_term", "validation_gain"
                            // (nested laws: "explains_where_they_differ")
  std::string description;  // the rule in words
  double value = 0, threshold = 0;
  bool applies = true;      // false: not applicable (no validation record, no neutral value)
  bool passed = true;
};

std::vector<RuleCheck> check_rules(const HypothesisEvidence& e, const AcceptanceRules& rules = {});
/// Every applicable rule passed.
bool passes(const std::vector<RuleCheck>& checks);

/// Two calibrated models judged where they disagree: the squared misfit of each (the costs'
/// units, each output divided by ||y_j - mean y_j||^2) and the noise's own misfit, summed only
/// over the samples (t, j) where the two simulated outputs differ by more than the noise level
/// sigma_j. Elsewhere the data cannot tell them apart, so a richer law's gain there is noise
/// fitted (or a difference too small to see); see `nested_evidence`.
struct MisfitWhereTheyDiffer {
  double first = 0, second = 0;  // squared misfit of each model on those samples
  double noise = 0;              // sum of sigma_j^2 over those samples, same units
  long samples = 0;              // (sample, output) pairs where they differ
};
MisfitWhereTheyDiffer misfit_where_they_differ(const Eigen::Ref<const Eigen::MatrixXd>& measured,
                                               const Eigen::Ref<const Eigen::MatrixXd>& first,
                                               const Eigen::Ref<const Eigen::MatrixXd>& second,
                                               const std::vector<double>& sigma);

/// The evidence for a richer law against its special case (both calibrated), restricted to the
/// samples where the two differ (estimation and, when given, validation): the special case is the
/// baseline, the richer law the hypothesis, the noise's misfit that on those samples, and no
/// switch-off rule (the special case is the richer law switched off, every other parameter free).
/// check_rules then asks the extra parameters to remove min_gain of the special case's misfit
/// where they act, and more than the noise there.
HypothesisEvidence nested_evidence(const MisfitWhereTheyDiffer& estimation, const MisfitWhereTheyDiffer* validation);
/// The rules for a richer law against its special case, on `nested_evidence`: check_rules, and
/// "explains_where_they_differ": where the two differ, the richer law removes at least as much of
/// the special case's misfit as it leaves beyond the noise's own misfit there, (cost_null - cost) /
/// (cost - noise_cost) >= 1. A richer law that only absorbs part of a mismatch it does not explain
/// (a stick-slip the simulated sign law cannot follow, an unmodelled mode) fits better there
/// without being the missing law.
std::vector<RuleCheck> check_nested_rules(const HypothesisEvidence& e, const AcceptanceRules& rules = {});

}  // namespace sets
