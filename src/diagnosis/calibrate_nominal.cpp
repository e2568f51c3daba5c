// Stage 1 of the diagnosis: the file's values, the calibrated nominal model (several starts, so
// that a stalled calibration is never blamed on missing physics), the noise level.

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <random>
#include <sstream>

#include "diagnosis/stages.hpp"
#include "sets/core/error.hpp"
#include "sets/diagnosis/equation_error.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets::diagnosis_stage {

int screening_substeps(const ModelFile& model, const Recording& est, const Simulator& exact, const Eigen::VectorXd& p,
                       int final_substeps, int at_least) {
  // Screening runs thousands of simulations: use the coarsest step that gives the same fits.
  // Every count is tried, not a ladder's rungs ({1, 2, 5} was): what decides is RK4's stability
  // interval (|h lambda| < 2.79 on the real axis), which a calibrated stiff mode can put at any
  // count, and a count that is one rung short costs the whole search the next rung (5 -> 10).
  // Trying them all costs at most final_substeps simulations here, the search thousands.
  const auto ref = evaluate(exact, p);
  for (int sub = std::max(1, at_least); ref.ok && sub < final_substeps; ++sub) {
    Simulator s(model, est, {sub});
    const auto r = evaluate(s, p);
    bool same = r.ok;
    for (std::size_t j = 0; same && j < r.fit.size(); ++j) same = std::abs(r.fit[j] - ref.fit[j]) < 0.2;
    if (same) return sub;
  }
  return std::max(at_least, final_substeps);
}

// A step can grow a mode the calibrated values made faster without overflowing over a record (a
// misfit of 1e88, not infinity: random plant 5 003 617, two masses, 1 substep), and every
// hypothesis screened and refined at that step is then judged against that number. The
// calibration fits better than the file's values at the final step, and the step was chosen
// where the file's values fit as at the final step; a step at which the calibrated values fit
// worse than the file's reverses that order: it no longer shows the model being searched around.
bool blows_up_at(const Simulator& fast, const Eigen::VectorXd& p, const ModelFile& file) {
  const auto at_p = evaluate(fast, p);
  if (!at_p.ok || !std::isfinite(at_p.cost)) return true;
  const auto at_file = evaluate(fast, values_of(file));
  return at_file.ok && at_p.cost > at_file.cost;
}

namespace {

using Start = std::pair<std::string, Eigen::VectorXd>;

// Least-squares estimates from the equation error of every state equation that can be
// reconstructed from the data (the start is the file's values elsewhere); empty if none.
Eigen::VectorXd equation_error_start(const ModelFile& model, const Recording& est, const Eigen::VectorXd& p0) {
  Eigen::VectorXd p = p0;
  bool changed = false;
  for (const auto& st : model.states) {
    EquationErrorFit f;
    try {
      f = equation_error_fit(model, est, st.name);
    } catch (const std::exception&) {
      continue;
    }
    // Not from sampled signals evaluated at the samples (a position loop's controller): measured on
    // one development plant only (800 015), where that start moved the nominal to another optimum
    // of the same fit and the search on to a worse one; the nominal's starts are kept as they were.
    if (!f.built || f.from_samples) continue;
    for (std::size_t k = 0; k < f.parameters.size(); ++k)
      for (std::size_t i = 0; i < model.parameters.size(); ++i) {
        const auto& mp = model.parameters[i];
        if (mp.name != f.parameters[k] || mp.fixed || !std::isfinite(f.estimate[k])) continue;
        p[static_cast<Eigen::Index>(i)] = std::clamp(f.estimate[k], mp.min, mp.max);
        changed = true;
      }
  }
  return changed ? p : Eigen::VectorXd();
}

// The first part of the record: a short horizon has fewer local minima of the output error.
Recording head_of(const Recording& r, int rows) {
  Recording h = r;
  for (auto& c : h.columns) c.resize(static_cast<std::size_t>(rows));
  return h;
}

// A calibration continued from where it stopped until Levenberg-Marquardt stops on its tolerances
// (at most `rounds` calls in all, `first` the first). Eigen's LM counts the Jacobian's simulations
// in its budget, so one call is about 8 iterations for 5 parameters, and a call that stopped on
// that budget is no optimum: continued from there at another step it can fall into another basin
// (random plant 5 002 312, two masses: the screening calibration from the file's values stopped
// at 59.5 %, continued at the final step it went to a coupling stiffness 50x the truth and a
// negative damping, 83.6 %, and Coulomb friction was named; continued at the screening step first,
// 94.4 %, then 99.7 % at the final step, as the truth).
struct Continued {
  CalibrationResult result;
  int calls = 1, evaluations = 0;
};

Continued until_converged(const Simulator& sim, CalibrationResult first, const CalibrationOptions& copt, int rounds = 4) {
  Continued k;
  k.evaluations = first.evaluations;
  k.result = std::move(first);
  while (k.result.ok && !k.result.converged && k.calls < rounds) {
    CalibrationResult next = calibrate(sim, k.result.parameters, k.result.free, copt);
    ++k.calls, k.evaluations += next.evaluations;
    if (!next.ok || next.cost > k.result.cost) break;  // calibrate never returns worse than its start
    k.result = std::move(next);
  }
  return k;
}

// One start calibrated with the screening substeps, its optimum checked with the final ones.
// RK4 damps a mode it resolves coarsely (|R(i w h)| < 1), so the coarse output error can prefer a
// negative damping that the coarse simulation hides and the fine one shows as growth without
// bound. An optimum whose final-substep simulation is not finite, or fits worse than its start or
// the file's values (`file`, final substeps), is rejected, and the start is calibrated again with
// the final substeps (whose trial steps that blow up Levenberg-Marquardt refuses). Fits and cost
// of the result are at the final substeps; ok = false (the reason in `note`) when neither converges.
CalibrationResult calibrate_from(const Context& c, const Eigen::VectorXd& start, const CalibrationResult& file,
                                 const std::vector<int>& free, const CalibrationOptions& copt, std::ostringstream& note) {
  const CalibrationResult from = evaluate(c.exact, start);
  double reference = 1e300;
  for (const CalibrationResult* r : {&from, &file})
    if (r->ok) reference = std::min(reference, r->cost);
  const auto confirmed = [reference](const CalibrationResult& x) { return x.ok && x.cost <= reference; };
  const Continued coarse = until_converged(c.fast, calibrate(c.fast, start, free, copt), copt);
  if (!coarse.result.ok) {
    note << "blows up;";
    return coarse.result;
  }
  if (coarse.calls > 1)
    note << "continued at " << c.options.screening_substeps << " RK4 substeps until converged (" << coarse.calls << " calls, "
         << coarse.evaluations << " simulations" << (coarse.result.converged ? "" : ", still not converged") << ") -> ";
  CalibrationResult x = evaluate(c.exact, coarse.result.parameters);
  x.free = free;
  if (confirmed(x)) return x;
  note << "an optimum that " << (x.ok ? "fits worse than its start or the file's values" : "diverges") << " at " << c.options.final_substeps
       << " RK4 substeps (the screening step hides it), calibrated again with " << c.options.final_substeps << " -> ";
  CalibrationResult again = calibrate(c.exact, start, free, copt);
  if (!confirmed(again)) {
    note << "did not converge;";
    again.ok = false;
  }
  return again;
}

// Why `model` cannot be simulated at `p` over `sim`'s record ("the simulation blew up at t = ... s
// (v is no longer finite)"), empty when it can; `outputs` gets the simulated outputs.
std::string simulation_failure(const ModelFile& model, const Simulator& sim, const Eigen::VectorXd& p, Eigen::MatrixXd& outputs) {
  try {
    outputs = sim.simulate(p).outputs;
    return "";
  } catch (const NumericalError& e) {
    const std::string what = e.what(), prefix = model.source + ": ";
    return what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
  }
}

// The fits of the file's values on both records. A nominal written by an engineer can be unstable
// at its file's values (a sign, a damping too small) while its structure is fine: then the fits are
// NaN ("not available"), d.fit_start_note says why, and the other starts are calibrated.
CalibrationResult fits_at_file_values(const Context& c, const Eigen::VectorXd& p0, Diagnosis& d) {
  CalibrationResult at_file;
  Eigen::MatrixXd y;
  const std::string failed = simulation_failure(c.model, c.exact, p0, y);
  const std::size_t outputs = static_cast<std::size_t>(c.exact.measured().cols());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  d.fit_start_estimation = failed.empty() ? fits(c.exact.measured(), y) : std::vector<double>(outputs, nan);
  at_file.ok = failed.empty();
  at_file.cost = at_file.ok ? cost_of(d.fit_start_estimation) : nan;
  if (!failed.empty()) d.fit_start_note = "the file's values cannot be simulated over the estimation record: " + failed;
  if (!c.validation) return at_file;
  const std::string failed_val = failed.empty() ? simulation_failure(c.model, *c.exact_validation, p0, y) : failed;
  d.fit_start_validation = failed_val.empty() ? fits(c.exact_validation->measured(), y) : std::vector<double>(outputs, nan);
  if (failed.empty() && !failed_val.empty())
    d.fit_start_note = "the file's values cannot be simulated over the validation record: " + failed_val;
  return at_file;
}

// The best start's optimum continued at the final substeps until Levenberg-Marquardt stops on its
// tolerances (at most `rounds` calls). The screening step's optimum is not the final step's: RK4 at
// a coarse step misplaces a lightly damped mode's frequency and the parameters absorb it (random
// plant 5 001 765: M_m 0.3 % off, a model error of 2.9 noise levels RMS that the rules called an
// unexplained mismatch and the noise reading took for the signal). And a calibration that stopped
// on its evaluation budget is no optimum (5 001 610, five parameters and one sine: fit 69 % where
// continuing reaches 93 %). Either leaves model error that would be blamed on missing physics.
CalibrationResult continue_at_final_substeps(const Context& c, const CalibrationResult& best, const CalibrationOptions& copt,
                                             std::ostringstream& note) {
  constexpr int rounds = 4;
  CalibrationResult r = best;
  int evaluations = 0, calls = 0;
  bool converged = false;
  while (calls < rounds && !converged) {
    CalibrationResult next = calibrate(c.exact, r.parameters, best.free, copt);
    ++calls, evaluations += next.evaluations, converged = next.converged;
    if (!next.ok || next.cost > r.cost) break;  // calibrate never returns worse than its start
    r = std::move(next);
  }
  r.free = best.free;
  note << " the best continued at " << c.options.final_substeps << " RK4 substeps until converged (" << calls
       << (calls == 1 ? " call, " : " calls, ") << evaluations << " simulations" << (converged ? "" : ", still not converged")
       << "): fit";
  for (double f : r.fit) note << " " << fixed1(f) << " %";
  note << ";";
  return r;
}

// The calibrations of `starts` (one worker job each, with its own simulators: a Simulator is not
// shared between threads); notes and choice in start order, so the result is the serial one.
// `best` is replaced by a start's optimum that fits better; `worst_cost` is raised to the worst.
void calibrate_starts(const Context& c, const std::vector<Start>& starts, const CalibrationResult& at_file, const std::vector<int>& free,
                      const CalibrationOptions& copt, CalibrationResult& best, double& worst_cost, std::ostringstream& note) {
  std::vector<CalibrationResult> results(starts.size());
  std::vector<std::ostringstream> notes(starts.size());
  run_jobs(c.options.threads, starts.size(), [&](std::size_t i) {
    const Simulator fast(c.model, c.estimation, {c.options.screening_substeps});
    const Simulator exact(c.model, c.estimation, {c.options.final_substeps});
    const Context own{c.model, c.estimation, c.validation, c.options, exact, fast, c.exact_validation, c.say};
    results[i] = calibrate_from(own, starts[i].second, at_file, free, copt, notes[i]);
  });
  for (std::size_t i = 0; i < starts.size(); ++i) {
    note << " " << starts[i].first << " -> " << notes[i].str();
    const CalibrationResult& r = results[i];
    if (!r.ok) continue;
    note << "fit";
    for (double f : r.fit) note << " " << fixed1(f) << " %";
    note << ";";
    worst_cost = std::max(worst_cost, r.cost);
    if (!best.ok || r.cost < best.cost) best = r;
  }
}

// Below this fit on an output the nominal is "far from the data" (as the report says). A fit is
// never NaN here (a simulation that is not finite ends with ok = false), so < and !(>=) agree.
constexpr double far_fit = 50;
bool far_from(const std::vector<double>& fit) {
  return std::any_of(fit.begin(), fit.end(), [](double f) { return !(f >= far_fit); });
}

// Starts for a nominal whose calibration stays far from the data from the file's values, the
// equation-error fit and the record's head: the file's free values times factors drawn
// log-uniformly in [1/spread, spread], clamped to the parameter's bounds. Random plant 5 008 712
// (two masses, states not measured): both starts stalled at -207 %, and the stall was then
// credited to a Bouc-Wen law; from four such starts, one reached 99.4 % and "no physics is
// missing". A fixed seed keeps the diagnosis reproducible (mt19937_64's output is the same on
// every platform; the mapping to [0, 1) is ours, as std's distributions are not).
constexpr double random_start_spread = 3;
constexpr int random_start_count = 6;
std::vector<Start> random_starts(const ModelFile& model, const std::vector<int>& free, const Eigen::VectorXd& p0) {
  std::mt19937_64 gen(20261130);
  std::vector<Start> out;
  for (int k = 1; k <= random_start_count; ++k) {
    Eigen::VectorXd p = p0;
    for (int i : free) {
      const double u = static_cast<double>(gen() >> 11) * 0x1.0p-53;  // [0, 1)
      const auto& mp = model.parameters[static_cast<std::size_t>(i)];
      p[i] = std::clamp(p0[i] * std::pow(random_start_spread, 2 * u - 1), mp.min, mp.max);
    }
    out.emplace_back("random start " + std::to_string(k), p);
  }
  return out;
}

// The random starts calibrated (at most once per diagnosis), `note` saying why and how they were
// drawn; their best (ok = false when none converged). `worst_cost` is raised to the worst.
CalibrationResult calibrate_random_starts(const Context& c, NominalFit& n, const CalibrationOptions& copt, const std::string& why,
                                          double& worst_cost, std::ostringstream& note) {
  const auto more = random_starts(c.model, n.free, values_of(c.model));
  note << " " << why << ": " << more.size() << " more starts, the file's values times random factors in [1/"
       << random_start_spread << ", " << random_start_spread << "]:";
  CalibrationResult best;
  calibrate_starts(c, more, n.file_values, n.free, copt, best, worst_cost, note);
  n.random_starts_drawn = true;
  return best;
}

// Levenberg-Marquardt's options for the nominal's free parameters.
CalibrationOptions nominal_calibration_options(const ModelFile& model, const std::vector<int>& free) {
  CalibrationOptions copt;
  copt.scale = scales_for(model, free, {});
  return copt;
}

// The calibrated values written into d.nominal, simulated on both records with their fits.
void store_nominal(const Context& c, NominalFit& n, Diagnosis& d) {
  d.nominal = c.model;
  store_values(d.nominal, n.calibration.parameters);
  n.simulation = c.exact.simulate(n.calibration.parameters);
  d.fit_nominal_estimation = fits(c.exact.measured(), n.simulation.outputs);
  if (c.validation) {
    n.validation_outputs = c.exact_validation->simulate(n.calibration.parameters).outputs;
    d.fit_nominal_validation = fits(c.exact_validation->measured(), n.validation_outputs);
  }
  n.cost = cost_of(d.fit_nominal_estimation);
  const bool was_far = d.nominal_far;
  d.nominal_far = far_from(d.fit_nominal_estimation);
  if (d.nominal_far && !was_far) {
    std::ostringstream note;
    note << " the nominal model cannot be brought near the data (best fit below " << far_fit << " % on "
         << (d.fit_nominal_estimation.size() > 1 ? "an output" : "the output") << ")";
    d.nominal_note += note.str();
  }
}

// The first starts: the file's values; the equation-error least squares; the calibration on the
// first tenth of the record (continued on all of it by calibrate_from).
std::vector<Start> first_starts(const Context& c, const std::vector<int>& free, const Eigen::VectorXd& p0,
                                const CalibrationOptions& copt) {
  std::vector<Start> starts{{"file values", p0}};
  if (free.empty()) return starts;
  const Eigen::VectorXd ee = equation_error_start(c.model, c.estimation, p0);
  if (ee.size()) starts.emplace_back("equation-error fit", ee);
  const Eigen::Index N = c.exact.measured().rows();
  const int rows = static_cast<int>(std::max<Eigen::Index>(std::min<Eigen::Index>(N, 200), N / 10));
  if (rows < N) {
    try {
      Simulator head(c.model, head_of(c.estimation, rows), {c.options.screening_substeps});
      const CalibrationResult h = calibrate(head, p0, free, copt);
      if (h.ok) starts.emplace_back("first tenth of the record", h.parameters);
    } catch (const std::exception&) {
    }
  }
  return starts;
}

// When every first start stays far from the data: the random starts, taken only when they reach
// the data on both records. A random start that fits better but stays far is no evidence of a
// stall (physics may be missing), and it lies farther from the engineer's values. Random plant
// 5 008 447, an undamped nominal of a damped plant: a random start fit 24.7 % against 10.4 %, the
// stiffness 2x the truth's, and the search from there named three wrong effects where the first
// starts' optimum led to the right two. 5 008 381, a Bouc-Wen law missing: 52.0 % on estimation
// with a negative damping, 7.5 % on validation.
void escape_far_calibration(const Context& c, NominalFit& n, const CalibrationOptions& copt, double& worst_cost,
                            std::ostringstream& note) {
  c.say("the nominal calibration stays far from the data (best fit below " + fixed1(far_fit) + " % on an output): " +
        std::to_string(random_start_count) + " more starts");
  const CalibrationResult escaped = calibrate_random_starts(c, n, copt, "far from the data", worst_cost, note);
  const auto near = [](const CalibrationResult& r) { return r.ok && !far_from(r.fit); };
  const bool reaches = near(escaped) && (!c.validation || near(evaluate(*c.exact_validation, escaped.parameters)));
  if (escaped.ok && (!n.calibration.ok || reaches)) n.calibration = escaped;
  else if (n.calibration.ok) note << " none reaches the data on both records: the first starts' best is kept;";
}

// The starts' best continued at the final substeps; the file's values when no start converged
// (NumericalError when those blow up too). `several_starts`: more than one start was calibrated.
void finish_calibration(const Context& c, NominalFit& n, bool several_starts, double worst_cost, const CalibrationOptions& copt,
                        std::ostringstream& note) {
  const double best_cost = n.calibration.ok ? n.calibration.cost : 1e300;
  const bool calibrated = n.calibration.ok;
  if (!calibrated && !n.file_values.ok)
    throw NumericalError(c.model.source + ": the nominal model cannot be simulated over the record from any start (" + note.str() + ")");
  if (!calibrated) {
    n.calibration = evaluate(c.exact, values_of(c.model));
    if (!n.free.empty()) note << " the nominal calibration did not converge from any start: the file's values are used;";
  }
  if (several_starts && worst_cost > 1.5 * best_cost) note << " the output-error cost has several minima; the best is used;";
  if (calibrated && !n.free.empty()) n.calibration = continue_at_final_substeps(c, n.calibration, copt, note);
}

}  // namespace

NominalFit calibrate_nominal(const Context& c, Diagnosis& d) {
  c.say("simulating the nominal model");
  const Eigen::VectorXd p0 = values_of(c.model);
  NominalFit n;
  n.file_values = fits_at_file_values(c, p0, d);
  if (!n.file_values.ok) c.say(d.fit_start_note + "; calibrating from the other starts");
  n.free = c.fast.free_parameters();
  for (int i : n.free) d.free_nominal.push_back(c.model.parameters[static_cast<std::size_t>(i)].name);
  c.say("calibrating the nominal model's free parameters from several starts (" + std::to_string(c.options.screening_substeps) +
        " RK4 substeps while screening, " + std::to_string(c.options.final_substeps) + " for reported fits)");
  const CalibrationOptions copt = nominal_calibration_options(c.model, n.free);
  const std::vector<Start> starts = first_starts(c, n.free, p0, copt);
  std::ostringstream note;
  if (!d.fit_start_note.empty()) note << d.fit_start_note << "; ";
  note << "calibrated from " << starts.size() << (starts.size() == 1 ? " start" : " starts") << ":";
  double worst_cost = 0;
  calibrate_starts(c, starts, n.file_values, n.free, copt, n.calibration, worst_cost, note);
  if (!n.free.empty() && (!n.calibration.ok || far_from(n.calibration.fit))) escape_far_calibration(c, n, copt, worst_cost, note);
  finish_calibration(c, n, starts.size() > 1 || n.random_starts_drawn, worst_cost, copt, note);
  d.nominal_note = note.str();
  store_nominal(c, n, d);
  return n;
}

bool recalibrate_stalled_nominal(const Context& c, NominalFit& n, Diagnosis& d) {
  if (n.free.empty() || n.random_starts_drawn || !n.calibration.ok) return false;
  c.say("the calibrated nominal is not within the noise: " + std::to_string(random_start_count) +
        " more starts, in case its calibration stalled");
  std::ostringstream note;
  double worst_cost = 0;
  const CalibrationOptions copt = nominal_calibration_options(c.model, n.free);
  CalibrationResult best = calibrate_random_starts(c, n, copt, "not within the noise", worst_cost, note);
  if (best.ok) best = continue_at_final_substeps(c, best, copt, note);
  // Taken as an effect would be (the acceptance rules' shares): an optimum that removes that much
  // of the misfit on both records is a better nominal, not noise in the optimiser.
  const auto removes = [](double before, double after, double share) { return after <= (1 - share) * before; };
  bool taken = best.ok && removes(n.calibration.cost, best.cost, c.options.min_cost_reduction);
  if (taken && c.validation) {
    const CalibrationResult v = evaluate(*c.exact_validation, best.parameters);
    taken = v.ok && removes(cost_of(d.fit_nominal_validation), v.cost, c.options.min_validation_reduction);
  }
  note << (taken ? " their best is taken (it removes as much of the misfit as an effect must);"
                 : " none fits markedly better on both records: the first starts' best is kept;");
  d.nominal_note += note.str();
  if (!taken) return false;
  n.calibration = best;
  store_nominal(c, n, d);
  return true;
}

}  // namespace sets::diagnosis_stage
