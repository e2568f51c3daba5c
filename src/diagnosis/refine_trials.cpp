// Stage 3 of the diagnosis, refinement: each hypothesis calibrated by output error from each of
// its starts (the worker pool runs every hypothesis-start pair), the best start kept, its cost
// with its own term switched off measured at the optimum; and the delay's whole number of samples.

#include <boost/algorithm/string/replace.hpp>

#include <algorithm>
#include <cmath>

#include "diagnosis/hypothesis_search.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets::diagnosis_stage {

namespace {

int substeps_of(const Context& c, int substeps) { return substeps > 0 ? substeps : c.options.screening_substeps; }

double validation_cost(const Context& c, const ModelFile& m, int substeps) {
  if (!c.validation) return kNaN;
  try {
    Simulator sv(m, *c.validation, {substeps});
    const auto r = evaluate(sv, sv.parameter_values());
    return r.ok ? r.cost : 1e300;
  } catch (const std::exception&) {
    return 1e300;
  }
}

// What every start of one hypothesis shares: its free parameters, their scales and the budget.
struct Setup {
  bool ok = false;
  std::vector<int> free;
  CalibrationOptions options;
  std::vector<Eigen::VectorXd> from;
};

Setup setup_of(const Context& c, const ToRefine& r, const Scales& known) {
  const Candidate& cand = *r.cand;
  Setup u;
  Simulator s(cand.model, c.estimation, {substeps_of(c, r.substeps)});
  u.free = s.free_parameters();
  auto ks = known;
  for (std::size_t k = 0; k < cand.parameters.size(); ++k) ks.emplace_back(cand.parameters[k], cand.scales[k]);
  u.options.scale = scales_for(cand.model, u.free, ks);
  // Multi-start (the screening's best grid points, its least-squares step, the equation-error
  // estimate); each with max_evaluations = 80 (n + 1), which calibrate() turns into Eigen's maxfev
  // = 80 simulations, Jacobians included: about 80 / (n + 2) iterations (a quarter of the
  // refinements end on it; 80 real iterations were tried and not landed: answers no better, three
  // tests worse, docs/reproduction/diagnosis.md, tenth session). With a third of it the Stribeck
  // law stopped at a third of the misfit reduction it reaches.
  u.options.max_evaluations = 80 * static_cast<int>(u.free.size() + 1);
  u.from = r.starts;
  if (u.from.empty()) u.from.push_back(s.parameter_values());
  if (cand.restart)  // from the file's values: the calibrated nominal may be far off
    u.from.push_back(values_of(at_file_values(cand.model, c.model)));
  u.ok = true;
  return u;
}

// `m` with the delay `part` taken out: its term prev(s, n) read back as the undelayed signal s
// (delay_candidate writes prev(a, n) in place of a; in a pair, s may be a later effect's signal
// at a, combine_candidates).
ModelFile without_delay(ModelFile m, const Candidate& part) {
  const std::string undelayed = delayed_signal(part.term);
  for (auto* texts : {&m.derivatives, &m.signals})
    for (auto& t : *texts) boost::algorithm::replace_all(t.second, part.term, undelayed);
  return m;
}

// The calibrated hypothesis (`best`: its best start) on validation, and with its own term
// switched off.
Trial finish(const Context& c, const Candidate& cand, const CalibrationResult& best, int substeps) {
  Trial t;
  t.cand = cand;
  t.substeps = substeps;
  if (!best.ok) return t;
  const int sub = substeps_of(c, substeps);
  try {
    Simulator s(cand.model, c.estimation, {sub});
    t.ok = true;
    t.cost = best.cost;
    t.costs = output_costs(best.fit);
    t.model = cand.model;
    store_values(t.model, best.parameters);
    t.cost_val = validation_cost(c, t.model, sub);
    // Switched off: every new parameter at its neutral value (NaN: irrelevant once the others are);
    // a delay, which has no parameter, taken out.
    auto switched_off = [&](const Candidate& part) {
      ModelFile m = t.model;
      if (part.effect == "time_delay") return std::make_pair(without_delay(m, part), true);
      bool any = false;
      for (std::size_t k = 0; k < part.parameters.size(); ++k)
        if (!std::isnan(part.neutral[k])) m.parameter(part.parameters[k])->value = part.neutral[k], any = true;
      return std::make_pair(m, any);
    };
    // The switched-off model on the hypothesis's simulator, or on its own when its text differs.
    auto cost_of = [&](const ModelFile& m) {
      if (m.derivatives == t.model.derivatives && m.signals == t.model.signals) return evaluate(s, values_of(m));
      Simulator other(m, c.estimation, {sub});
      return evaluate(other, values_of(m));
    };
    if (cand.parts.empty()) {
      const auto [m, any] = switched_off(cand);
      if (any) {
        t.neutral_model = m;
        const auto rn = cost_of(m);
        t.cost_neutral = rn.ok ? rn.cost : 1e300;
        if (rn.ok) t.costs_neutral = output_costs(rn.fit);
        if (rn.ok) t.cost_neutral_val = validation_cost(c, m, sub);
      }
    } else {
      // Two at once: each must matter on its own; the rule judges the weaker one.
      for (const auto& part : cand.parts) {
        const auto [m, any] = switched_off(part);
        const auto rn = cost_of(m);
        t.part_neutral.push_back(!any ? kNaN : rn.ok ? rn.cost : 1e300);
      }
      for (double v : t.part_neutral)
        if (std::isfinite(v) && !(v >= t.cost_neutral)) t.cost_neutral = v;
    }
  } catch (const std::exception&) {
    t = Trial();
    t.cand = cand;  // a hypothesis that cannot be simulated loses
  }
  return t;
}

}  // namespace

ModelFile at_file_values(ModelFile m, const ModelFile& file) {
  for (auto& q : m.parameters)
    if (const auto* v = file.parameter(q.name); v && !q.fixed) q.value = v->value;
  return m;
}

// Output-error calibration of each hypothesis from each of its starts (the best kept), then its
// cost with its own term switched off at the calibrated point. Every (hypothesis, start) pair is
// one job of the worker pool, so both threads stay busy to the end of the round; the result is
// the serial one (the best start in start order, a hypothesis lost when any of its starts throws).
std::vector<Trial> refine(const Context& c, const std::vector<ToRefine>& hypotheses, const Scales& known) {
  const std::size_t n = hypotheses.size();
  std::vector<Setup> setups(n);
  std::vector<std::pair<std::size_t, std::size_t>> jobs;  // (hypothesis, start)
  for (std::size_t i = 0; i < n; ++i) {
    try {
      setups[i] = setup_of(c, hypotheses[i], known);
    } catch (const std::exception&) {
      continue;
    }
    for (std::size_t k = 0; k < setups[i].from.size(); ++k) jobs.emplace_back(i, k);
  }
  // Longest first (more free parameters: more simulations per Jacobian), so that the round does
  // not end on one long job while the other thread idles; results stay indexed by job.
  std::stable_sort(jobs.begin(), jobs.end(), [&](const auto& x, const auto& y) {
    return setups[x.first].free.size() > setups[y.first].free.size();
  });
  struct Outcome {
    CalibrationResult r;
    bool threw = false;
  };
  std::vector<Outcome> out(jobs.size());
  run_jobs(c.options.threads, jobs.size(), [&](std::size_t j) {
    const auto [i, k] = jobs[j];
    try {
      const Simulator s(hypotheses[i].cand->model, c.estimation, {substeps_of(c, hypotheses[i].substeps)});
      out[j].r = calibrate(s, setups[i].from[k], setups[i].free, setups[i].options);
    } catch (const std::exception&) {
      out[j].threw = true;
    }
  });
  std::vector<CalibrationResult> best(n);
  std::vector<bool> lost(n, false);
  for (std::size_t i = 0; i < n; ++i) lost[i] = !setups[i].ok;
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    const std::size_t i = jobs[j].first;
    const CalibrationResult& r = out[j].r;
    lost[i] = lost[i] || out[j].threw;
    if (r.ok && (!best[i].ok || r.cost < best[i].cost)) best[i] = r;
  }
  std::vector<Trial> trials(n);
  run_jobs(c.options.threads, n, [&](std::size_t i) {
    if (lost[i]) best[i].ok = false;
    trials[i] = finish(c, *hypotheses[i].cand, best[i], hypotheses[i].substeps);
  });
  return trials;
}

std::vector<int> delays_around(int n0, int samples) {
  static const std::vector<int> grid = {1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64};
  const auto above = std::upper_bound(grid.begin(), grid.end(), n0);
  const auto below = std::lower_bound(grid.begin(), grid.end(), n0);
  const int lo = below == grid.begin() ? 1 : *(below - 1) + 1;
  const int hi = above == grid.end() ? n0 + 8 : *above - 1;
  std::vector<int> around;
  for (int n = lo; n <= hi && n < samples / 10; ++n) around.push_back(n);
  return around;
}

// The delay grid is coarse: every whole number of samples between the screened one's neighbours
// is screened again by simulation (cheap), the best is refined.
Candidate best_delay(const Context& c, const ModelFile& current, const Candidate& chosen, const std::vector<double>& bound) {
  std::vector<Candidate> around;
  for (int n : delays_around(chosen.delay_samples, c.exact.samples())) around.push_back(delay_candidate(current, chosen.equation, n));
  if (around.size() < 2) return chosen;
  ScreeningOptions so;
  so.substeps = c.options.screening_substeps;
  so.threads = c.options.threads;
  so.noise_bound = bound;
  so.equation_error = false;
  const Screening s = screen_hypotheses(current, c.estimation, around, so);
  return s.ranked.empty() ? chosen : s.ranked.front().candidate;
}

}  // namespace sets::diagnosis_stage
