// Stage 1 of the diagnosis: the file's values, the calibrated nominal model.

#include <cmath>

#include "diagnosis/stages.hpp"

namespace sets::diagnosis_stage {

int screening_substeps(const ModelFile& model, const Recording& est, const Simulator& exact, int final_substeps) {
  // Screening runs thousands of simulations: use the coarsest step that gives the same fits.
  const auto ref = evaluate(exact, exact.parameter_values());
  for (int sub : {1, 2, 5}) {
    if (sub >= final_substeps || !ref.ok) break;
    Simulator s(model, est, {sub});
    const auto r = evaluate(s, s.parameter_values());
    bool same = r.ok;
    for (std::size_t j = 0; same && j < r.fit.size(); ++j) same = std::abs(r.fit[j] - ref.fit[j]) < 0.2;
    if (same) return sub;
  }
  return final_substeps;
}

NominalFit calibrate_nominal(const Context& c, Diagnosis& d) {
  const Eigen::MatrixXd& Y = c.exact.measured();
  c.say("simulating the nominal model");
  Eigen::VectorXd p0 = values_of(c.model);
  {
    SimulationResult r = c.exact.simulate(p0);  // throws with the time if it blows up
    d.fit_start_estimation = fits(Y, r.outputs);
    if (c.validation)
      d.fit_start_validation = fits(c.exact_validation->measured(), c.exact_validation->simulate(p0).outputs);
  }
  NominalFit n;
  n.free = c.fast.free_parameters();
  for (int i : n.free) d.free_nominal.push_back(c.model.parameters[static_cast<std::size_t>(i)].name);
  c.say("calibrating the nominal model's free parameters (" + std::to_string(c.options.screening_substeps) +
        " RK4 substeps while screening, " + std::to_string(c.options.final_substeps) + " for reported fits)");
  CalibrationOptions copt;
  copt.scale = scales_for(c.model, n.free, {});
  // Calibrated with the screening step; the reported fits below use the full substeps.
  n.calibration = calibrate(c.fast, p0, n.free, copt);
  d.nominal = c.model;
  store_values(d.nominal, n.calibration.parameters);
  n.simulation = c.exact.simulate(n.calibration.parameters);
  d.fit_nominal_estimation = fits(Y, n.simulation.outputs);
  if (c.validation) {
    n.validation_outputs = c.exact_validation->simulate(n.calibration.parameters).outputs;
    d.fit_nominal_validation = fits(c.exact_validation->measured(), n.validation_outputs);
  }
  n.cost = cost_of(d.fit_nominal_estimation);
  return n;
}

}  // namespace sets::diagnosis_stage
