// Stage 3 of the diagnosis, judging a round: every refined hypothesis checked against the
// documented rules (acceptance.hpp) and against each special case it nests, the sparsest that
// passes picked, the hypotheses the data cannot tell from it listed as equally good, and the pick
// recorded in the diagnosis with its intervals.

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "diagnosis/hypothesis_search.hpp"

namespace sets::diagnosis_stage {

namespace {

HypothesisEvidence evidence_of(const Round& r, const NoiseFloor& noise, const Trial& t) {
  HypothesisEvidence e;
  e.cost_null = r.cost_cur;
  e.cost = t.cost;
  e.cost_neutral = t.cost_neutral;
  e.cost_null_validation = r.cost_cur_val;
  e.cost_validation = t.cost_val;
  e.noise_cost = noise.cost;
  e.cost_null_outputs = r.costs_cur;
  e.cost_outputs = t.costs;
  e.noise_cost_outputs = noise.costs;
  return e;
}

// Nested hypotheses: a richer law is judged against each special case of it that was calibrated,
// by the same rules with that special case as the baseline (its extra parameters must remove the
// share of misfit the rules ask, on estimation and validation, and more than the noise). The
// switch-off rule does not apply: the special case, calibrated, is the richer law with its extra
// terms switched off and every other parameter free.
HypothesisEvidence against(const Round& r, const NoiseFloor& noise, const Trial& richer, const Trial& special) {
  HypothesisEvidence e = evidence_of(r, noise, richer);
  e.cost_null = special.cost;
  e.cost_null_outputs = special.costs;
  e.cost_null_validation = special.cost_val;
  e.cost_neutral = kNaN;
  return e;
}

// The special cases of an accepted law that were not calibrated in this round are, as baselines
// of the nested rule only.
std::vector<Trial> uncalibrated_special_cases(const Context& c, const HypothesisSearch& h, const Round& r) {
  std::vector<Candidate> extra;
  std::vector<const Candidate*> calibrated;
  for (std::size_t j = 1; j < r.trials.size(); ++j)
    if (r.trials[j].ok) calibrated.push_back(&r.trials[j].cand);
  for (std::size_t i = 1; i < r.trials.size(); ++i)
    if (r.trials[i].accepted)
      for (auto& k : missing_special_cases(c, h.current, r.current_simulation, r.trials[i].cand, calibrated)) {
        bool dup = false;
        for (const auto& x : extra) dup = dup || (x.effect == k.effect && x.equation == k.equation);
        if (!dup) extra.push_back(std::move(k));
      }
  std::vector<ToRefine> extra_to_refine;
  for (const auto& e : extra) extra_to_refine.push_back({&e, {values_of(e.model)}});
  return refine(c, extra_to_refine, h.known_scales);
}

using Box = std::map<std::string, std::array<double, 3>>;  // parameter -> estimate, lo, hi

// A law at its optimum as stage 4 computes it: the calibration continued (a second budget: a
// rough cost such as Stribeck's stops short of it), then refined with the final substeps; with the
// output error linearised there. ok = false when it cannot be built.
struct AtOptimum {
  bool ok = false;
  std::vector<int> free;
  std::vector<double> scale;
  Eigen::MatrixXd J, R;  // output Jacobian, measured - simulated
  Eigen::VectorXd parameters;
};

AtOptimum at_optimum(const Context& c, const HypothesisSearch& h, const Trial& t) {
  const DiagnosisOptions& opt = c.options;
  AtOptimum a;
  try {
    Simulator fast(t.model, c.estimation, {opt.screening_substeps}), s(t.model, c.estimation, {opt.final_substeps});
    a.free = s.free_parameters();
    auto ks = h.known_scales;
    for (std::size_t k = 0; k < t.cand.parameters.size(); ++k) ks.emplace_back(t.cand.parameters[k], t.cand.scales[k]);
    CalibrationOptions o;
    o.scale = scales_for(t.model, a.free, ks);
    o.max_evaluations = 80 * static_cast<int>(a.free.size() + 1);
    const CalibrationResult further = calibrate(fast, values_of(t.model), a.free, o);
    const CalibrationResult r =
        refine_with_final_substeps(c, s, further.ok && further.cost < t.cost ? further.parameters : values_of(t.model), a.free, o);
    if (!r.ok) return a;  // the law blows up with the final substeps
    a.J = output_jacobian(s, r.parameters, a.free, o.scale, r.outputs);
    a.R = s.measured() - r.outputs;
    a.parameters = r.parameters;
    a.scale = o.scale;
    a.ok = true;
  } catch (const std::exception&) {
    a.ok = false;
  }
  return a;
}

// A richer law's output-error intervals at its optimum, as stage 4 computes them (empty when they
// cannot be built: then nothing is excluded by them), and its largest |residual| per output there
// (on the samples the strips use).
struct Intervals {
  Box box;
  std::vector<double> largest;
};

Intervals intervals_at_optimum(const Context& c, const HypothesisSearch& h, const Trial& t) {
  Intervals out;
  const AtOptimum a = at_optimum(c, h, t);
  if (!a.ok) return out;
  const OutputErrorIntervals oe = output_error_intervals(a.J, a.R, a.parameters, a.free, a.scale);
  for (std::size_t k = 0; oe.built && k < a.free.size(); ++k)
    out.box[t.model.parameters[static_cast<std::size_t>(a.free[k])].name] = {a.parameters[a.free[k]], oe.lo[k], oe.hi[k]};
  for (Eigen::Index j = 0; j < a.R.cols(); ++j) {  // on the samples the strips use
    double m = 0;
    for (Eigen::Index t = 0; t < a.R.rows(); t += oe.stride) m = std::max(m, std::abs(a.R(t, j)));
    out.largest.push_back(m);
  }
  return out;
}

// Do the data exclude the special case itself? Its output error linearised at *its own* optimum
// (where that linearisation holds), every parameter of it free: no point of it fits within the
// bound. The bound per output is the noise's (noise_bound_factor x sigma, under which the truth
// fits), or the richer law's largest residual when the richer law does not fit within the noise
// either (then the special case is excluded only if it cannot fit as closely as the richer law
// does). This is what "the data exclude the special case" means in bounded error; the richer
// law's interval of a fixed parameter, linearised at the richer law's optimum, is only a
// sufficient condition for it: where the model's other parameters are poorly determined, its
// projection reaches the fixed value far from that optimum, where the linearisation no longer
// holds (5 001 955: asymmetric friction fits to the noise, Coulomb friction leaves 30 times the
// noise's misfit, yet dFv's interval held 0, beside Kb in [-4.8, 5.1]). EMPS stays Coulomb
// friction + offset by it: Coulomb friction fits within the bound asymmetric friction meets.
bool special_case_falsified(const Context& c, const HypothesisSearch& h, const Trial& special, const std::vector<double>& bound) {
  if (bound.empty()) return false;
  const AtOptimum a = at_optimum(c, h, special);
  return a.ok && a.R.cols() == static_cast<Eigen::Index>(bound.size()) && linearised_strips_falsified(a.J, a.R, a.scale, bound);
}

}  // namespace

// Each trial against the acceptance rules, then each accepted richer law against its special
// cases: the rules with the special case as baseline, and the data must exclude the special case
// (the richer law's output-error interval, linearised at its optimum, of a parameter fixed on the way leaves out the fixed
// value: a richer law whose extra term could be zero fits better only by fitting what else the
// model leaves out). Fills r.ok and r.beats.
void judge_round(const Context& c, const HypothesisSearch& h, const NoiseFloor& noise, const AcceptanceRules& rules, Round& r) {
  auto& trials = r.trials;
  for (std::size_t i = 1; i < trials.size(); ++i) {
    if (!trials[i].ok) continue;
    trials[i].rules = check_rules(evidence_of(r, noise, trials[i]), rules);
    trials[i].accepted = passes(trials[i].rules);
  }
  const std::vector<Trial> baselines = uncalibrated_special_cases(c, h, r);
  std::vector<const Trial*> special_cases;
  for (std::size_t j = 1; j < trials.size(); ++j)
    if (trials[j].ok) special_cases.push_back(&trials[j]);
  for (const auto& b : baselines)
    if (b.ok) special_cases.push_back(&b);
  std::map<std::size_t, Intervals> intervals;
  auto intervals_of = [&](std::size_t i) -> const Intervals& {
    if (!intervals.count(i)) intervals[i] = intervals_at_optimum(c, h, trials[i]);
    return intervals[i];
  };
  auto interval_of = [&](std::size_t i, const std::string& name) -> std::array<double, 3> {
    const auto& box = intervals_of(i).box;
    const auto it = box.find(name);
    return it == box.end() ? std::array<double, 3>{kNaN, -inf, inf} : it->second;
  };
  auto excludes = [&](std::size_t i, const Trial& special, const Fixed& fixed, std::string& why) {
    if (fixed.empty()) return true;  // reached by equalities only: the rules alone decide
    for (const auto& [name, value] : fixed) {
      const auto [estimate, lo, hi] = interval_of(i, name);
      if (value < lo || value > hi) return true;
      why += (why.empty() ? "" : ", ") + name + " = " + fmt(estimate) + " in [" + fmt(lo) + ", " + fmt(hi) + "] holds " + fmt(value);
    }
    std::vector<double> bound = intervals_of(i).largest;
    for (std::size_t j = 0; j < bound.size() && j < noise.sigma.size(); ++j)
      bound[j] = std::max(bound[j], noise_bound_factor(c.exact.samples()) * noise.sigma[j]);
    if (special_case_falsified(c, h, special, bound)) return true;
    why += "; " + special.cand.effect + ", linearised at its own optimum, is not excluded by the bound the richer law meets";
    return false;
  };
  for (std::size_t i = 1; i < trials.size(); ++i) {
    for (const Trial* j : special_cases) {
      Fixed fixed;
      if (!trials[i].accepted || !nests(trials[i].cand, j->cand, &fixed)) continue;
      if (const auto checks = check_rules(against(r, noise, trials[i], *j), rules); !passes(checks)) {
        trials[i].accepted = false;
        trials[i].not_beyond = j->cand.effect + " (fails " + failed_rules(checks) + " against it)";
      } else if (std::string why; !excludes(i, *j, fixed, why)) {
        trials[i].accepted = false;
        trials[i].not_beyond = j->cand.effect + " (output-error interval linearised at its optimum: " + why + ")";
      } else {
        r.beats[i] += (r.beats[i].empty() ? "" : ", ") + j->cand.effect;
      }
    }
    if (trials[i].accepted) r.ok.push_back(i);
  }
}

// One progress line per refined hypothesis.
void say_round(const Context& c, const Round& r) {
  for (std::size_t i = 1; i < r.trials.size(); ++i) {
    const Trial& t = r.trials[i];
    std::ostringstream line;
    line << "    " << r.list[i - 1]->candidate.effect << " (" << r.list[i - 1]->candidate.equation << "): ";
    if (!t.ok) line << "could not be calibrated";
    else {
      line << "misfit " << fixed1(100 * t.cost / std::max(r.cost_cur, 1e-300)) << " % of the current model's";
      if (c.validation) line << ", validation " << fixed1(100 * t.cost_val / std::max(r.cost_cur_val, 1e-300)) << " %";
      line << (t.accepted             ? ", passes every rule"
               : t.not_beyond.empty() ? ", fails " + failed_rules(t.rules)
                                      : ", not beyond its special case " + t.not_beyond);
    }
    c.say(line.str());
  }
}

// The sparsest explanation among the accepted: misfit (validation when there is one) x
// tolerance^parameters; `best` is the best misfit. Between nested hypotheses the rules decide,
// not the parameter count: an accepted richer law has passed them against the special case picked.
std::pair<std::size_t, std::size_t> pick_sparsest(const Context& c, const Round& r) {
  const auto& trials = r.trials;
  auto judged = [&](std::size_t i) { return c.validation ? trials[i].cost_val : trials[i].cost; };
  auto score = [&](std::size_t i) {
    int p = static_cast<int>(trials[i].cand.parameters.size());
    for (const auto& part : parts_of(trials[i].cand)) p += part.effect == "time_delay" ? 1 : 0;
    return judged(i) * std::pow(c.options.sparsity_tolerance, p);
  };
  std::size_t pick = r.ok.front(), best = r.ok.front();
  for (std::size_t i : r.ok) {
    if (score(i) < score(pick)) pick = i;
    if (judged(i) < judged(best)) best = i;
  }
  for (bool moved = true; moved;) {
    moved = false;
    for (std::size_t i : r.ok)
      if (nests(trials[i].cand, trials[pick].cand)) {
        pick = i;
        moved = true;
        break;
      }
  }
  return {pick, best};
}

// The hypotheses of the round the data cannot tell from the pick (`a`): each passes every rule on
// its own (r.ok: the nested rule included, so a richer law below its special case is not one), and
// the nested rule's comparison (against) finds neither beyond the other. One-sided would list a
// hypothesis the data prefer and sparsity passed over: the data do tell those apart. A hypothesis
// holding every effect of the pick is the pick with more beside it, not another explanation; one
// holding part of a pair is kept (the pair's other member is then not needed on these data).
// 5 002 875: -(T2 - Ta)/R2_x with Ta fixed ties slope and intercept in T2; viscous friction and a
// constant offset both free them, the same family, so either fits as well as the other.
std::vector<EquallyGood> equally_good(const Round& r, const NoiseFloor& noise, const AcceptanceRules& rules, std::size_t a) {
  std::vector<EquallyGood> out;
  const std::vector<Candidate> mine = parts_of(r.trials[a].cand);
  for (std::size_t b : r.ok) {
    if (b == a) continue;
    const std::vector<Candidate> theirs = parts_of(r.trials[b].cand);
    const bool holds_pick = std::all_of(mine.begin(), mine.end(), [&](const Candidate& p) {
      return std::any_of(theirs.begin(), theirs.end(), [&](const Candidate& q) { return q.effect == p.effect && q.equation == p.equation; });
    });
    if (holds_pick || passes(check_rules(against(r, noise, r.trials[a], r.trials[b]), rules)) ||
        passes(check_rules(against(r, noise, r.trials[b], r.trials[a]), rules)))
      continue;
    EquallyGood e;
    for (const auto& q : theirs) e.effects.push_back(q.effect), e.equations.push_back(q.equation);
    e.misfit = r.trials[b].cost / std::max(r.cost_cur, 1e-300);
    e.misfit_validation = r.trials[b].cost_val / std::max(r.cost_cur_val, 1e-300);
    out.push_back(std::move(e));
  }
  std::stable_sort(out.begin(), out.end(), [](const EquallyGood& x, const EquallyGood& y) { return x.misfit < y.misfit; });
  std::vector<EquallyGood> once;  // the same effects at the same places refined twice (variants of one law): once
  for (auto& e : out)
    if (std::none_of(once.begin(), once.end(), [&](const EquallyGood& x) { return x.effects == e.effects && x.equations == e.equations; }))
      once.push_back(std::move(e));
  return once;
}

// The picked hypothesis's effects added to the diagnosis (two at once: each with its own share of
// the misfit, the larger first) and to the search.
void record_pick(const Context& c, const Round& r, std::size_t pick, std::size_t best, std::vector<EquallyGood> alike,
                 HypothesisSearch& h, std::vector<std::string>& chosen, Diagnosis& d) {
  const Trial& t = r.trials[pick];
  const std::vector<Candidate> parts = parts_of(t.cand);
  std::vector<std::size_t> order(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k) order[k] = k;
  auto own_share = [&](std::size_t k) {
    const double off = t.part_neutral.empty() ? t.cost_neutral : t.part_neutral[k];
    return std::isfinite(off) && off > 0 ? (off - t.cost) / off : 0.0;
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return own_share(a) > own_share(b); });
  for (std::size_t k : order) {
    const Candidate& part = parts[k];
    DiagnosedEffect e;
    e.name = part.effect;
    e.equation = part.equation;
    e.term = part.term;
    e.delay_samples = part.delay_samples;
    if (const auto* pe = find_effect(e.name)) e.placement = pe->placement;
    e.rules = t.rules;
    for (auto& rule : e.rules)
      if (rule.name == "own_term" && !t.part_neutral.empty()) {
        rule.value = own_share(k);
        rule.applies = std::isfinite(t.part_neutral[k]);
        rule.passed = !rule.applies || rule.value >= rule.threshold;
      }
    e.screening_gain = t.screening_gain;
    e.cost_reduction_estimation = t.rules[0].value;
    e.cost_reduction_validation = t.rules[3].applies ? t.rules[3].value : 0;
    std::ostringstream ev;
    ev << "adding " << part.term << " to " << part.equation;
    if (parts.size() > 1) ev << " (together with " << parts[1 - k].effect << " in " << parts[1 - k].equation << ")";
    ev << " removes " << fixed1(100 * e.cost_reduction_estimation) << " % of the squared misfit on the estimation record";
    if (c.validation) ev << " and " << fixed1(100 * e.cost_reduction_validation) << " % on validation";
    ev << " (screened " << r.screening.ranked.size() << " hypotheses, refined " << r.list.size() << ", " << r.ok.size()
       << " passed every rule";
    if (pick != best) ev << "; preferred to " << r.trials[best].cand.effect << " as the sparser explanation";
    if (r.beats.count(pick)) ev << "; preferred to " << r.beats.at(pick) << ", its special case, by the same rules";
    ev << ")";
    if (r.index == 0 && !d.regions.empty()) ev << "; nominal residual concentrated " << d.regions.front().description;
    e.evidence = ev.str();
    if (k == order.front()) {
      e.equally_good = std::move(alike);
      for (const auto& a : e.equally_good) c.say("  equally good on these data: " + equally_good_text(a));
    }
    c.say("  found " + e.name + " in " + e.equation);
    for (std::size_t q = 0; q < part.parameters.size(); ++q) h.known_scales.emplace_back(part.parameters[q], part.scales[q]);
    d.effects.push_back(e);
    chosen.push_back(part.effect);
    h.chosen.push_back(part);
  }
  h.current = t.model;
}

}  // namespace sets::diagnosis_stage
