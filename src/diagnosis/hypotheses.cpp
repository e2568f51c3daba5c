// Stage 3 of the diagnosis: every catalogue effect, wherever it can enter, as a competing
// hypothesis calibrated with the free parameters; the acceptable ones added greedily (fewest
// terms that explain the data).

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <mutex>
#include <thread>

#include "diagnosis/stages.hpp"
#include "sets/numeric/glpk_environment.hpp"

namespace sets::diagnosis_stage {

namespace {

using Scales = std::vector<std::pair<std::string, double>>;

struct Trial {
  Candidate cand;
  ModelFile model;  // calibrated
  double cost = 1e300, cost_val = 1e300;
  ModelFile neutral_model;           // the calibrated model with the effect switched off
  double cost_neutral = 1e300, cost_neutral_val = 1e300;
  std::vector<double> fit, fit_val;
  bool ok = false;
};

// Calibrates one hypothesis (with every free parameter), and evaluates it with its own term
// switched off at the calibrated point.
Trial run_trial(const Context& c, Candidate cand, const Scales& known_scales) {
  const int substeps = c.options.screening_substeps;
  Trial t;
  t.cand = std::move(cand);
  try {
    if (t.cand.restart)
      for (auto& q : t.cand.model.parameters)
        if (const auto* orig = c.model.parameter(q.name); orig && !q.fixed) q.value = orig->value;
    Simulator s(t.cand.model, c.estimation, {substeps});
    const std::vector<int> fr = s.free_parameters();
    auto ks = known_scales;
    for (std::size_t k = 0; k < t.cand.parameters.size(); ++k) ks.emplace_back(t.cand.parameters[k], t.cand.scales[k]);
    CalibrationOptions o;
    o.scale = scales_for(t.cand.model, fr, ks);
    o.max_evaluations = 40 * static_cast<int>(fr.size() + 1);
    const auto r = calibrate(s, s.parameter_values(), fr, o);
    if (!r.ok) return t;
    t.ok = true;
    t.cost = r.cost;
    t.fit = r.fit;
    t.model = t.cand.model;
    store_values(t.model, r.parameters);
    if (c.validation) {
      Simulator sv(t.model, *c.validation, {substeps});
      const auto rv = evaluate(sv, r.parameters);
      t.cost_val = rv.ok ? rv.cost : 1e300;
      t.fit_val = rv.fit;
    }
    // The same parameters with the effect switched off: what the effect itself contributes.
    if (!t.cand.parameters.empty()) {
      t.neutral_model = t.model;
      for (std::size_t k = 0; k < t.cand.parameters.size(); ++k)
        if (!std::isnan(t.cand.neutral[k])) t.neutral_model.parameter(t.cand.parameters[k])->value = t.cand.neutral[k];
      const auto rn = evaluate(s, values_of(t.neutral_model));
      t.cost_neutral = rn.ok ? rn.cost : 1e300;
      if (c.validation && rn.ok) {
        Simulator sv(t.neutral_model, *c.validation, {substeps});
        const auto rv = evaluate(sv, values_of(t.neutral_model));
        t.cost_neutral_val = rv.ok ? rv.cost : 1e300;
      }
    }
  } catch (const std::exception&) {
    t.ok = false;  // a hypothesis that cannot be simulated loses
  }
  return t;
}

std::vector<Trial> run_trials(const Context& c, const std::vector<Candidate>& cands, const Scales& known_scales) {
  std::vector<Trial> trials(cands.size());
  std::atomic<std::size_t> next{0};
  std::mutex mu;
  auto worker = [&] {
    const GlpkThreadEnvironment glpk;  // freed when the worker ends
    for (std::size_t i; (i = next++) < cands.size();) {
      Trial t = run_trial(c, cands[i], known_scales);
      std::lock_guard<std::mutex> lock(mu);
      trials[i] = std::move(t);
    }
  };
  std::vector<std::thread> pool;
  for (int k = 0; k < std::max(1, c.options.threads); ++k) pool.emplace_back(worker);
  for (auto& th : pool) th.join();
  return trials;
}

// Time delay: ranked by a short calibration on the first fifth of the record (a delay shifts the
// optimum of the other parameters, so an uncalibrated ranking prefers too short a delay); the
// best two per actuator compete with the other hypotheses.
std::vector<Candidate> keep_best_delays(const Context& c, std::vector<Candidate> cands, const Scales& known_scales) {
  const Eigen::Index N = c.exact.samples();
  Recording head = c.estimation;
  const std::size_t rows = static_cast<std::size_t>(std::max<Eigen::Index>(std::min<Eigen::Index>(N, 200), N / 5));
  for (auto& col : head.columns) col.resize(rows);
  std::vector<Candidate> kept;
  std::map<std::string, std::vector<std::pair<double, std::size_t>>> ranked;
  for (std::size_t i = 0; i < cands.size(); ++i) {
    if (cands[i].effect != "time_delay") continue;
    if (cands[i].delay_samples >= static_cast<int>(rows) / 10) continue;
    Simulator s(cands[i].model, head, {c.options.screening_substeps});
    CalibrationOptions o;
    const auto fr = s.free_parameters();
    o.scale = scales_for(cands[i].model, fr, known_scales);
    o.max_evaluations = 10 * static_cast<int>(fr.size() + 1);
    const auto r = calibrate(s, s.parameter_values(), fr, o);
    ranked[cands[i].equation].push_back({r.ok ? r.cost : 1e300, i});
  }
  for (auto& [a, list] : ranked) {
    std::sort(list.begin(), list.end());
    for (std::size_t k = 0; k < std::min<std::size_t>(2, list.size()); ++k) kept.push_back(cands[list[k].second]);
  }
  for (auto& cand : cands)
    if (cand.effect != "time_delay") kept.push_back(std::move(cand));
  return kept;
}

// The delay grid is coarse: try every whole number of samples between the chosen one's neighbours.
void refine_delay(const Context& c, const ModelFile& current, const Scales& known_scales, Trial& t) {
  static const std::vector<int> grid = {1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64};
  const Eigen::Index N = c.exact.samples();
  const int n0 = t.cand.delay_samples;
  const auto it = std::find(grid.begin(), grid.end(), n0);
  const int lo = it == grid.begin() ? 1 : *(it - 1) + 1;
  const int hi = (it == grid.end() || it + 1 == grid.end()) ? n0 : *(it + 1) - 1;
  for (int n = lo; n <= hi; ++n) {
    if (n == n0 || n >= N / 10) continue;
    Candidate cand = delay_candidate(current, t.cand.equation, n);
    for (auto& q : cand.model.parameters) q.value = t.model.parameter(q.name)->value;
    Simulator s(cand.model, c.estimation, {c.options.screening_substeps});
    CalibrationOptions o;
    const auto fr = s.free_parameters();
    o.scale = scales_for(cand.model, fr, known_scales);
    o.max_evaluations = 10 * static_cast<int>(fr.size() + 1);
    const auto r = calibrate(s, s.parameter_values(), fr, o);
    if (r.ok && r.cost < t.cost) {
      t.cand = cand;
      t.model = cand.model;
      store_values(t.model, r.parameters);
      t.cost = r.cost;
      t.fit = r.fit;
      if (c.validation) {
        Simulator sv(t.model, *c.validation, {c.options.screening_substeps});
        const auto rv = evaluate(sv, r.parameters);
        t.cost_val = rv.ok ? rv.cost : 1e300;
      }
    }
  }
}

}  // namespace

HypothesisSearch search_hypotheses(const Context& c, const NominalFit& nominal, const NoiseFloor& noise, Diagnosis& d) {
  const DiagnosisOptions& opt = c.options;
  const Recording* val = c.validation;
  const double floor_cost = noise.cost;
  HypothesisSearch h;
  ModelFile& current = h.current;
  current = d.nominal;
  double cost_cur = cost_of(evaluate(c.fast, nominal.calibration.parameters).fit);
  double cost_cur_val = 0;
  if (val) {
    Simulator fast_val(c.model, *val, SimulationOptions{opt.screening_substeps});
    cost_cur_val = cost_of(evaluate(fast_val, nominal.calibration.parameters).fit);
  }
  std::vector<std::string> chosen;
  d.nothing_missing = nominal.cost <= opt.noise_floor_factor * floor_cost;
  for (int round = 0; round < opt.max_effects && !d.nothing_missing; ++round) {
    if (cost_cur <= opt.noise_floor_factor * floor_cost) break;
    Simulator cur_sim(current, c.estimation, {opt.screening_substeps});
    const SimulationResult cur_res = cur_sim.simulate(values_of(current));
    std::vector<std::string> exclude = chosen;
    for (const auto& e : chosen) {  // one friction law at a time
      if (e == "coulomb_friction") exclude.push_back("stribeck_friction");
      if (e == "stribeck_friction") exclude.push_back("coulomb_friction");
    }
    std::vector<Candidate> cands =
        keep_best_delays(c, generate_candidates(current, cur_res, c.estimation, exclude), h.known_scales);
    // The null hypothesis: the current model calibrated with the same budget. A hypothesis must
    // beat it, so that a better optimum of the old parameters is not credited to a new effect.
    {
      Candidate null;
      null.model = current;
      cands.insert(cands.begin(), null);
    }
    c.say("round " + std::to_string(round + 1) + ": calibrating " + std::to_string(cands.size()) + " competing hypotheses");
    std::vector<Trial> trials = run_trials(c, cands, h.known_scales);
    // Acceptance: removes enough of the misfit, more than noise could, and (with a validation
    // record) also helps there.
    if (trials.front().ok && trials.front().cost < cost_cur) {
      cost_cur = trials.front().cost;
      cost_cur_val = trials.front().cost_val;
      current = trials.front().model;
    }
    // A hypothesis whose calibration merely found a better optimum of the old parameters (its own
    // term switched off fits as well) shows a better baseline, not an effect.
    for (std::size_t i = 1; i < trials.size(); ++i) {
      const auto& t = trials[i];
      if (t.ok && t.cost_neutral < cost_cur && (!val || t.cost_neutral_val < 1e299)) {
        cost_cur = t.cost_neutral;
        cost_cur_val = val ? t.cost_neutral_val : 0;
        // Keep the current structure (the switched-off term is dropped), take the better values.
        for (auto& q : current.parameters)
          if (const auto* nq = t.neutral_model.parameter(q.name)) q.value = nq->value;
      }
    }
    std::vector<std::size_t> ok;
    for (std::size_t i = 1; i < trials.size(); ++i) {
      const auto& t = trials[i];
      if (!t.ok) continue;
      const double gain = (cost_cur - t.cost) / cost_cur;
      if (gain < opt.min_cost_reduction || cost_cur - t.cost < floor_cost) continue;
      if (t.cost_neutral < 1e299 && (t.cost_neutral - t.cost) / t.cost_neutral < opt.min_cost_reduction) continue;
      if (val && (cost_cur_val - t.cost_val) / cost_cur_val < 0.5 * opt.min_cost_reduction) continue;
      ok.push_back(i);
    }
    if (ok.empty()) break;
    auto judged = [&](std::size_t i) { return val ? trials[i].cost_val : trials[i].cost; };
    std::size_t best = ok.front();
    for (std::size_t i : ok)
      if (judged(i) < judged(best)) best = i;
    std::size_t pick = best;
    for (std::size_t i : ok)
      if (judged(i) <= opt.sparsity_tolerance * judged(best) &&
          (trials[i].cand.parameters.size() < trials[pick].cand.parameters.size() ||
           (trials[i].cand.parameters.size() == trials[pick].cand.parameters.size() && judged(i) < judged(pick))))
        pick = i;
    if (trials[pick].cand.effect == "time_delay") refine_delay(c, current, h.known_scales, trials[pick]);
    const Trial& t = trials[pick];
    DiagnosedEffect e;
    e.name = t.cand.effect;
    e.equation = t.cand.equation;
    e.term = t.cand.term;
    e.cost_reduction_estimation = (cost_cur - t.cost) / cost_cur;
    e.cost_reduction_validation = val ? (cost_cur_val - t.cost_val) / cost_cur_val : 0;
    std::ostringstream ev;
    ev << "adding " << t.cand.term << " to " << t.cand.equation << " removes " << fixed1(100 * e.cost_reduction_estimation)
       << " % of the squared misfit on the estimation record";
    if (val) ev << " and " << fixed1(100 * e.cost_reduction_validation) << " % on validation";
    ev << " (best of " << trials.size() - 1 << " competing hypotheses";
    if (pick != best) ev << "; preferred to " << trials[best].cand.effect << " as the simpler explanation";
    ev << ")";
    if (round == 0 && !d.regions.empty()) ev << "; nominal residual concentrated " << d.regions.front().description;
    e.evidence = ev.str();
    c.say("  found " + e.name + " in " + e.equation);
    for (std::size_t k = 0; k < t.cand.parameters.size(); ++k) h.known_scales.emplace_back(t.cand.parameters[k], t.cand.scales[k]);
    d.effects.push_back(e);
    chosen.push_back(t.cand.effect);
    h.chosen.push_back(t.cand);
    current = t.model;
    cost_cur = t.cost;
    cost_cur_val = t.cost_val;
  }
  return h;
}

}  // namespace sets::diagnosis_stage
