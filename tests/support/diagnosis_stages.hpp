#pragma once
// Runs the stages of sets::diagnose (src/diagnosis/stages.hpp) one at a time on a plant, the way
// diagnose() chains them, so that each stage's own contract can be tested on its output.

#include <memory>
#include <string>

#include "diagnosis/stages.hpp"
#include "sets/data/intersample.hpp"
#include "sets/examples/synthetic_plants.hpp"

namespace sets::test {

struct StageRun {
  ModelFile model;
  Recording estimation, validation;
  DiagnosisOptions options;
  std::unique_ptr<Simulator> exact, fast, exact_validation;
  std::unique_ptr<diagnosis_stage::Context> context;
  Diagnosis d;

  /// The plant's nominal and records (the first `samples` of each when > 0, to keep a test
  /// short); screening with the final substeps (`substeps`, no substep search), one thread, no
  /// progress lines.
  explicit StageRun(const SyntheticPlant& plant, bool with_validation = true, int samples = 0, int substeps = 4)
      : model(with_intersample(plant.nominal)),
        estimation(first_samples(plant.estimation, samples)),
        validation(first_samples(plant.validation, samples)) {
    options.threads = 1;
    options.final_substeps = substeps;
    options.screening_substeps = substeps;
    exact = std::make_unique<Simulator>(model, estimation, SimulationOptions{options.final_substeps});
    fast = std::make_unique<Simulator>(model, estimation, SimulationOptions{options.screening_substeps});
    if (with_validation)
      exact_validation = std::make_unique<Simulator>(model, validation, SimulationOptions{options.final_substeps});
    d.has_validation = with_validation;
    d.outputs = exact->output_columns();
    context = std::make_unique<diagnosis_stage::Context>(diagnosis_stage::Context{
        model, estimation, with_validation ? &validation : nullptr, options, *exact, *fast, exact_validation.get(),
        [](const std::string&) {}});
  }
  StageRun(const StageRun&) = delete;
  StageRun& operator=(const StageRun&) = delete;

  const diagnosis_stage::Context& c() const { return *context; }

  static Recording first_samples(Recording r, int samples) {
    if (samples > 0)
      for (auto& column : r.columns)
        if (static_cast<int>(column.size()) > samples) column.resize(static_cast<std::size_t>(samples));
    return r;
  }
};

}  // namespace sets::test
