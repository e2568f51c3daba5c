#include "sets/diagnosis/acceptance.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace sets {

std::vector<RuleCheck> check_rules(const HypothesisEvidence& e, const AcceptanceRules& r) {
  std::vector<RuleCheck> out;
  auto share = [](double before, double after) { return before > 0 ? (before - after) / before : 0.0; };
  out.push_back({"estimation_gain", "removes at least this share of the squared misfit on the estimation record",
                 share(e.cost_null, e.cost), r.min_gain, true, false});
  double beyond = e.noise_cost > 0 ? (e.cost_null - e.cost) / e.noise_cost : (e.cost_null > e.cost ? 1e300 : 0.0);
  // On either record: noise fitted on one cannot remove more than the other's own noise misfit there.
  if (e.noise_cost_validation > 0 && std::isfinite(e.cost_validation) && std::isfinite(e.cost_null_validation))
    beyond = std::max(beyond, (e.cost_null_validation - e.cost_validation) / e.noise_cost_validation);
  out.push_back({"beyond_noise", "removes more squared misfit than the measurement noise alone contains (multiple)",
                 beyond, r.noise_multiple, true, false});
  const bool neutral = std::isfinite(e.cost_neutral);
  out.push_back({"own_term", "switching the effect off at the calibrated point costs at least this share",
                 neutral ? share(e.cost_neutral, e.cost) : 0.0, r.min_own_term, neutral, false});
  const bool val = std::isfinite(e.cost_validation) && std::isfinite(e.cost_null_validation);
  out.push_back({"validation_gain", "removes at least this share of the squared misfit on the validation record",
                 val ? share(e.cost_null_validation, e.cost_validation) : 0.0, r.min_validation_gain, val, false});
  for (auto& c : out) c.passed = !c.applies || (std::isfinite(c.value) && c.value >= c.threshold);
  return out;
}

bool passes(const std::vector<RuleCheck>& checks) {
  for (const auto& c : checks)
    if (!c.passed) return false;
  return true;
}

std::string failed_rules(const std::vector<RuleCheck>& checks) {
  std::ostringstream o;
  o << std::setprecision(3);
  for (const auto& c : checks)
    if (!c.passed) o << (o.tellp() > 0 ? ", " : "") << c.name << " " << c.value << " < " << c.threshold;
  return o.str();
}

}  // namespace sets
