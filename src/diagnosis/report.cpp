// Stage 5 of the diagnosis: the JSON (stable keys) and the text report.

#include <nlohmann/json.hpp>

#include <cmath>

#include "diagnosis/stages.hpp"

namespace sets {

using diagnosis_stage::fixed1;
using diagnosis_stage::fmt;

namespace {
using J = nlohmann::ordered_json;

J num(double x) { return std::isfinite(x) ? J(x) : J(nullptr); }
J fit_obj(const std::vector<std::string>& outs, const std::vector<double>& f) {
  J o = J::object();
  for (std::size_t i = 0; i < f.size() && i < outs.size(); ++i) o[outs[i]] = num(f[i]);
  return o;
}

J varying_json(const VaryingParameter& v) {
  J when = J::array();
  for (const auto& w : v.when) when.push_back({w.first, w.second});
  J traj = J::array();
  for (const auto& sv : v.trajectory) traj.push_back({{"start", sv.start}, {"end", sv.end}, {"value", sv.value}});
  J jumps = J::array();
  for (const auto& jp : v.jumps) jumps.push_back({{"time", jp.first}, {"size", jp.second}});
  return {{"name", v.name}, {"value", v.value}, {"range", {v.lo, v.hi}}, {"explained", v.explained}, {"when", when},
          {"explained_squared", v.explained_squared}, {"bound", v.bound}, {"method", v.method}, {"jumps", jumps}, {"trajectory", traj}};
}

// Where the calibrated nominal fails: windows, regions, varying parameters, bands, error bound.
J mismatch_json(const Diagnosis& d) {
  J windows = J::array();
  for (const auto& w : d.windows)
    windows.push_back({{"output", w.output}, {"start", w.start}, {"end", w.end}, {"rms", w.rms}, {"falsified", w.falsified}});
  J regions = J::array();
  for (const auto& r : d.regions)
    regions.push_back({{"description", r.description}, {"variable", r.variable}, {"residual_share", r.residual_share},
                       {"sample_share", r.sample_share}});
  J varying = J::array();
  for (const auto& v : d.varying) varying.push_back(varying_json(v));
  J bands = J::array();
  for (const auto& b : d.bands) bands.push_back({{"output", b.output}, {"band_hz", {b.lo_hz, b.hi_hz}}, {"peak_hz", b.peak_hz}});
  J bounds = J::object();
  for (std::size_t i = 0; i < d.error_bound.size(); ++i) bounds[d.outputs[i]] = d.error_bound[i];
  return {{"windows", windows}, {"regions", regions}, {"varying_parameters", varying}, {"frequency_band", bands},
          {"error_bound", bounds}};
}

J parameter_json(const Diagnosis& d, const EffectParameter& p) {
  J oe_delta = J::object();
  for (std::size_t k = 0; k < p.oe_delta.size() && k < d.outputs.size(); ++k) oe_delta[d.outputs[k]] = num(p.oe_delta[k]);
  const bool bounded = p.has_bounded_error_interval();
  return {{"estimate", num(p.estimate)}, {"interval", {num(p.lo), num(p.hi)}},
          {"interval_kind", bounded ? "bounded-error interval: holds when |equation error| <= error_bound.equation_error "
                                      "(an assumption); met with the declared min/max"
                                    : "no bounded-error set could be built: only the declared min/max; see the estimates"},
          {"interval_equation_error", p.has_ee ? J{num(p.ee_lo), num(p.ee_hi)} : J(nullptr)},
          {"interval_equation_error_certified", p.has_ee ? J(p.ee_certified) : J(nullptr)},
          {"estimate_interval_output_error_linearised", {num(p.estimate_oe_lo), num(p.estimate_oe_hi)}},
          {"estimate_statistical_95", {num(p.estimate_stat_lo), num(p.estimate_stat_hi)}},
          {"role", p.role},
          {"error_bound", {{"output_error", oe_delta}, {"equation_error", p.has_ee ? num(p.ee_delta) : J(nullptr)}}}};
}

J effect_json(const Diagnosis& d, const DiagnosedEffect& e) {
  J ps = J::object();
  for (const auto& p : e.parameters) ps[p.name] = parameter_json(d, p);
  J rules = J::array();
  for (const auto& r : e.rules)
    rules.push_back({{"name", r.name}, {"value", num(r.value)}, {"threshold", r.threshold}, {"applies", r.applies}, {"passed", r.passed},
                     {"rule", r.description}});
  J alike = J::array();
  for (const auto& a : e.equally_good)
    alike.push_back({{"effects", a.effects}, {"equations", a.equations}, {"misfit_share", num(a.misfit)},
                     {"misfit_share_validation", num(a.misfit_validation)}, {"text", diagnosis_stage::equally_good_text(a)}});
  return {{"name", e.name}, {"equation", e.equation}, {"term", e.term}, {"parameters", ps}, {"evidence", e.evidence},
          {"placement", e.placement}, {"delay_samples", e.delay_samples}, {"rules", rules}, {"equally_good", alike}};
}

J noise_levels_json(const std::vector<OutputNoise>& levels) {
  J noise = J::object();
  for (const auto& n : levels)
    noise[n.output] = {{"sigma", num(n.estimate.sigma)}, {"method", noise_method_name(n.estimate.method)},
                       {"record", n.record}, {"model", n.model}, {"reason", n.estimate.reason},
                       {"quantisation_step", n.estimate.quantisation_step > 0 ? num(n.estimate.quantisation_step) : J(nullptr)},
                       {"ar_pole", n.estimate.ar_pole != 0 ? num(n.estimate.ar_pole) : J(nullptr)}};
  return noise;
}

J data_hypothesis_json(const Diagnosis& d) {
  const DataHypothesis& h = d.data_hypothesis;
  return {{"tested", h.tested}, {"found", h.found}, {"finding", h.finding}, {"note", h.note},
          {"inputs", h.inputs}, {"declared", h.declared}, {"alternative", h.alternative},
          {"ratio", h.tested ? num(h.ratio) : J(nullptr)},
          {"fit_declared", {{"estimation", fit_obj(d.outputs, h.fit_declared_estimation)},
                            {"validation", fit_obj(d.outputs, h.fit_declared_validation)}}},
          {"fit_alternative", {{"estimation", fit_obj(d.outputs, h.fit_alternative_estimation)},
                               {"validation", fit_obj(d.outputs, h.fit_alternative_validation)}}}};
}

J residual_tests_json(const Diagnosis& d, const ResidualTests& t) {
  J b = J::object();
  for (std::size_t i = 0; i < t.bound.size() && i < d.outputs.size(); ++i) b[d.outputs[i]] = num(t.bound[i]);
  J w = J::object();  // the AR(1) pole the whiteness test whitened each output's residual by
  for (std::size_t i = 0; i < t.whitened_by.size() && i < d.outputs.size(); ++i) w[d.outputs[i]] = num(t.whitened_by[i]);
  return {{"falsified", t.falsified}, {"white", t.white}, {"whitened_by", w}, {"worst_autocorrelation_z", num(t.worst_autocorrelation_z)},
          {"white_threshold", num(t.white_threshold)}, {"bursty", t.bursty}, {"burst_ratio", num(t.worst_burst_ratio)}, {"independent", t.independent},
          {"follows_model_signals", t.follows_model_signals()}, {"within_noise", t.within_noise()},
          {"worst_z", num(t.worst_z)}, {"z_threshold", num(t.z_threshold)}, {"worst_signal", t.worst_signal}, {"bound", b}};
}
}  // namespace

std::string diagnosis_json(const Diagnosis& d, const std::string& augmented_path) {
  J j;
  J params = J::object();
  for (const auto& n : d.free_nominal) params[n] = num(d.nominal.parameter(n)->value);
  j["nominal"]["parameters"] = params;
  j["nominal"]["fit"]["estimation"] = fit_obj(d.outputs, d.fit_nominal_estimation);
  j["nominal"]["fit"]["validation"] = fit_obj(d.outputs, d.fit_nominal_validation);
  j["nominal"]["fit_before_calibration"]["estimation"] = fit_obj(d.outputs, d.fit_start_estimation);
  j["nominal"]["fit_before_calibration"]["validation"] = fit_obj(d.outputs, d.fit_start_validation);
  j["nominal"]["fit_before_calibration_note"] = d.fit_start_note;  // why a fit above is null
  j["mismatch"] = mismatch_json(d);
  J effects = J::array();
  for (const auto& e : d.effects) effects.push_back(effect_json(d, e));
  j["effects"] = effects;
  j["noise_level"] = noise_levels_json(d.noise);              // the calibrated nominal's: the rules' floor
  j["noise_level_final"] = noise_levels_json(d.noise_final);  // the final model's: reported
  j["data_hypothesis"] = data_hypothesis_json(d);
  j["augmented"]["model"] = augmented_path.empty() ? J(nullptr) : J(augmented_path);
  j["augmented"]["fit"]["estimation"] = fit_obj(d.outputs, d.fit_augmented_estimation);
  j["augmented"]["fit"]["validation"] = fit_obj(d.outputs, d.fit_augmented_validation);
  j["verdict"] = d.verdict;
  j["answer"] = d.nothing_missing ? "nothing_missing" : d.unexplained ? "unexplained" : "missing";
  j["unexplained"] = d.unexplained;
  j["where"] = d.where;
  j["nominal"]["calibration_note"] = d.nominal_note;
  j["nominal"]["far_from_data"] = d.nominal_far;
  J sig = J::object();
  for (std::size_t i = 0; i < d.noise_sigma.size() && i < d.outputs.size(); ++i) sig[d.outputs[i]] = num(d.noise_sigma[i]);
  j["noise"] = {{"sigma", sig}, {"method", d.noise_note}};
  j["residual_tests"] = {{"nominal", residual_tests_json(d, d.nominal_tests)}, {"final", residual_tests_json(d, d.final_tests)}};
  j["hypotheses"] = {{"screened", d.hypotheses_screened}, {"refined", d.hypotheses_refined}};
  j["nothing_missing"] = d.nothing_missing;
  j["bound_note"] = d.bound_note;
  j["seconds"] = d.seconds;
  return j.dump(2) + "\n";
}

namespace {

void fit_line(std::ostream& o, const Diagnosis& d, const char* label, const std::vector<double>& f) {
  o << "  " << std::left << std::setw(34) << label;
  for (std::size_t i = 0; i < f.size(); ++i) o << "  " << d.outputs[i] << " " << (std::isnan(f[i]) ? "not available" : fixed1(f[i]) + " %");
  o << "\n";
}

// Windows, regions, frequency bands and the parameter that would have to vary most.
void mismatch_lines(std::ostream& o, const Diagnosis& d) {
  int shown = 0;
  for (const auto& w : d.windows) {
    if (shown++ == 4) break;
    o << "  " << w.output << ": t = " << fmt(w.start, 4) << " .. " << fmt(w.end, 4) << " s, residual RMS " << fmt(w.rms)
      << (w.falsified ? " (falsified: no parameter value fits inside the bound)" : "") << "\n";
  }
  if (d.windows.size() > 4) o << "  ... " << d.windows.size() << " windows in all\n";
  for (std::size_t i = 0; i < std::min<std::size_t>(3, d.regions.size()); ++i)
    o << "  residual concentrated " << d.regions[i].description << ": " << fixed1(100 * d.regions[i].residual_share)
      << " % of it in " << fixed1(100 * d.regions[i].sample_share) << " % of the samples\n";
  for (const auto& b : d.bands)
    o << "  frequency band of the " << b.output << " residual: " << fmt(b.lo_hz) << " .. " << fmt(b.hi_hz) << " Hz (peak "
      << fmt(b.peak_hz) << " Hz)\n";
  if (d.varying.empty()) return;
  const auto& v = d.varying.front();
  o << "  parameter that would have to vary most: " << v.name << " between " << fmt(v.lo, 4) << " and " << fmt(v.hi, 4)
    << " (removes " << fixed1(100 * v.explained) << " % of the residual's window-norm bound";
  if (!v.when.empty()) {
    o << "; it jumps in t = ";
    for (std::size_t w = 0; w < v.when.size(); ++w) o << (w ? ", " : "") << fmt(v.when[w].first, 4) << " .. " << fmt(v.when[w].second, 4);
    o << " s";
  }
  o << ")\n";
}

void noise_lines(std::ostream& o, const std::vector<OutputNoise>& levels) {
  for (const auto& n : levels)
    o << "  " << n.output << ": sigma = " << fmt(n.estimate.sigma) << " (" << noise_method_name(n.estimate.method) << ", " << n.record
      << " record: " << n.estimate.reason << ")\n";
}

// One parameter of a named effect: its estimate, its bounded-error interval and the estimates.
void parameter_line(std::ostream& o, const Diagnosis& d, const EffectParameter& p) {
  o << "     " << p.name << " = " << fmt(p.estimate, 5);
  if (p.has_bounded_error_interval())
    o << ", bounded-error interval [" << fmt(p.lo, 5) << ", " << fmt(p.hi, 5) << "] under |equation error| <= " << fmt(p.ee_delta, 3);
  else
    o << ", no bounded-error interval (" << (p.has_ee ? "equation-error PUI not certified" : "no equation-error PUI") << ")";
  o << "; estimates: output error linearised at the estimate [" << fmt(p.estimate_oe_lo, 5) << ", " << fmt(p.estimate_oe_hi, 5)
    << "] with delta =";
  for (std::size_t k = 0; k < p.oe_delta.size(); ++k) o << (k ? "," : "") << " " << fmt(p.oe_delta[k], 3) << " (" << d.outputs[k] << ")";
  if (p.has_ee && !p.ee_certified) o << "; equation error (not certified) [" << fmt(p.ee_lo, 5) << ", " << fmt(p.ee_hi, 5) << "]";
  o << "; statistical 95 % [" << fmt(p.estimate_stat_lo, 5) << ", " << fmt(p.estimate_stat_hi, 5) << "]\n";
}

// The k-th named effect (from 1): its term, parameters, rules, evidence and look-alikes.
void effect_lines(std::ostream& o, const Diagnosis& d, const DiagnosedEffect& e, std::size_t k) {
  o << "  " << k << ". " << e.name << " in " << e.equation << ": " << e.term << "\n";
  for (const auto& p : e.parameters) parameter_line(o, d, p);
  if (e.delay_samples > 0) o << "     delay: " << e.delay_samples << " samples\n";
  o << "     rules:";
  for (const auto& r : e.rules)
    if (r.applies) o << " " << r.name << " " << fmt(r.value, 3) << (r.passed ? " >= " : " < ") << fmt(r.threshold, 3) << ";";
  o << "\n";
  o << "     evidence: " << e.evidence << "\n";
  for (std::size_t i = 0; i < e.equally_good.size(); ++i)
    o << (i ? "; " : "     equally good on these data: ") << diagnosis_stage::equally_good_text(e.equally_good[i])
      << (i + 1 == e.equally_good.size() ? " - the data cannot tell them apart\n" : "");
}

}  // namespace

std::string diagnosis_text(const Diagnosis& d) {
  std::ostringstream o;
  o << "Fit per output (100 (1 - |y - yhat| / |y - mean y|)):\n";
  fit_line(o, d, "nominal, file values, estimation", d.fit_start_estimation);
  if (!d.fit_start_note.empty()) o << "  (" << d.fit_start_note << ")\n";
  fit_line(o, d, "nominal, calibrated, estimation", d.fit_nominal_estimation);
  if (d.has_validation) fit_line(o, d, "nominal, calibrated, validation", d.fit_nominal_validation);
  o << "Calibrated nominal parameters:";
  for (const auto& n : d.free_nominal) o << " " << n << " = " << fmt(d.nominal.parameter(n)->value, 5);
  o << "\nWhere the nominal model fails:\n";
  mismatch_lines(o, d);
  o << "Noise level (estimated, one value per output channel), from the calibrated nominal's residual (the rules' floor):\n";
  noise_lines(o, d.noise);
  if (!d.effects.empty()) {
    o << "Noise level from the augmented model's residual (what the final model leaves as noise):\n";
    noise_lines(o, d.noise_final);
  }
  if (d.data_hypothesis.found) o << "About the data (not physics): " << d.data_hypothesis.finding << ".\n";
  o << "Nominal calibration: " << d.nominal_note << "\n";
  o << "Verdict: " << d.verdict << "\n";
  for (std::size_t k = 0; k < d.effects.size(); ++k) effect_lines(o, d, d.effects[k], k + 1);
  if (!d.effects.empty()) {
    fit_line(o, d, "augmented, estimation", d.fit_augmented_estimation);
    if (d.has_validation) fit_line(o, d, "augmented, validation", d.fit_augmented_validation);
  }
  o << "(" << fixed1(d.seconds) << " s)\n";
  return o.str();
}

}  // namespace sets
