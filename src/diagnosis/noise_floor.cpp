// The noise level of every output (sets/data/noise_level.hpp) and the misfit the noise alone
// gives (the diagnosis' noise floor). The noise of a channel is a property of the channel: it is
// estimated on every record from a calibrated model's residual and the model's exogenous inputs,
// and the value of the most reliable method is used for all records. The floor the rules use is
// read from the calibrated nominal's residual (before any effect is named) and lowered where a
// calibrated hypothesis leaves less than it; the final estimate is read again from the augmented
// model's, which no longer carries the effects it names.

#include "diagnosis/stages.hpp"

namespace sets::diagnosis_stage {

namespace {

// The model's inputs (exogenous by the model file's definition) as columns of the recording.
Eigen::MatrixXd exogenous_inputs(const ModelFile& model, const Recording& r) {
  Eigen::MatrixXd U(r.rows(), static_cast<Eigen::Index>(model.inputs.size()));
  for (std::size_t i = 0; i < model.inputs.size(); ++i) {
    const auto& col = r.column(model.inputs[i].second);
    U.col(static_cast<Eigen::Index>(i)) = Eigen::Map<const Eigen::VectorXd>(col.data(), r.rows());
  }
  return U;
}

// The noise of every output read from one model's simulated outputs on the estimation record
// and (when given, same columns) on the validation record.
std::vector<OutputNoise> read_noise(const Context& c, const std::vector<std::string>& outputs, const Eigen::MatrixXd& simulated,
                                    const Eigen::MatrixXd& simulated_validation, const std::string& model) {
  const Eigen::MatrixXd& Y = c.exact.measured();
  const Eigen::MatrixXd U = exogenous_inputs(c.model, c.estimation);
  Eigen::MatrixXd Uv;
  const bool validation = c.validation && c.exact_validation && simulated_validation.cols() == Y.cols() &&
                          simulated_validation.rows() == c.exact_validation->measured().rows();
  if (validation) Uv = exogenous_inputs(c.model, *c.validation);
  std::vector<OutputNoise> out;
  for (Eigen::Index j = 0; j < Y.cols(); ++j) {
    std::vector<NoiseLevelEstimate> e{estimate_noise(Y.col(j), simulated.col(j), U)};
    if (validation) e.push_back(estimate_noise(c.exact_validation->measured().col(j), simulated_validation.col(j), Uv));
    const std::size_t best = most_reliable(e);
    out.push_back({outputs[static_cast<std::size_t>(j)], e[best], best == 0 ? "estimation" : "validation", model});
  }
  return out;
}

// The misfit (cost_of units) noise of level sigma gives on each output of a record's outputs Y (0
// where an output is constant).
std::vector<double> noise_costs_on(const Eigen::MatrixXd& Y, const std::vector<double>& sigma) {
  std::vector<double> costs;
  for (Eigen::Index j = 0; j < Y.cols() && j < static_cast<Eigen::Index>(sigma.size()); ++j) {
    const double s = sigma[static_cast<std::size_t>(j)], den = (Y.col(j).array() - Y.col(j).mean()).matrix().squaredNorm();
    costs.push_back(den > 0 ? s * s * static_cast<double>(Y.rows()) / den : 0.0);
  }
  return costs;
}

}  // namespace

NoiseFloor levels_of(const std::vector<OutputNoise>& readings) {
  NoiseFloor f;
  for (const auto& n : readings) {
    f.sigma.push_back(n.estimate.sigma);
    f.pole.push_back(n.estimate.ar_pole);
  }
  return f;
}

// The floor's misfits on both records from its levels.
void fill_costs(const Context& c, NoiseFloor& f) {
  f.costs = noise_costs_on(c.exact.measured(), f.sigma);
  f.cost = 0;
  for (double x : f.costs) f.cost += x;
  if (c.exact_validation) {
    f.cost_validation = 0;
    for (double x : noise_costs_on(c.exact_validation->measured(), f.sigma)) f.cost_validation += x;
  }
}

NoiseFloor noise_floor(const Context& c, const NominalFit& nominal, Diagnosis& d) {
  c.say("estimating the noise level of every output");
  d.noise = read_noise(c, d.outputs, nominal.simulation.outputs, nominal.validation_outputs, "nominal");
  NoiseFloor f = levels_of(d.noise);
  fill_costs(c, f);
  return f;
}

NoiseFloor floor_within_fits(const Context& c, const NoiseFloor& floor, const std::vector<double>& least_costs,
                             const std::vector<std::string>& outputs) {
  NoiseFloor f = floor;
  f.note.clear();
  for (std::size_t j = 0; j < least_costs.size() && j < f.costs.size() && j < outputs.size(); ++j)
    if (least_costs[j] >= 0 && least_costs[j] < f.costs[j]) {
      const double sigma = f.sigma[j] * std::sqrt(least_costs[j] / f.costs[j]);
      f.note += (f.note.empty() ? "" : "; ") + outputs[j] + " " + fmt(f.sigma[j]) + " -> " + fmt(sigma);
      f.sigma[j] = sigma;
    }
  fill_costs(c, f);
  return f;
}

void final_noise(const Context& c, Diagnosis& d) {
  if (d.effects.empty()) {
    d.noise_final = d.noise;
    return;
  }
  c.say("estimating the noise level again from the augmented model's residual");
  d.noise_final = read_noise(c, d.outputs, d.augmented_estimation, d.augmented_validation, "augmented");
}

}  // namespace sets::diagnosis_stage
