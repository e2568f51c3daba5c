#include "sets/diagnosis/acceptance.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace sets {

namespace {

// Misfit removed over the noise's own misfit, the larger of two measures, either of which shows a
// gain the noise cannot give:
// - per output, each output's share counted in units of its own noise, (removed_j / noise_j)
//   averaged over the m outputs: the rule on outputs whitened by their noise. Summed by spread alone,
//   an output whose noise is large for its spread drowns the evidence of a quiet one (random plant
//   5 003 724: a dead zone removes 31 noise levels' misfit from the measured drive, 0.1 from the
//   noisy position, and failed at 0.57);
// - pooled, removed / noise summed over outputs by their spread: the units the calibration
//   minimises (calibration.hpp). A hypothesis calibrated there can trade a quiet output's fit for a
//   noisy output's, and per output the quiet one's noise units then outweigh the gain (random plant
//   5 004 998: a true offset removes 60 % of the misfit, 4.8 noise levels on the noisy output, and
//   costs the quiet one 9.8 of its own; -2.5 per output, 4.0 pooled: nothing was named).
// For one output, or outputs with equal noise for their spread, the two are the same number.
double beyond_noise(const HypothesisEvidence& e) {
  const double pooled = e.noise_cost > 0 ? (e.cost_null - e.cost) / e.noise_cost : (e.cost_null > e.cost ? 1e300 : 0.0);
  const std::size_t m = e.noise_cost_outputs.size();
  bool per_output = m > 0 && e.cost_null_outputs.size() == m && e.cost_outputs.size() == m;
  for (std::size_t j = 0; per_output && j < m; ++j) per_output = e.noise_cost_outputs[j] > 0;
  if (!per_output) return pooled;
  double sum = 0;
  for (std::size_t j = 0; j < m; ++j) sum += (e.cost_null_outputs[j] - e.cost_outputs[j]) / e.noise_cost_outputs[j];
  return std::max(pooled, sum / static_cast<double>(m));
}

}  // namespace

std::vector<RuleCheck> check_rules(const HypothesisEvidence& e, const AcceptanceRules& r) {
  std::vector<RuleCheck> out;
  auto share = [](double before, double after) { return before > 0 ? (before - after) / before : 0.0; };
  out.push_back({"estimation_gain", "removes at least this share of the squared misfit on the estimation record",
                 share(e.cost_null, e.cost), r.min_gain, true, false});
  double beyond = beyond_noise(e);
  // On either record: noise fitted on one cannot remove more than the other's own noise misfit there.
  if (e.noise_cost_validation > 0 && std::isfinite(e.cost_validation) && std::isfinite(e.cost_null_validation))
    beyond = std::max(beyond, (e.cost_null_validation - e.cost_validation) / e.noise_cost_validation);
  out.push_back({"beyond_noise", "removes more squared misfit than the measurement noise alone contains (multiple; the larger of: each output in units of its own noise, averaged; all outputs pooled by spread)",
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
