#include "sets/diagnosis/acceptance.hpp"

#include <cmath>

namespace sets {

std::vector<RuleCheck> check_rules(const HypothesisEvidence& e, const AcceptanceRules& r) {
  std::vector<RuleCheck> out;
  auto share = [](double before, double after) { return before > 0 ? (before - after) / before : 0.0; };
  out.push_back({"estimation_gain", "removes at least this share of the squared misfit on the estimation record",
                 share(e.cost_null, e.cost), r.min_gain, true, false});
  out.push_back({"beyond_noise", "removes more squared misfit than the measurement noise alone contains (multiple)",
                 e.noise_cost > 0 ? (e.cost_null - e.cost) / e.noise_cost : (e.cost_null > e.cost ? 1e300 : 0.0),
                 r.noise_multiple, true, false});
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

std::vector<RuleCheck> check_nested_rules(const HypothesisEvidence& e, const AcceptanceRules& r) {
  std::vector<RuleCheck> out = check_rules(e, r);
  const double left = e.cost - e.noise_cost;  // what the richer law leaves beyond the noise
  const double gain = e.cost_null - e.cost;
  RuleCheck k{"explains_where_they_differ",
              "where the two laws differ, removes at least as much misfit as it leaves beyond the noise (multiple)",
              left > 0 ? gain / left : (gain > 0 ? 1e300 : 0.0), 1.0, true, false};
  k.passed = std::isfinite(k.value) && k.value >= k.threshold;
  out.push_back(k);
  return out;
}

MisfitWhereTheyDiffer misfit_where_they_differ(const Eigen::Ref<const Eigen::MatrixXd>& measured,
                                               const Eigen::Ref<const Eigen::MatrixXd>& first,
                                               const Eigen::Ref<const Eigen::MatrixXd>& second,
                                               const std::vector<double>& sigma) {
  MisfitWhereTheyDiffer m;
  const bool same_shape = first.rows() == measured.rows() && second.rows() == measured.rows() &&
                          first.cols() == measured.cols() && second.cols() == measured.cols() &&
                          static_cast<Eigen::Index>(sigma.size()) == measured.cols();
  if (!same_shape) return m;
  for (Eigen::Index j = 0; j < measured.cols(); ++j) {
    const double spread = (measured.col(j).array() - measured.col(j).mean()).matrix().squaredNorm();
    const double s = sigma[static_cast<std::size_t>(j)];
    if (!(spread > 0) || !std::isfinite(s)) continue;
    double a = 0, b = 0;
    long n = 0;
    for (Eigen::Index t = 0; t < measured.rows(); ++t) {
      if (!(std::abs(first(t, j) - second(t, j)) > s)) continue;  // the noise could hide this difference
      a += (measured(t, j) - first(t, j)) * (measured(t, j) - first(t, j));
      b += (measured(t, j) - second(t, j)) * (measured(t, j) - second(t, j));
      ++n;
    }
    m.first += a / spread;
    m.second += b / spread;
    m.noise += static_cast<double>(n) * s * s / spread;
    m.samples += n;
  }
  return m;
}

HypothesisEvidence nested_evidence(const MisfitWhereTheyDiffer& estimation, const MisfitWhereTheyDiffer* validation) {
  HypothesisEvidence e;
  e.cost_null = estimation.first;
  e.cost = estimation.second;
  e.noise_cost = estimation.noise;
  if (validation && validation->samples > 0) {  // a record where they never differ cannot judge them
    e.cost_null_validation = validation->first;
    e.cost_validation = validation->second;
  }
  return e;
}

}  // namespace sets
