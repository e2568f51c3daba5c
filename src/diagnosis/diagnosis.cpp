#include "sets/diagnosis/diagnosis.hpp"

#include <chrono>
#include <iomanip>
#include <memory>
#include <sstream>

#include "diagnosis/stages.hpp"

namespace sets {

using namespace diagnosis_stage;

namespace {

// The answer in one sentence, and whether nothing is missing.
void conclude(const NominalFit& nominal, const NoiseFloor& noise, const DiagnosisOptions& opt, Diagnosis& d) {
  if (d.effects.empty()) {
    if (nominal.cost <= opt.noise_floor_factor * noise.cost || !d.nothing_missing) {
      // Either within the noise, or no catalogue effect helps: never invent one.
      d.nothing_missing = nominal.cost <= opt.noise_floor_factor * noise.cost;
    }
    d.verdict = d.nothing_missing
                    ? "No physics is missing: the calibrated nominal model explains the data to within the noise."
                    : "No effect of the catalogue explains the remaining mismatch; no physics is added.";
    if (!d.nothing_missing) {
      // Is what remains distinguishable from noise at all? A small relative misfit means the model is fine.
      bool all_good = true;
      for (double f : d.fit_nominal_estimation) all_good = all_good && f > 90;
      if (all_good) {
        d.nothing_missing = true;
        d.verdict = "No physics is missing: no catalogue effect improves the calibrated nominal model beyond the noise.";
      }
    }
  } else {
    d.verdict = "Missing physics: ";
    for (std::size_t k = 0; k < d.effects.size(); ++k) d.verdict += (k ? ", " : "") + d.effects[k].name + " (" + d.effects[k].equation + ")";
    d.verdict += ".";
  }
}

}  // namespace

Diagnosis diagnose(const ModelFile& model_file, const Recording& est, const Recording* val, const DiagnosisOptions& options) {
  // Every input's intersample behaviour written out (the file's, or the override): the fits are
  // made under it and the augmented model file records it.
  const ModelFile model = with_intersample(model_file, options.intersample);
  const auto t_start = std::chrono::steady_clock::now();
  auto say = [&](const std::string& s) {
    if (!options.progress) return;
    std::ostringstream os;
    os << std::fixed << std::setprecision(1)
       << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s: " << s;
    options.progress(os.str());
  };
  Diagnosis d;
  d.has_validation = val != nullptr;
  DiagnosisOptions opt = options;
  Simulator exact(model, est, {opt.final_substeps});
  if (opt.screening_substeps <= 0) opt.screening_substeps = screening_substeps(model, est, exact, opt.final_substeps);
  Simulator fast(model, est, {opt.screening_substeps});
  std::unique_ptr<Simulator> exact_val;
  if (val) exact_val = std::make_unique<Simulator>(model, *val, SimulationOptions{opt.final_substeps});
  d.outputs = exact.output_columns();
  const Context c{model, est, val, opt, exact, fast, exact_val.get(), say};

  const NominalFit nominal = calibrate_nominal(c, d);                          // 1.
  const NoiseFloor noise = noise_floor(c, nominal, d);
  test_data_hypothesis(c, nominal, noise, d);                                   // about the data, not physics
  locate_mismatch(c, nominal, noise, d);                                        // 2.
  const HypothesisSearch search = search_hypotheses(c, nominal, noise, d);      // 3.
  augment(c, nominal, search, d);                                               // 4.
  conclude(nominal, noise, opt, d);

  d.time_estimation = Eigen::Map<const Eigen::VectorXd>(exact.time().data(), exact.samples());
  d.measured_estimation = exact.measured();
  d.nominal_estimation = nominal.simulation.outputs;
  if (val) {
    d.time_validation = Eigen::Map<const Eigen::VectorXd>(exact_val->time().data(), exact_val->samples());
    d.measured_validation = exact_val->measured();
    d.nominal_validation = nominal.validation_outputs;
  }
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return d;
}

}  // namespace sets
