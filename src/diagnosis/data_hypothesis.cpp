// A finding about the data, not the physics: does another intersample behaviour of the inputs
// explain the recording markedly better than the declared one? The same nominal structure is
// calibrated under both; R = V_declared / V_alternative (squared simulation errors, each output
// divided by its own spread, so units and Ts cancel). Found when R >= 2 (at least half of the
// declared model's squared error is due to the timing assumption) and the difference exceeds what
// the noise alone gives. Reported apart from missing physics, never as a catalogue effect.
// See docs/methods/diagnosis.md ("The data hypothesis").

#include <algorithm>

#include "diagnosis/stages.hpp"

namespace sets::diagnosis_stage {

namespace {

constexpr double min_ratio = 2.0;
// Above 0.375 fs an input with more than this share of its power is not band-limited well inside
// Nyquist: no interpolation is "the" signal, and the question is one of modelling, not data.
constexpr double max_high_band_share = 1e-3;

std::string fits_text(const std::vector<double>& a, const std::vector<double>& b) {
  std::string s;
  for (std::size_t j = 0; j < a.size() && j < b.size(); ++j) s += (j ? ", " : "") + fixed1(a[j]) + " -> " + fixed1(b[j]) + " %";
  return s;
}

const char* behaviour(const std::string& mode) {
  return mode == "bl" ? "band-limited" : mode == "foh" ? "linear between samples" : "held";
}

// The inputs to try under another behaviour: held or linear inputs that are band-limited are tried
// band-limited; if there are none, band-limited ones are tried held. `skipped` says which inputs
// are not band-limited.
struct InputsToTry {
  std::vector<std::string> inputs;
  bool band_limited = false;  // the alternative is bl (else zoh)
  std::string skipped;
};

InputsToTry inputs_to_try(const Context& c, const std::vector<std::string>& moving) {
  std::vector<std::string> to_bl, to_zoh;
  InputsToTry t;
  for (const auto& in : moving) {
    if (declared_intersample(c.model, in) == Intersample::bl) {
      to_zoh.push_back(in);
      continue;
    }
    std::string column;
    for (const auto& [sym, col] : c.model.inputs)
      if (sym == in) column = col;
    const double share = power_share_above(c.estimation.column(column));
    if (share < max_high_band_share)
      to_bl.push_back(in);
    else
      t.skipped += (t.skipped.empty() ? "" : "; ") + in + " has " + fmt(100 * share, 2) + " % of its power above 0.375 fs";
  }
  t.band_limited = !to_bl.empty();
  t.inputs = t.band_limited ? to_bl : to_zoh;
  return t;
}

// "the input u behaves as band-limited, not held: fit 71.4 -> 84.4 % on estimation (...) ...".
std::string finding_of(const DataHypothesis& h, const std::string& names) {
  std::string f = std::string(h.inputs.size() > 1 ? "the inputs " : "the input ") + names +
                  (h.inputs.size() > 1 ? " behave as " : " behaves as ") + behaviour(h.alternative) + ", not " +
                  behaviour(h.declared) + ": fit " + fits_text(h.fit_declared_estimation, h.fit_alternative_estimation) +
                  " on estimation";
  if (!h.fit_alternative_validation.empty())
    f += " (" + fits_text(h.fit_declared_validation, h.fit_alternative_validation) + " on validation)";
  return f + " with the nominal structure; declare \"intersample\": {\"" + h.inputs.front() + "\": \"" + h.alternative +
         "\"} in the model file or run with --intersample " + h.alternative;
}

}  // namespace

void test_data_hypothesis(const Context& c, const NominalFit& nominal, const NoiseFloor& noise, Diagnosis& d) {
  DataHypothesis& h = d.data_hypothesis;
  const std::vector<std::string> moving = inputs_between_samples(c.model);
  if (moving.empty()) {
    h.note = "no input is read between samples (only by sampled signals, or no inputs): the intersample behaviour cannot matter";
    return;
  }
  const InputsToTry to_try = inputs_to_try(c, moving);
  h.inputs = to_try.inputs;
  if (h.inputs.empty()) {
    h.note = "not tested: no input is band-limited (" + to_try.skipped + ")";
    return;
  }
  h.declared = intersample_name(declared_intersample(c.model, h.inputs.front()));
  h.alternative = to_try.band_limited ? "bl" : "zoh";
  std::string names;
  for (const auto& in : h.inputs) names += (names.empty() ? "" : ", ") + in;
  c.say("data hypothesis: calibrating the nominal with " + names + " " + behaviour(h.alternative));
  const ModelFile alt = with_intersample(c.model, h.inputs, to_try.band_limited ? Intersample::bl : Intersample::zoh);
  Simulator fast(alt, c.estimation, {c.options.screening_substeps});
  Simulator exact(alt, c.estimation, {c.options.final_substeps});
  CalibrationOptions copt;
  copt.scale = scales_for(c.model, nominal.free, {});
  // From the declared optimum: the timing assumption moves the parameters only a little.
  const CalibrationResult r = calibrate(fast, nominal.calibration.parameters, nominal.free, copt);
  const CalibrationResult rx = evaluate(exact, r.parameters);
  if (!r.ok || !rx.ok) {
    h.note = "not tested: the nominal model blows up with " + names + " " + behaviour(h.alternative);
    return;
  }
  h.tested = true;
  h.fit_declared_estimation = d.fit_nominal_estimation;
  h.fit_alternative_estimation = rx.fit;
  if (c.validation) {
    h.fit_declared_validation = d.fit_nominal_validation;
    Simulator val(alt, *c.validation, {c.options.final_substeps});
    const CalibrationResult rv = evaluate(val, r.parameters);
    if (rv.ok) h.fit_alternative_validation = rv.fit;
  }
  const double v_declared = nominal.cost, v_alt = rx.cost;
  h.ratio = v_alt > 0 ? v_declared / v_alt : (v_declared > 0 ? 1e300 : 1.0);
  h.found = h.ratio >= min_ratio && v_declared - v_alt > noise.cost;
  h.note = "nominal structure calibrated with " + names + " " + behaviour(h.declared) + " (declared) and " +
           behaviour(h.alternative) + ": squared misfit ratio R = " + fmt(h.ratio, 3) + " (a finding needs R >= " +
           fmt(min_ratio) + " and a difference above the noise's own misfit)" + (to_try.skipped.empty() ? "" : "; " + to_try.skipped);
  if (h.found) h.finding = finding_of(h, names);
}

}  // namespace sets::diagnosis_stage
