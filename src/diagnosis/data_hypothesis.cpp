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

}  // namespace

void test_data_hypothesis(const Context& c, const NominalFit& nominal, const NoiseFloor& noise, Diagnosis& d) {
  DataHypothesis& h = d.data_hypothesis;
  const std::vector<std::string> moving = inputs_between_samples(c.model);
  if (moving.empty()) {
    h.note = "no input is read between samples (only by sampled signals, or no inputs): the intersample behaviour cannot matter";
    return;
  }
  // Held or linear inputs that are band-limited are tried band-limited; if there are none,
  // band-limited ones are tried held.
  std::vector<std::string> to_bl, to_zoh;
  std::string skipped;
  for (const auto& in : moving) {
    const Intersample mode = declared_intersample(c.model, in);
    if (mode == Intersample::bl) {
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
      skipped += (skipped.empty() ? "" : "; ") + in + " has " + fmt(100 * share, 2) + " % of its power above 0.375 fs";
  }
  const bool try_bl = !to_bl.empty();
  h.inputs = try_bl ? to_bl : to_zoh;
  if (h.inputs.empty()) {
    h.note = "not tested: no input is band-limited (" + skipped + ")";
    return;
  }
  h.declared = intersample_name(declared_intersample(c.model, h.inputs.front()));
  h.alternative = try_bl ? "bl" : "zoh";
  std::string names;
  for (const auto& in : h.inputs) names += (names.empty() ? "" : ", ") + in;
  c.say("data hypothesis: calibrating the nominal with " + names + " " + behaviour(h.alternative));
  const ModelFile alt = with_intersample(c.model, h.inputs, try_bl ? Intersample::bl : Intersample::zoh);
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
           fmt(min_ratio) + " and a difference above the noise's own misfit)" + (skipped.empty() ? "" : "; " + skipped);
  if (!h.found) return;
  h.finding = std::string(h.inputs.size() > 1 ? "the inputs " : "the input ") + names + (h.inputs.size() > 1 ? " behave as " : " behaves as ") +
              behaviour(h.alternative) + ", not " + behaviour(h.declared) + ": fit " +
              fits_text(h.fit_declared_estimation, h.fit_alternative_estimation) + " on estimation";
  if (!h.fit_alternative_validation.empty())
    h.finding += " (" + fits_text(h.fit_declared_validation, h.fit_alternative_validation) + " on validation)";
  h.finding += " with the nominal structure; declare \"intersample\": {\"" + h.inputs.front() + "\": \"" + h.alternative +
               "\"} in the model file or run with --intersample " + h.alternative;
}

}  // namespace sets::diagnosis_stage
