#include "sets/diagnosis/diagnosis.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <functional>
#include <iomanip>
#include <memory>
#include <sstream>

#include "diagnosis/stages.hpp"

namespace sets {

using namespace diagnosis_stage;

namespace {

// Where the mismatch is, in one line (windows, regions, frequency band).
std::string where_of(const Diagnosis& d) {
  std::ostringstream o;
  std::vector<MismatchWindow> ws = d.windows;
  std::sort(ws.begin(), ws.end(), [](const auto& a, const auto& b) { return a.rms * (a.end - a.start) > b.rms * (b.end - b.start); });
  for (std::size_t i = 0; i < std::min<std::size_t>(2, ws.size()); ++i)
    o << (i ? ", " : "largest in ") << ws[i].output << " at t = " << fmt(ws[i].start, 4) << " .. " << fmt(ws[i].end, 4) << " s";
  for (std::size_t i = 0; i < std::min<std::size_t>(2, d.regions.size()); ++i)
    o << (o.tellp() > 0 ? "; " : "") << "concentrated " << d.regions[i].description << " (" << fixed1(100 * d.regions[i].residual_share)
      << " % of it in " << fixed1(100 * d.regions[i].sample_share) << " % of the samples)";
  for (const auto& b : d.bands)
    o << (o.tellp() > 0 ? "; " : "") << "residual of " << b.output << " in " << fmt(b.lo_hz) << " .. " << fmt(b.hi_hz) << " Hz";
  return o.str();
}

// The answer: nothing missing (both residual tests agree), missing effects, or a real mismatch no
// catalogue effect explains.
void conclude(Diagnosis& d) {
  if (!d.effects.empty()) {
    d.nothing_missing = false;
    d.verdict = "Missing physics: ";
    for (std::size_t k = 0; k < d.effects.size(); ++k) d.verdict += (k ? ", " : "") + d.effects[k].name + " (" + d.effects[k].equation + ")";
    // Said, never hidden: an augmented model that fits worse than the nominal it extends.
    if (cost_of(d.fit_augmented_estimation) > cost_of(d.fit_nominal_estimation)) {
      d.verdict += "; the augmented model fits the estimation record worse than the calibrated nominal (";
      for (std::size_t j = 0; j < d.outputs.size(); ++j)
        d.verdict += (j ? ", " : "") + d.outputs[j] + " " + fixed1(d.fit_augmented_estimation[j]) + " % against " +
                     fixed1(d.fit_nominal_estimation[j]) + " %";
      d.verdict += ")";
    }
    // Against the noise read from the augmented model's own residual (diagnose, below).
    d.verdict += d.final_tests.within_noise() ? "; the augmented model is within the noise read from its residual."
                                              : "; a mismatch beyond the noise read from the augmented model's residual remains (" +
                                                    d.final_tests.summary() + ").";
    return;
  }
  d.nothing_missing = d.nominal_tests.within_noise();
  if (d.nothing_missing) {
    d.verdict = "No physics is missing: the calibrated nominal model is within the noise (" + d.nominal_tests.summary() + ").";
    return;
  }
  d.unexplained = true;
  d.where = where_of(d);
  const ResidualTests& t = d.nominal_tests;
  const std::string what = t.falsified ? "The mismatch is real but no catalogue effect explains it ("
                           : t.white && t.bursty ? "The residual is inside the noise bound but its fast part has bursts, which noise "
                                                   "does not (a switching mismatch that no catalogue effect explains; "
                           : t.white ? "The residual is inside the noise bound and white but follows the model's signals, which "
                                       "noise does not (a mismatch that no catalogue effect explains; "
                           : t.any_whitened() ? "The residual is inside the noise bound but not the coloured noise read from it (a "
                                        "mismatch that no catalogue effect explains, or noise of another colour; "
                                      : "The residual is inside the noise bound but not white (coloured measurement noise, or a "
                                        "mismatch that no catalogue effect explains; ";
  d.verdict = what + d.nominal_tests.summary() + ")" + (d.where.empty() ? "" : "; " + d.where) +
              (d.nominal_far ? "; " + d.nominal_note : "") + ".";
}

// The noise floor read from the calibrated nominal's residual, and that residual's tests.
NoiseFloor floor_and_tests(const Context& c, const NominalFit& nominal, Diagnosis& d) {
  const NoiseFloor noise = noise_floor(c, nominal, d);
  d.noise_sigma = noise.sigma;
  d.noise_note.clear();
  for (const auto& n : d.noise)
    d.noise_note += (d.noise_note.empty() ? "" : "; ") + n.output + ": " + noise_method_name(n.estimate.method);
  c.say("testing the calibrated nominal's residual (falsification, whiteness, independence)");
  d.nominal_tests = test_residual(c.exact, nominal.calibration.parameters, nominal.simulation, noise.sigma, noise.pole);
  return noise;
}

// A progress line: the wall time since `t_start` (the diagnosis' one start, which d.seconds is
// measured from too) and the process's CPU time (all threads) since this call, so the split per
// stage can be read on a loaded machine too. Silent without options.progress.
std::function<void(const std::string&)> progress_lines(const DiagnosisOptions& options, std::chrono::steady_clock::time_point t_start) {
  if (!options.progress) return [](const std::string&) {};
  const std::clock_t cpu_start = std::clock();
  return [progress = options.progress, t_start, cpu_start](const std::string& s) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(1)
       << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s (CPU "
       << static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC << " s): " << s;
    progress(os.str());
  };
}

// The screening step for the search, given the calibrated nominal. The calibrated values can have
// faster modes than the file's: a screening step that resolved the file's values may blow up on
// them (RK4 outside its stability region). Then the step is chosen again at the calibrated values,
// finer, by the first choice's test (a step just inside the stability interval is finite but can
// misplace the mode, |R(h lambda)| near 1). Not when it merely lost precision: the screening
// optima are refined with the final substeps anyway, and Silverbox's screening would double.
// When the file's values could not be simulated, no step was chosen at them (the final one was
// used): it is chosen at the calibrated values. `c.options.screening_substeps` is the first choice.
int screening_step_at_calibrated(const Context& c, const NominalFit& nominal, bool step_given) {
  const int first = c.options.screening_substeps, final_step = c.options.final_substeps;
  const Eigen::VectorXd& p = nominal.calibration.parameters;
  const bool chosen_at_calibrated = !step_given && !nominal.file_values.ok;
  int sub = first;
  if (chosen_at_calibrated) sub = screening_substeps(c.model, c.estimation, c.exact, p, final_step);
  else if (blows_up_at(c.fast, p, c.model)) sub = screening_substeps(c.model, c.estimation, c.exact, p, final_step, first + 1);
  if (sub != first)
    c.say(std::string(chosen_at_calibrated ? "the screening step chosen at the calibrated nominal (the file's values blow up): "
                                           : "the calibrated nominal needs a finer screening step: ") +
          std::to_string(sub) + " RK4 substeps instead of " + std::to_string(first));
  return sub;
}

// Each model is tested against the noise read from its own residual, as the nominal is: the
// nominal's floor carries the effects named since (random plant 5 005 586: 31x the truth, and the
// bound it gives passed an augmented model that still misses a dead zone; against the final
// reading that model is falsified), or reads coloured noise the nominal's error masked as white
// and too low (5 005 868: 0.19x).
void test_final_model(const Context& c, Diagnosis& d) {
  d.final_tests = d.nominal_tests;
  if (d.effects.empty()) return;
  const NoiseFloor left = levels_of(d.noise_final);
  Simulator aug(d.augmented, c.estimation, {c.options.final_substeps});
  const Eigen::VectorXd p = aug.parameter_values();
  d.final_tests = test_residual(aug, p, aug.simulate(p), left.sigma, left.pole);
}

// The series the reports plot: time, measured and nominal outputs of both records.
void keep_series(const Context& c, const NominalFit& nominal, Diagnosis& d) {
  d.time_estimation = Eigen::Map<const Eigen::VectorXd>(c.exact.time().data(), c.exact.samples());
  d.measured_estimation = c.exact.measured();
  d.nominal_estimation = nominal.simulation.outputs;
  if (!c.exact_validation) return;
  d.time_validation = Eigen::Map<const Eigen::VectorXd>(c.exact_validation->time().data(), c.exact_validation->samples());
  d.measured_validation = c.exact_validation->measured();
  d.nominal_validation = nominal.validation_outputs;
}

}  // namespace

Diagnosis diagnose(const ModelFile& model_file, const Recording& est, const Recording* val, const DiagnosisOptions& options) {
  // Every input's intersample behaviour written out (the file's, or the override): the fits are
  // made under it and the augmented model file records it.
  const ModelFile model = with_intersample(model_file, options.intersample);
  const auto t_start = std::chrono::steady_clock::now();
  const auto say = progress_lines(options, t_start);
  Diagnosis d;
  d.has_validation = val != nullptr;
  DiagnosisOptions opt = options;
  Simulator exact(model, est, {opt.final_substeps});
  if (opt.screening_substeps <= 0)
    opt.screening_substeps = screening_substeps(model, est, exact, exact.parameter_values(), opt.final_substeps);
  Simulator fast(model, est, {opt.screening_substeps});
  std::unique_ptr<Simulator> exact_val;
  if (val) exact_val = std::make_unique<Simulator>(model, *val, SimulationOptions{opt.final_substeps});
  d.outputs = exact.output_columns();
  const Context at_file_step{model, est, val, opt, exact, fast, exact_val.get(), say};
  NominalFit nominal = calibrate_nominal(at_file_step, d);  // 1.
  NoiseFloor noise = floor_and_tests(at_file_step, nominal, d);
  // Random plant 5 008 857 (clean, two masses): calibrated from the first starts to 99.2 % with a
  // coupling damping 16x the truth's, it named viscous friction (99.8 %, as the truth's values fit).
  if (!d.nominal_tests.within_noise() && recalibrate_stalled_nominal(at_file_step, nominal, d))
    noise = floor_and_tests(at_file_step, nominal, d);
  const int sub = screening_step_at_calibrated(at_file_step, nominal, options.screening_substeps > 0);
  std::unique_ptr<Simulator> other_step;
  if (sub != opt.screening_substeps) {
    opt.screening_substeps = sub;
    other_step = std::make_unique<Simulator>(model, est, SimulationOptions{sub});
  }
  const Context c{model, est, val, opt, exact, other_step ? *other_step : fast, exact_val.get(), say};
  test_data_hypothesis(c, nominal, noise, d);                                   // about the data, not physics
  locate_mismatch(c, nominal, noise, d);                                        // 2.
  const HypothesisSearch search = search_hypotheses(c, nominal, noise, d);      // 3.
  augment(c, nominal, search, d);                                               // 4.
  final_noise(c, d);                                                            // not a rule's input
  test_final_model(c, d);
  conclude(d);
  say("done");
  keep_series(c, nominal, d);
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return d;
}

}  // namespace sets
