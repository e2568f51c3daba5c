#include "sets/examples/random_plants.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "sets/core/error.hpp"
#include "sets/data/simulation.hpp"
#include "sets/diagnosis/calibration.hpp"

#include "random_plant_builder.hpp"

namespace sets {

namespace {

using namespace random_plant_detail;

// ------------------------------------------------------------------ excitation
struct Excitation {
  std::string kind;
  bool rich = true;
};

// A signal of n samples with levels in [lo, hi]; `period` is the plant's dominant time scale.
std::vector<double> excitation(Rng& rng, const std::string& kind, int n, double Ts, double lo, double hi, double period) {
  std::vector<double> u(static_cast<std::size_t>(n));
  const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  if (kind == "steps" || kind == "few_steps" || kind == "prbs") {
    const double total = n * Ts;
    double hold_lo = 0.5 * period, hold_hi = 4 * period;
    if (kind == "few_steps") hold_lo = total / 7, hold_hi = total / 3;
    if (kind == "prbs") hold_lo = hold_hi = std::max(Ts, 0.3 * period);
    double next = 0, value = rng.uniform(lo, hi);
    bool high = rng.chance(0.5);
    for (int k = 0; k < n; ++k) {
      if (k * Ts >= next) {
        high = !high;
        value = kind == "prbs" ? (high ? hi : lo) : rng.uniform(lo, hi);
        next = k * Ts + (kind == "prbs" ? hold_lo * rng.integer(1, 4) : rng.uniform(hold_lo, hold_hi));
      }
      u[static_cast<std::size_t>(k)] = value;
    }
  } else if (kind == "multisine" || kind == "sine") {
    const int lines = kind == "sine" ? 1 : rng.integer(5, 15);
    const double fmax = std::min(0.4 / Ts, 3.0 / period), fmin = 1.0 / (n * Ts);
    std::vector<double> f, phase;
    for (int i = 0; i < lines; ++i) {
      f.push_back(kind == "sine" ? rng.uniform(0.3, 1.5) / period : rng.log_uniform(std::max(fmin * 3, fmax / 100), fmax));
      phase.push_back(rng.uniform(0, 2 * kPi));
    }
    double peak = 0;
    for (int k = 0; k < n; ++k) {
      double s = 0;
      for (int i = 0; i < lines; ++i) s += std::sin(2 * kPi * f[static_cast<std::size_t>(i)] * k * Ts + phase[static_cast<std::size_t>(i)]);
      u[static_cast<std::size_t>(k)] = s;
      peak = std::max(peak, std::abs(s));
    }
    for (auto& x : u) x = mid + half * x / std::max(peak, 1e-12);
  } else {  // filtered Gaussian noise, first order with the plant's time scale
    const double a = std::exp(-Ts / std::max(0.3 * period, Ts));
    double x = 0, peak = 0;
    for (int k = 0; k < n; ++k) {
      x = a * x + std::sqrt(1 - a * a) * rng.normal();
      u[static_cast<std::size_t>(k)] = x;
      peak = std::max(peak, std::abs(x));
    }
    for (auto& v : u) v = mid + half * std::clamp(v / std::max(0.8 * peak, 1e-12), -1.0, 1.0);
  }
  return u;
}

// ------------------------------------------------------------------ model files
std::string derivative_text(const Eq& e, const std::vector<std::string>& removed) {
  std::string body = e.body;
  for (const auto& term : removed) {  // " - c*v" left out of the nominal
    const auto at = body.find(" - " + term);
    if (at != std::string::npos) body.erase(at, term.size() + 3);
  }
  for (const auto& x : e.extra) body += " - " + x;
  std::string d = e.inertia.empty() ? body : "(" + body + ")/" + e.inertia;
  if (!e.wrap.empty()) d = replace_word(e.wrap, "@f", "(" + d + ")");
  return d;
}

ModelFile model_of(const Build& b, const std::vector<Eq>& eqs, const NamedTexts& sampled, const NamedTexts& outputs,
                   const std::vector<ModelState>& states, const std::vector<std::string>& removed,
                   const std::vector<ModelParameter>& params, const std::string& time_col) {
  ModelFile m;
  m.time_column = time_col;
  m.inputs = b.inputs;
  m.parameters = params;
  m.states = states;
  m.sampled = sampled;
  for (const auto& e : eqs) m.derivatives.emplace_back(e.state, derivative_text(e, removed));
  m.outputs = outputs;
  return m;
}

// ------------------------------------------------------------------ noise
std::vector<double> add_noise(Rng& r, const Eigen::VectorXd& y, const std::string& kind, double sigma) {
  std::vector<double> out(static_cast<std::size_t>(y.size()));
  const double a = r.uniform(0.6, 0.95);
  double e = 0;
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    double v = y[k];
    if (kind == "white") v += sigma * r.normal();
    if (kind == "coloured") {
      e = a * e + std::sqrt(1 - a * a) * sigma * r.normal();  // AR(1) with marginal std sigma
      v += e;
    }
    if (kind == "quantised") {
      const double q = sigma * std::sqrt(12.0);
      v = q * std::round((v + 0.1 * sigma * r.normal()) / q);
    }
    out[static_cast<std::size_t>(k)] = v;
  }
  return out;
}

// ------------------------------------------------------------------ the stages of random_plant
// The estimation and validation records: time, excited inputs, outputs still zero.
struct Records {
  std::string time_col, excitation_kind;
  double per_time_scale = 0;  // samples per dominant time scale
  int n = 0;
  Recording est, val;
};

Records draw_records(Rng& r, Names& names, Build& b, const RandomPlantOptions& options) {
  Records rec;
  // Sampling: from about 6 to several hundred samples per dominant time scale.
  rec.per_time_scale = r.log_uniform(6, 300);
  b.Ts = b.period / rec.per_time_scale;
  rec.n = options.samples > 0 ? options.samples : r.integer(2500, 5000);
  rec.time_col = names({"t", "time", "tt"});
  rec.excitation_kind = r.pick(std::vector<std::string>{"steps", "steps", "prbs", "multisine", "noise", "few_steps", "sine"});
  std::vector<double> tcol(static_cast<std::size_t>(rec.n));
  for (int k = 0; k < rec.n; ++k) tcol[static_cast<std::size_t>(k)] = k * b.Ts;
  for (Recording* one : {&rec.est, &rec.val}) {
    one->add(rec.time_col, tcol);
    for (const auto& [sym, col] : b.inputs)
      one->add(col, excitation(r, rec.excitation_kind, rec.n, b.Ts, b.u_lo, b.u_hi, b.period));
    for (const auto& [sym, col] : b.outputs) one->add(col, std::vector<double>(static_cast<std::size_t>(rec.n), 0.0));
  }
  return rec;
}

// Two effects of one kind (two friction laws, two sensor laws, a square-root outflow beside a
// saturated level of another law) would describe one thing twice.
bool clash(const std::string& a, const std::string& c) {
  static const std::set<std::string> friction = {"coulomb_friction", "stribeck_friction", "quadratic_drag",
                                                 "asymmetric_friction", "viscous_friction"};
  static const std::set<std::string> sensor = {"output_saturation", "hysteresis", "absolute_value_sensor"};
  return a == c || (friction.count(a) && friction.count(c)) || (sensor.count(a) && sensor.count(c)) ||
         ((a == "sqrt_outflow") != (c == "sqrt_outflow") && (a == "state_saturation" || c == "state_saturation"));
}

// How many effects, which; nullopt when the forced effect cannot enter the drawn family (draw again).
std::optional<std::vector<std::string>> draw_effect_names(Rng& r, const Build& b, const RandomPlantOptions& options) {
  int count = options.effects;
  if (count < 0) {
    const double u = r.uniform(0, 1);
    count = u < 0.3 ? 0 : u < 0.7 ? 1 : 2;
  }
  std::vector<std::string> avail = effects_for(b), drawn;
  if (!options.effect.empty()) {
    if (std::find(avail.begin(), avail.end(), options.effect) == avail.end()) {
      if (!options.family.empty()) throw InputError("random plant: " + options.effect + " cannot enter a " + b.family + " plant");
      return std::nullopt;
    }
    drawn.push_back(options.effect);
  }
  while (static_cast<int>(drawn.size()) < count) {
    const std::string e = r.pick(avail);
    bool ok = true;
    for (const auto& d : drawn) ok = ok && !clash(d, e);
    if (ok) drawn.push_back(e);
    else if (avail.size() < 3) break;
  }
  return drawn;
}

// The plant without effects simulated on the estimation input (its scales size the effects).
// A plant that grows without bound is not a plant anyone identifies: the second half of every
// signal must stay within 100 x the first half's RMS.
bool simulates_bounded(const Build& b, const Records& rec, SimulationResult& clean) {
  const ModelFile model = model_of(b, b.eqs, b.sampled, b.outputs, b.states, {}, b.params, rec.time_col);
  try {
    Simulator s(model, rec.est, {10});
    clean = s.simulate(s.parameter_values());
  } catch (const std::exception&) {
    return false;
  }
  bool bounded = clean.values.allFinite();
  for (Eigen::Index v = 0; bounded && v < clean.values.cols(); ++v) {
    const Eigen::Index h = clean.values.rows() / 2;
    const double first = clean.values.col(v).head(h).norm(), second = clean.values.col(v).tail(h).norm();
    bounded = second <= 100 * first + 1e-300;
  }
  return bounded;
}

// Noise per output, drawn before the effects' strengths: every effect must move the outputs by
// several noise levels.
struct Noise {
  std::vector<double> fraction;  // of the output's standard deviation
  std::vector<std::string> kind;
  double max_fraction = 0;
};

Noise draw_noise(Rng& r, std::size_t outputs) {
  Noise noise;
  for (std::size_t j = 0; j < outputs; ++j) {
    noise.fraction.push_back(r.log_uniform(0.002, 0.03));
    noise.kind.push_back(r.pick(std::vector<std::string>{"white", "white", "coloured", "quantised"}));
  }
  noise.max_fraction = *std::max_element(noise.fraction.begin(), noise.fraction.end());
  return noise;
}

bool simulate_outputs(const ModelFile& m, const Recording& rec, Eigen::MatrixXd& y) {
  try {
    Simulator s(m, rec, {10});
    return s.simulate_outputs(s.parameter_values(), y);
  } catch (const std::exception&) {
    return false;
  }
}

using EffectValues = std::vector<std::pair<std::string, double>>;

// The truth with the effects at knobs k, one of them left out (skip) or none (-1).
class Truth {
 public:
  Truth(const Build& b, const std::vector<Effect>& effects, std::string time_col)
      : b_(b), effects_(effects), time_col_(std::move(time_col)) {}

  // level >= 0: effect `skip` replaced by its nested special case instead, its free parameters
  // starting at `level` between the law's ends.
  ModelFile with(const std::vector<double>& knobs, int skip, std::vector<EffectValues>* values, double level = -1) const {
    std::vector<Eq> eqs = b_.eqs;
    NamedTexts sampled = b_.sampled, outputs = b_.outputs;
    std::vector<ModelState> states = b_.states;
    std::vector<ModelParameter> ps = b_.params;
    for (std::size_t i = 0; i < effects_.size(); ++i) {
      EffectValues v;
      if (static_cast<int>(i) != skip) effects_[i].apply(knobs[i], eqs, sampled, outputs, states, ps, v);
      else if (level >= 0) effects_[i].apply_special_case(knobs[i], level, eqs, ps);
      if (values) values->push_back(v);
    }
    // The truth has the damping the nominal leaves out; without the viscous effect it goes too.
    std::vector<std::string> removed;
    if (skip >= 0 && effects_[static_cast<std::size_t>(skip)].name == "viscous_friction") removed = b_.removed;
    return model_of(b_, eqs, sampled, outputs, states, removed, ps, time_col_);
  }

  // Strength of effect i: the RMS output deviation it causes (the others present) over the RMS
  // of the output, largest over the outputs; -1 when a simulation fails.
  double strength(const std::vector<double>& knobs, std::size_t i, const Recording& est) const {
    Eigen::MatrixXd y1, y0;
    if (!simulate_outputs(with(knobs, -1, nullptr), est, y1) || !simulate_outputs(with(knobs, static_cast<int>(i), nullptr), est, y0))
      return -1.0;
    double s = 0;
    for (Eigen::Index j = 0; j < y1.cols(); ++j) {
      const double den = std::sqrt((y0.col(j).array() - y0.col(j).mean()).square().mean());
      s = std::max(s, std::sqrt((y1.col(j) - y0.col(j)).array().square().mean()) / std::max(den, 1e-300));
    }
    return s;
  }

  const std::vector<Effect>& effects() const { return effects_; }

 private:
  const Build& b_;
  const std::vector<Effect>& effects_;
  std::string time_col_;
};

// Each effect's knob set by bisection on log(knob) for a drawn strength; false when an effect
// cannot be made strong enough to see or weak enough to hide.
bool set_strengths(Rng& r, const Truth& truth, const Recording& est, const Noise& noise, std::vector<double>& knobs,
                   std::vector<double>& strengths) {
  const double floor = noise.max_fraction;
  for (std::size_t i = 0; i < truth.effects().size(); ++i) {
    const double target = r.log_uniform(std::max(0.04, 4 * floor), 0.4);
    if (!truth.effects()[i].has_knob) {
      strengths[i] = truth.strength(knobs, i, est);
      // A mirror or a square-root law cannot be made weak.
      if (!(strengths[i] >= std::max(0.03, 3 * floor) && strengths[i] <= 1.5)) return false;
      continue;
    }
    double lo = std::log(1e-4), hi = std::log(20.0);
    for (int it = 0; it < 18; ++it) {
      knobs[i] = std::exp(0.5 * (lo + hi));
      const double s = truth.strength(knobs, i, est);
      if (s < 0 || s > target) hi = std::log(knobs[i]);
      else lo = std::log(knobs[i]);
    }
    knobs[i] = std::exp(lo);
    strengths[i] = truth.strength(knobs, i, est);
    if (!(strengths[i] >= 0.6 * target && strengths[i] >= 3 * floor && strengths[i] <= 0.5)) return false;
  }
  return true;
}

// The estimation record with the truth's noise-free outputs y in place of the measured ones.
bool noise_free_record(const Build& b, const ModelFile& truth, const Recording& est, Recording& clean_rec, Eigen::MatrixXd& y) {
  if (!simulate_outputs(truth, est, y)) return false;
  clean_rec = est;
  for (std::size_t j = 0; j < b.outputs.size(); ++j) {
    const Eigen::VectorXd yj = y.col(static_cast<Eigen::Index>(j));
    clean_rec.add(b.outputs[j].second, std::vector<double>(yj.data(), yj.data() + yj.size()));
  }
  return true;
}

// `model` (its free parameters from their values) calibrated on the noise-free outputs y: RMS miss
// / noise level, largest over the outputs; -1 when the calibration fails.
double calibrated_miss(const ModelFile& model, const Recording& clean_rec, const Eigen::MatrixXd& y, const Noise& noise) {
  try {
    Simulator s(model, clean_rec, {2});
    const CalibrationResult cr = calibrate(s, s.parameter_values(), s.free_parameters());
    if (!cr.ok) return -1;
    double worst = 0;
    for (Eigen::Index j = 0; j < y.cols(); ++j) {
      const double sd = std::sqrt((y.col(j).array() - y.col(j).mean()).square().mean());
      const double miss = std::sqrt((y.col(j) - cr.outputs.col(j)).array().square().mean());
      worst = std::max(worst, miss / std::max(noise.fraction[static_cast<std::size_t>(j)] * sd, 1e-300));
    }
    return worst;
  } catch (const std::exception&) {
    return -1;
  }
}

// Strong enough to matter: without it, the plant's own structure calibrated on the noise-free
// outputs (from the true values) still misses by at least 2 noise levels RMS on some output.
bool detectable(const Build& b, const Truth& truth_of, const ModelFile& truth, const Recording& est, const Noise& noise,
                const std::vector<double>& knobs, std::vector<double>& detectability) {
  const std::size_t count = truth_of.effects().size();
  detectability.assign(count, 0.0);
  Eigen::MatrixXd y;
  Recording clean_rec;
  if (!noise_free_record(b, truth, est, clean_rec, y)) return false;
  for (std::size_t i = 0; i < count; ++i) {
    detectability[i] = std::max(0.0, calibrated_miss(truth_of.with(knobs, static_cast<int>(i), nullptr), clean_rec, y, noise));
    if (detectability[i] < kDetectableInNoiseLevels) return false;
  }
  return true;
}

// Each richer law against its nested special case, the same measure as `detectable` (on the
// estimation record, as that is): -1 for an effect without one or where every calibration fails.
// Calibrations end in local optima: the best of three starts (the special case at either end of
// the law and midway) and of the plant without the law (`detectability`: Fc = 0, no offset, a
// point of the special case).
std::vector<double> detectability_vs_special_cases(const Build& b, const Truth& truth_of, const ModelFile& truth,
                                                   const Recording& est, const Noise& noise, const std::vector<double>& knobs,
                                                   const std::vector<double>& detectability) {
  std::vector<double> out(truth_of.effects().size(), -1.0);
  Eigen::MatrixXd y;
  Recording clean_rec;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (truth_of.effects()[i].special_case.empty()) continue;
    if (y.size() == 0 && !noise_free_record(b, truth, est, clean_rec, y)) return out;
    for (double level : {0.0, 0.5, 1.0}) {
      const double miss = calibrated_miss(truth_of.with(knobs, static_cast<int>(i), nullptr, level), clean_rec, y, noise);
      if (miss >= 0) out[i] = std::min({miss, out[i] < 0 ? miss : out[i], detectability[i]});
    }
  }
  return out;
}

// A law within the noise of its special case is that special case on these data (-1: no special
// case, or no calibration to measure it by).
bool distinct_from_special_cases(const std::vector<double>& vs_special) {
  return std::none_of(vs_special.begin(), vs_special.end(), [](double v) { return v >= 0 && v < kDetectableInNoiseLevels; });
}

// The measured outputs: the truth simulated on each record plus the drawn noise; sigma and
// sigma_validation: the true noise standard deviation per output on each record.
bool add_measured_outputs(Rng& r, const ModelFile& truth, const Build& b, const Noise& noise, Records& rec,
                          std::vector<double>& sigma, std::vector<double>& sigma_validation) {
  for (Recording* one : {&rec.est, &rec.val}) {
    Eigen::MatrixXd y;
    if (!simulate_outputs(truth, *one, y)) return false;
    for (std::size_t j = 0; j < b.outputs.size(); ++j) {
      const Eigen::VectorXd yj = y.col(static_cast<Eigen::Index>(j));
      const double sd = std::sqrt((yj.array() - yj.mean()).square().mean());
      const double s = std::max(noise.fraction[j] * sd, 1e-300);
      one->add(b.outputs[j].second, add_noise(r, yj, noise.kind[j], s));
      (one == &rec.est ? sigma : sigma_validation).push_back(s);
    }
  }
  return true;
}

// The nominal: effects left out, free parameters off by up to a factor 1.8, states measured
// start from their first sample.
ModelFile nominal_of(Rng& r, const Build& b, const std::string& time_col) {
  std::vector<ModelParameter> params;
  for (auto q : b.params) {
    if (std::find(b.removed_params.begin(), b.removed_params.end(), q.name) != b.removed_params.end()) continue;
    if (!q.fixed) q.value *= r.log_uniform(1 / 1.8, 1.8);
    params.push_back(q);
  }
  std::vector<ModelState> states = b.states;
  for (auto& s : states)
    for (const auto& [sym, col] : b.outputs)
      if (sym == s.name && r.chance(0.5)) s.initial_value.reset(), s.initial_column = col;
  return model_of(b, b.eqs, b.sampled, b.outputs, states, b.removed, params, time_col);
}

std::string description(const Build& b, const Records& rec, const Noise& noise) {
  std::ostringstream d;
  d << b.family << ", N = " << rec.n << ", Ts = " << b.Ts << " s (" << std::round(rec.per_time_scale)
    << " samples per time scale), " << rec.excitation_kind << " input, noise";
  for (std::size_t j = 0; j < noise.kind.size(); ++j) {
    std::ostringstream o;
    o.precision(2);
    o << noise.kind[j] << " " << 100 * noise.fraction[j] << " %";
    d << " " << o.str();
  }
  return d.str();
}

}  // namespace

std::vector<std::string> random_plant_families() {
  return {"one_mass", "two_mass", "motor", "thermal", "tanks", "position_loop"};
}

std::vector<std::string> random_plant_effects() {
  return {"coulomb_friction", "stribeck_friction", "viscous_friction", "quadratic_drag", "asymmetric_friction",
          "constant_offset",  "cubic_stiffness",   "bouc_wen_hysteresis", "backlash", "dead_zone", "input_saturation",
          "time_delay",       "output_saturation", "hysteresis", "absolute_value_sensor", "sqrt_outflow", "state_saturation"};
}

SyntheticPlant random_plant(unsigned seed, const RandomPlantOptions& options) {
  for (int attempt = 0; attempt < 40; ++attempt) {
    Rng r(0x9E3779B97F4A7C15ull * (seed + 1) + static_cast<std::uint64_t>(attempt) * 7919u);
    Names names(r);
    Build b;
    b.names = &names;
    b.family = options.family.empty() ? r.pick(random_plant_families()) : options.family;
    draw_family(r, b);
    Records rec = draw_records(r, names, b, options);
    const std::optional<std::vector<std::string>> drawn = draw_effect_names(r, b, options);
    if (!drawn) continue;
    SimulationResult clean;
    if (!simulates_bounded(b, rec, clean)) continue;
    const Scales sc = scales_of(clean, b.Ts);
    std::vector<Effect> effects;
    for (const auto& e : *drawn) effects.push_back(make_effect(r, b, e, sc));
    if (std::find(drawn->begin(), drawn->end(), "viscous_friction") != drawn->end()) {
      const Velocity& vel = b.velocities.front();
      b.removed = {vel.damping + "*" + vel.v};
      b.removed_params = {vel.damping};
    }
    const Noise noise = draw_noise(r, b.outputs.size());
    const Truth truth_of(b, effects, rec.time_col);
    std::vector<double> knobs(effects.size(), 0.1), strengths(effects.size(), 0);
    if (!set_strengths(r, truth_of, rec.est, noise, knobs, strengths)) continue;
    std::vector<EffectValues> values;
    const ModelFile truth = truth_of.with(knobs, -1, &values);
    std::vector<double> detectability;
    if (!detectable(b, truth_of, truth, rec.est, noise, knobs, detectability)) continue;
    SyntheticPlant p;
    if (!add_measured_outputs(r, truth, b, noise, rec, p.noise_sigma, p.noise_sigma_validation)) continue;
    p.family = b.family;
    p.name = "random-" + std::to_string(seed);
    p.nominal = nominal_of(r, b, rec.time_col);
    // After every other draw of this plant: measuring takes names from r, so a plant whose laws
    // all pass is the plant drawn before the measure could reject one.
    const std::vector<double> vs_special = detectability_vs_special_cases(b, truth_of, truth, rec.est, noise, knobs, detectability);
    if (options.distinct_from_special_cases && !distinct_from_special_cases(vs_special)) continue;
    p.nominal.name = "nominal " + b.family + " model (random plant " + std::to_string(seed) + ")";
    p.truth = truth;
    p.truth.name = "truth of random plant " + std::to_string(seed);
    p.estimation = std::move(rec.est);
    p.validation = std::move(rec.val);
    p.estimation.source = p.name + " (estimation)";
    p.validation.source = p.name + " (validation)";
    for (std::size_t i = 0; i < effects.size(); ++i)
      p.effects.push_back({effects[i].name, effects[i].where, values[i], strengths[i], detectability[i], effects[i].special_case,
                           vs_special[i]});
    p.true_effect = p.effects.empty() ? "none" : p.effects.front().name;
    if (!p.effects.empty()) p.true_values = p.effects.front().values;
    p.description = description(b, rec, noise);
    return p;
  }
  throw InputError("random plant " + std::to_string(seed) + ": no admissible plant in 40 attempts");
}

}  // namespace sets
