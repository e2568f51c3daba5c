// The noise level of every output (sets/data/noise_level.hpp) and the misfit the noise alone
// gives (the diagnosis' noise floor). The noise of a channel is a property of the channel: it is
// estimated on every record from the calibrated nominal's residual and the model's exogenous
// inputs, and the value of the most reliable method is used for all records.

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

}  // namespace

NoiseFloor noise_floor(const Context& c, const NominalFit& nominal, Diagnosis& d) {
  c.say("estimating the noise level of every output");
  const Eigen::MatrixXd& Y = c.exact.measured();
  const Eigen::MatrixXd U = exogenous_inputs(c.model, c.estimation);
  Eigen::MatrixXd Uv;
  if (c.validation) Uv = exogenous_inputs(c.model, *c.validation);
  NoiseFloor f;
  const Eigen::Index N = Y.rows();
  for (Eigen::Index j = 0; j < Y.cols(); ++j) {
    std::vector<NoiseLevelEstimate> e{estimate_noise(Y.col(j), nominal.simulation.outputs.col(j), U)};
    if (c.validation && nominal.validation_outputs.cols() == Y.cols())
      e.push_back(estimate_noise(c.exact_validation->measured().col(j), nominal.validation_outputs.col(j), Uv));
    const std::size_t best = most_reliable(e);
    OutputNoise on;
    on.output = d.outputs[static_cast<std::size_t>(j)];
    on.estimate = e[best];
    on.record = best == 0 ? "estimation" : "validation";
    d.noise.push_back(on);
    const double s = on.estimate.sigma;
    f.sigma.push_back(s);
    const double den = (Y.col(j).array() - Y.col(j).mean()).matrix().squaredNorm();
    if (den > 0) f.cost += s * s * static_cast<double>(N) / den;
  }
  return f;
}

}  // namespace sets::diagnosis_stage
