// Stage 3 of the diagnosis, second refinements within a round: hypotheses whose first
// refinement can have ended in the wrong basin are refined again from other starts — from a
// special case's optimum, from the model they nest switched off, from the file's values (a
// delay, and the delay of a pair that failed from there alone), a pair's members alone and a
// richer pair from the pair's optimum; and a chosen delay refined at its neighbouring whole
// numbers of samples.

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <optional>
#include <set>

#include "diagnosis/hypothesis_search.hpp"

namespace sets::diagnosis_stage {

// A richer law refined from the screening's starts can end in a worse basin than its special case
// (700 067: Stribeck 4.4 % of the misfit, Coulomb 4.3 %), though it contains it. Each one-effect
// richer law in the round is refined again from the optimum of each special case refined beside
// it (starts_at_special_case) and from that optimum with its extra term switched on
// (switched_on_start), and keeps the better of the two results. A richer law the shortlist left
// out whose special case is in it is refined from the switched-on start alone: its screening
// linearised it at the special case's neighbourhood too (at Fs = 0 vs does nothing), so its rank
// says little about its own basin (5 001 597: Coulomb listed, Stribeck not).
void continue_from_special_cases(const Context& c, const HypothesisSearch& h, Round& r) {
  std::vector<const ScreenedHypothesis*> laws(r.list.begin(), r.list.end());
  const std::size_t listed = laws.size();
  for (const auto& s : r.screening.ranked) {
    if (!s.candidate.parts.empty() || std::find(laws.begin(), laws.end(), &s) != laws.end()) continue;
    for (std::size_t j = 1; j < r.trials.size(); ++j)
      if (r.trials[j].ok && r.trials[j].cand.parts.empty() && nests(s.candidate, r.trials[j].cand)) {
        laws.push_back(&s);
        break;
      }
  }
  std::vector<std::size_t> which;
  std::vector<ToRefine> again;
  for (std::size_t i = 0; i < laws.size(); ++i) {
    std::vector<Eigen::VectorXd> starts;
    for (std::size_t j = 1; j < r.trials.size(); ++j) {
      if (j == i + 1) continue;  // itself (only listed laws have a trial)
      if (i < listed)
        for (auto& s : starts_at_special_case(laws[i]->candidate, r.trials[j])) starts.push_back(std::move(s));
      if (auto on = switched_on_start(c, laws[i]->candidate, r.trials[j])) starts.push_back(std::move(*on));
    }
    if (starts.empty()) continue;
    which.push_back(i);
    again.push_back({&laws[i]->candidate, std::move(starts)});
  }
  if (again.empty()) return;
  const std::vector<Trial> continued = refine(c, again, h.known_scales);
  for (std::size_t k = 0; k < which.size(); ++k) {
    const std::size_t i = which[k];
    if (i >= listed) {
      if (!continued[k].ok) continue;
      r.list.push_back(laws[i]);
      r.trials.push_back(continued[k]);
      continue;
    }
    Trial& t = r.trials[i + 1];
    if (continued[k].ok && (!t.ok || continued[k].cost < t.cost)) t = continued[k];
  }
}

namespace {

// `cand`'s parameter vector at the current model's point with its own term switched off (its new
// parameters at their neutral values; NaN: irrelevant, left where they are): the current model
// itself. Empty when no parameter switches the term off (a delay, a sensor law without one) or
// when switching it off does not give the current model back (a law that replaces a term).
std::optional<Eigen::VectorXd> switched_off_start(const Candidate& cand, const ModelFile& current) {
  ModelFile m = cand.model;
  for (auto& q : m.parameters)
    if (const auto* v = current.parameter(q.name)) q.value = v->value;
  bool any = false;
  for (const auto& part : parts_of(cand)) {
    const PhysicsEffect* e = find_effect(part.effect);
    if (part.effect == "time_delay" || (e && e->placement == "replaces a*x")) return {};
    for (std::size_t k = 0; k < part.parameters.size(); ++k)
      if (!std::isnan(part.neutral[k])) m.parameter(part.parameters[k])->value = part.neutral[k], any = true;
  }
  if (!any) return {};
  return values_of(m);
}

// A delay has no value that switches it off, so a delay that ends worse than the current model has
// no start from which Levenberg-Marquardt can only descend. Its candidate's starts hold the
// calibrated model's parameters, and the calibration has absorbed the missing delay into them (a
// phase lag made up for by other terms); with the delay added that point can be several times
// worse than the model without it, or unstable, and the refinement stays there. The file's values
// were calibrated by no one against the missing delay: the start the nominal's own calibration had.
// `cand`'s parameter vector with every model parameter the file declares free at the file's value,
// its own at its screening start. Empty when the candidate has no delay.
std::optional<Eigen::VectorXd> delay_from_file_start(const Candidate& cand, const ModelFile& file) {
  bool delay = false;
  for (const auto& part : parts_of(cand)) delay = delay || part.effect == "time_delay";
  if (!delay) return {};
  return values_of(at_file_values(cand.model, file));
}

// The round's trials `which` refined again from the starts `again` (a progress line says `why`
// unless it is empty), each keeping the better of its two results (its screening gain with it).
void refine_again(const Context& c, const HypothesisSearch& h, const std::vector<std::size_t>& which,
                  const std::vector<ToRefine>& again, const std::string& why, Round& r) {
  if (!why.empty()) {
    std::string names;
    for (const auto& a : again) names += (names.empty() ? "" : ", ") + a.cand->effect + " (" + a.cand->equation + ")";
    c.say("  " + why + ": " + names);
  }
  const std::vector<Trial> better = refine(c, again, h.known_scales);
  for (std::size_t k = 0; k < which.size(); ++k) {
    Trial& t = r.trials[which[k]];
    if (!better[k].ok || (t.ok && better[k].cost >= t.cost)) continue;
    const double gain = t.screening_gain;
    t = better[k];
    t.screening_gain = gain;
  }
}

// A pair holding a delay that ended worse than the current model from the file's values too: its
// partner started from its screening value, fitted at the calibrated point against the absorbed
// delay, and that value means nothing at the file's (5 010 869: a viscous term fitted against the
// calibration's negative damping kept the pair at 130 % of the current misfit, where the file's
// values with the delay alone reach the noise). The delay alone, when the shortlist left it out,
// is refined from the file's values and joins the round as its own hypothesis.
void refine_delays_of_failed_pairs(const Context& c, const HypothesisSearch& h, const std::vector<std::size_t>& retried,
                                   Round& r) {
  std::vector<const ScreenedHypothesis*> alone;
  std::vector<ToRefine> again;
  std::string names;
  for (std::size_t i : retried) {
    const Trial& t = r.trials[i];
    if (t.cand.parts.empty() || (t.ok && t.cost <= r.cost_cur)) continue;
    for (const auto& part : t.cand.parts) {
      if (part.effect != "time_delay") continue;
      const ScreenedHypothesis* a = screened_alone(r.screening, part);
      if (!a || std::find(r.list.begin(), r.list.end(), a) != r.list.end() ||
          std::find(alone.begin(), alone.end(), a) != alone.end())
        continue;
      if (auto start = delay_from_file_start(a->candidate, c.model)) {
        alone.push_back(a);
        again.push_back({&a->candidate, {std::move(*start)}});
        names += (names.empty() ? "" : ", ") + a->candidate.effect + " (" + a->candidate.equation + ")";
      }
    }
  }
  if (again.empty()) return;
  c.say("  refining from the file's values the delay alone of a pair that ended worse from there too: " + names);
  const std::vector<Trial> refined = refine(c, again, h.known_scales);
  for (std::size_t k = 0; k < alone.size(); ++k) {
    if (!refined[k].ok) continue;
    r.list.push_back(alone[k]);
    r.trials.push_back(refined[k]);
    r.trials.back().screening_gain = alone[k]->gain;
  }
}

}  // namespace

// A hypothesis adds a term to the current model: with its term switched off it *is* the current
// model, so at its optimum it cannot fit worse than the baseline (the current model calibrated
// with the same budget, or a better optimum of its parameters a trial found). When its refinement
// from the screening's starts ends worse, or cannot be calibrated, every start lay in another
// basin: the screening linearises at the current point, and where the calibrated nominal is far
// from the data its least-squares step puts the new term, and the model's parameters with it,
// where the output error is many times the current model's (random plant 5 001 938, an offset
// beside a cubic stiffness, nominal fit 15 %: the offset ended at 6.8x the current misfit and
// nothing was named; from the current point it removes 39 %). Such a hypothesis is refined again
// from the current model's point with its term switched off — a start from which Levenberg-Marquardt
// can only descend — and keeps the better result. Only those: the others already beat that point,
// so the extra calibrations are spent where a hypothesis contradicts its own nesting. A delay, which
// nothing switches off, is refined again from the file's values instead (delay_from_file_start).
// Returns whether any was refined.
bool refine_worse_than_the_baseline(const Context& c, const HypothesisSearch& h, Round& r) {
  std::vector<std::size_t> which;
  std::vector<ToRefine> again;
  std::string names, delays;
  auto add = [&](std::size_t i, Eigen::VectorXd start, std::string& to) {
    const Candidate& cand = r.list[i - 1]->candidate;
    which.push_back(i);
    again.push_back({&cand, {std::move(start)}});
    to += (to.empty() ? "" : ", ") + cand.effect + " (" + cand.equation + ")";
  };
  for (std::size_t i = 1; i < r.trials.size(); ++i) {
    const Trial& t = r.trials[i];
    if (t.ok && t.cost <= r.cost_cur) continue;
    if (auto start = switched_off_start(r.list[i - 1]->candidate, h.current)) add(i, std::move(*start), names);
    else if (auto from_file = delay_from_file_start(r.list[i - 1]->candidate, c.model)) add(i, std::move(*from_file), delays);
  }
  if (again.empty()) return false;
  if (!names.empty()) c.say("  refining again from the current model's optimum, switched off (ended worse than it): " + names);
  if (!delays.empty()) c.say("  refining again from the file's values (a delay, ended worse than the current model): " + delays);
  refine_again(c, h, which, again, "", r);
  refine_delays_of_failed_pairs(c, h, which, r);
  return true;
}

namespace {

// The share of pair `t`'s misfit that its member `k` removes: its cost with that member switched off
// against its own; NaN where the member cannot be switched off.
double member_share(const Trial& t, std::size_t k) {
  const double off = t.part_neutral[k];
  return std::isfinite(off) && off > 0 ? (off - t.cost) / off : kNaN;
}

}  // namespace

// A pair one of whose members does nothing at the pair's optimum (switching it off costs less than
// the own-term share) found the other member alone. When that fits better than the member's own
// trial (or it had none), the pair reached a point the member's own starts missed (e.g. a delay
// whose starts stopped in another basin): the member is refined again from the pair's optimum and
// judged as itself, beside its earlier trial (the two can differ on validation; 5 000 932).
void refine_members_of_nil_pairs(const Context& c, const HypothesisSearch& h, double min_own_term, Round& r, Diagnosis& d) {
  std::vector<const ScreenedHypothesis*> again;  // each once, with every pair's optimum as a start
  std::vector<ToRefine> to_refine;
  for (std::size_t i = 1; i < r.trials.size(); ++i) {
    const Trial& t = r.trials[i];
    if (!t.ok || t.part_neutral.size() != 2) continue;
    for (std::size_t k = 0; k < 2; ++k) {
      const Candidate& kept = t.cand.parts[1 - k];
      if (!(member_share(t, k) < min_own_term) || member_share(t, 1 - k) < min_own_term) continue;  // NaN: cannot be switched off
      const ScreenedHypothesis* alone = screened_alone(r.screening, kept);
      if (!alone) continue;
      // Refined alone already, to a point that fits at least as well: nothing was missed.
      const auto listed = std::find(r.list.begin(), r.list.end(), alone);
      if (listed != r.list.end()) {
        const Trial& own = r.trials[static_cast<std::size_t>(listed - r.list.begin()) + 1];
        if (own.ok && own.cost <= t.part_neutral[k]) continue;
      }
      auto at = static_cast<std::size_t>(std::find(again.begin(), again.end(), alone) - again.begin());
      if (at == again.size()) {
        again.push_back(alone);
        to_refine.push_back({&alone->candidate, {}});
      }
      to_refine[at].starts.push_back(values_of(mapped_by_role(alone->candidate, kept, t.model)));
    }
  }
  if (again.empty()) return;
  std::string names;
  for (const auto* alone : again) names += (names.empty() ? "" : ", ") + alone->candidate.effect + " (" + alone->candidate.equation + ")";
  c.say("  refining from a pair's optimum where its other member does nothing: " + names);
  std::vector<Trial> trials = refine(c, to_refine, h.known_scales);
  d.hypotheses_refined += static_cast<int>(trials.size());
  for (std::size_t n = 0; n < trials.size(); ++n) {
    if (!trials[n].ok) continue;
    trials[n].screening_gain = again[n]->gain;
    r.list.push_back(again[n]);
    r.trials.push_back(std::move(trials[n]));
  }
}

namespace {

// `effect` at `equation` (a delay: of `samples`) among `cands`, if there.
const Candidate* find_candidate(const std::vector<Candidate>& cands, const std::string& effect, const std::string& equation,
                                int samples) {
  for (const auto& k : cands)
    if (k.parts.empty() && k.effect == effect && k.equation == equation && k.delay_samples == samples) return &k;
  return nullptr;
}

// The pair of `special`'s members with member `j` replaced by the one-effect law `richer` at its
// place, built on `current` as screening builds pairs (pair_on).
std::optional<Candidate> richer_pair(const Context& c, const std::vector<Candidate>& on_current, const Candidate& special,
                                     std::size_t j, const std::string& richer) {
  const Candidate &a = special.parts[0], &b = special.parts[1];
  const Candidate* first = j == 0 ? find_candidate(on_current, richer, a.equation, 0)
                                  : find_candidate(on_current, a.effect, a.equation, a.delay_samples);
  if (!first) return {};
  return pair_on(c, *first, [&](const std::vector<Candidate>& on_first) {
    return j == 1 ? find_candidate(on_first, richer, b.equation, 0) : find_candidate(on_first, b.effect, b.equation, b.delay_samples);
  });
}

}  // namespace

// A pair (two effects at once) whose member is the special case of a richer law (Coulomb friction
// beside a dead zone) is refined in its own context, but the richer law only alone, beside the
// current model that still misses the other effect: there the richer law's extra term is fitted
// against what the missing effect leaves, and it did not beat its special case (development
// 5 002 724, Stribeck friction and a dead zone: the pair Coulomb + dead zone named, Stribeck then
// excluded as one friction law per place). So each pair that beats the current model and has
// such a member is refined once more with that member replaced by the richer law switched on
// at the pair's optimum (pair_switched_on_start): one start, the richer pair's own basin, as for
// one effect. The richer pair is then judged by the nested rule against the pair it contains
// (judge_round): named only where its extra parameters remove >= 10 % of that pair's misfit, more
// than the noise could, and the data exclude the special case. Only pairs both of whose members
// matter at the pair's optimum (own-term share >= the rule's): where the other member does nothing
// the pair is its special case alone, whose richer law is refined alone already, and the richer
// pair's extra freedom let the idle member fit with it what the law alone should (the fixed suite's
// Stribeck plant: Coulomb + cubic stiffness, the cubic at 2 %, became Stribeck + cubic stiffness).
void refine_richer_pairs(const Context& c, const HypothesisSearch& h, double min_own_term, Round& r, Diagnosis& d) {
  std::vector<Candidate> on_current;
  try {
    on_current = generate_candidates(h.current, r.current_simulation, c.estimation);
  } catch (const std::exception&) {
    return;
  }
  std::deque<Candidate> pairs;  // stable addresses for ToRefine
  std::vector<ToRefine> to_refine;
  std::vector<std::size_t> from;  // the special pair's trial
  for (std::size_t i = 1; i < r.trials.size(); ++i) {
    const Trial& t = r.trials[i];
    if (!t.ok || t.cand.parts.size() != 2 || !(t.cost < r.cost_cur)) continue;
    if (member_share(t, 0) < min_own_term || member_share(t, 1) < min_own_term) continue;  // NaN: cannot be switched off, matters
    for (std::size_t j = 0; j < 2; ++j)
      for (const auto& e : physics_catalogue())
        for (const auto& sc : e.special_cases) {
          if (sc.effects != std::vector<std::string>{t.cand.parts[j].effect}) continue;
          try {
            std::optional<Candidate> p = richer_pair(c, on_current, t.cand, j, e.name);
            if (!p) continue;
            std::optional<Eigen::VectorXd> start = pair_switched_on_start(c, *p, t, j);
            if (!start) continue;
            pairs.push_back(std::move(*p));
            to_refine.push_back({&pairs.back(), {std::move(*start)}});
            from.push_back(i);
          } catch (const std::exception&) {
          }
        }
  }
  if (to_refine.empty()) return;
  std::string names;
  for (const auto& x : to_refine) names += (names.empty() ? "" : ", ") + x.cand->effect + " (" + x.cand->equation + ")";
  c.say("  refining pairs with a member switched on as its richer law: " + names);
  std::vector<Trial> trials = refine(c, to_refine, h.known_scales);
  d.hypotheses_refined += static_cast<int>(trials.size());
  for (std::size_t n = 0; n < trials.size(); ++n) {
    if (!trials[n].ok) continue;
    ScreenedHypothesis sh;
    sh.candidate = trials[n].cand;
    sh.gain = r.list[from[n] - 1]->gain;
    r.built.push_back(std::move(sh));
    trials[n].screening_gain = r.built.back().gain;
    r.list.push_back(&r.built.back());
    r.trials.push_back(std::move(trials[n]));
  }
}

// A richer hypothesis contains each special case of it: it must never end worse than one
// calibrated in the same round. It can: its starts were taken before that special case's optimum
// was found (5 002 818: Coulomb friction reached 29.6 % of the misfit from a pair's optimum where
// the hysteresis does nothing, after the Stribeck law had been refined from Coulomb's own 33.5 %
// and ended at 31.5 %; named Coulomb), or a richer pair was refined from its switched-on start
// alone. Each richer hypothesis that ends worse than a special case of it (or could not be
// calibrated) is refined once more from the best such special case's optimum
// (starts_from_special_case) and keeps the better result; the extra calibrations are spent only
// where a hypothesis contradicts its own nesting.
void refine_richer_below_special_cases(const Context& c, const HypothesisSearch& h, Round& r) {
  std::vector<std::size_t> which;
  std::vector<ToRefine> again;
  for (std::size_t i = 1; i < r.trials.size(); ++i) {
    const Trial& t = r.trials[i];
    const Trial* best = nullptr;
    for (std::size_t j = 1; j < r.trials.size(); ++j) {
      const Trial& s = r.trials[j];
      if (j == i || !s.ok || !(s.cost < (t.ok ? t.cost : inf)) || (best && best->cost <= s.cost)) continue;
      if (nests(r.list[i - 1]->candidate, s.cand)) best = &s;
    }
    if (!best) continue;
    std::vector<Eigen::VectorXd> starts = starts_from_special_case(c, r.list[i - 1]->candidate, *best);
    if (starts.empty()) continue;
    which.push_back(i);
    again.push_back({&r.list[i - 1]->candidate, std::move(starts)});
  }
  if (!again.empty()) refine_again(c, h, which, again, "refining again from a special case's optimum that fits better", r);
}

namespace {

// The trial `t` (a delay alone, or a pair with one) with its delay at the whole number of samples
// between the grid's neighbours that fits best at its optimum (one simulation each); its own number
// when that fits best, or when it has no delay.
int best_delay_at_optimum(const Context& c, const Trial& t) {
  Candidate at_optimum = t.cand;
  at_optimum.model = t.model;
  int best = at_optimum.delay_samples;
  double best_cost = kNaN;
  const std::vector<Candidate> parts = parts_of(at_optimum);
  for (const Candidate& part : parts) {
    if (part.effect != "time_delay") continue;
    for (int n : delays_around(part.delay_samples, c.exact.samples())) {
      try {
        const ModelFile m = with_delay_samples(at_optimum, n).model;
        const CalibrationResult r = evaluate(Simulator(m, c.estimation, {c.options.screening_substeps}), values_of(m));
        if (r.ok && !(r.cost >= best_cost)) best = n, best_cost = r.cost;
      } catch (const std::exception&) {
      }
    }
  }
  return best;
}

// One calibration of refine_delay_numbers: the round's trial `trial` refined as `target` from `starts`.
struct DelayMove {
  std::size_t trial;
  Candidate target;
  std::vector<Eigen::VectorXd> starts;
};

// Trial `i` with its delay moved to `n` samples, started from its optimum there and from n's
// screening start; a delay alone also from the nominal's own start (delay_from_file_start): the
// current model's parameters were calibrated against the missing delay, and their basin can hold
// the delay's calibration (5 004 216: a delay at its true number calibrated from there leaves 4
// times the noise's misfit, from the file's values the noise's).
DelayMove move_to(const Context& c, std::size_t i, const Trial& t, int n) {
  Candidate at_optimum = t.cand;
  at_optimum.model = t.model;
  DelayMove m{i, with_delay_samples(t.cand, n), {}};
  if (n != t.cand.delay_samples) m.starts = {values_of(with_delay_samples(at_optimum, n).model), values_of(m.target.model)};
  if (t.cand.parts.empty())
    if (auto from_file = delay_from_file_start(m.target, c.model)) m.starts.push_back(std::move(*from_file));
  return m;
}

// Calibrates every move; a trial keeps a result that fits better than it. Returns the trials whose
// delay changed number.
std::vector<std::size_t> apply_moves(const Context& c, const HypothesisSearch& h, const std::deque<DelayMove>& moves, Round& r) {
  std::vector<ToRefine> to_refine;
  for (const auto& m : moves) to_refine.push_back({&m.target, m.starts});
  const std::vector<Trial> moved = to_refine.empty() ? std::vector<Trial>{} : refine(c, to_refine, h.known_scales);
  std::vector<std::size_t> renumbered;
  for (std::size_t k = 0; k < moves.size(); ++k) {
    Trial& t = r.trials[moves[k].trial];
    if (!moved[k].ok || moved[k].cost >= t.cost) continue;
    if (moved[k].cand.delay_samples != t.cand.delay_samples &&
        std::find(renumbered.begin(), renumbered.end(), moves[k].trial) == renumbered.end())
      renumbered.push_back(moves[k].trial);
    const double gain = t.screening_gain;
    t = moved[k];
    t.screening_gain = gain;
  }
  return renumbered;
}

}  // namespace

// A delay competes at its best whole number of samples, as every other law competes at its
// calibrated optimum: the screening grid (1, 2, 3, 4, 6, 8, 11, ...) is coarse, and beside a delay
// one grid step off another law fits the step's error (5 001 140: a delay of 5 samples screened at
// 4 or 6, an offset beside it, and the pair was named). Each hypothesis with a delay is moved to
// the whole number between its grid neighbours that fits best at its own optimum
// (best_delay_at_optimum) and calibrated there, from that optimum and from its screening start;
// kept when it fits better. A delay alone is also tried at the number the screening at the current
// model ranks first (best_delay). Alone and in a pair alike: were only the pair's delay moved, the
// pair would be judged against a delay alone a number or more off, or stuck in the current model's
// basin, and its partner named for fitting the difference (development 5 004 216, a delay of 5
// samples: alone 1.0 % of the misfit, with a viscous friction 0.2 %, the noise's; the friction was
// named. 5 004 170 and 222 likewise with an offset). Where the round refines no delay alone, a
// pair's delay otherwise stays a grid step off (development plant 5 003 764: a delay of 39 samples beside an output
// saturation, refined at 32 in every pair; at 38 the pair with the output saturation removes
// 95 % of the misfit instead of 88 %, the pair with an offset 98 % instead of 90 %).
void refine_delay_numbers(const Context& c, const HypothesisSearch& h, const std::vector<double>& bound, Round& r) {
  std::deque<DelayMove> moves;
  std::map<std::size_t, std::set<int>> tried;
  for (std::size_t i = 1; i < r.trials.size(); ++i) {
    const Trial& t = r.trials[i];
    const bool alone = t.cand.parts.empty() && t.cand.effect == "time_delay";
    if (!t.ok || (!alone && t.cand.parts.empty())) continue;
    const int n = best_delay_at_optimum(c, t);
    if (alone || n != t.cand.delay_samples) moves.push_back(move_to(c, i, t, n));
    if (!alone) continue;
    tried[i] = {t.cand.delay_samples, n};
    const int screened = best_delay(c, h.current, t.cand, bound).delay_samples;  // at the current model
    if (tried[i].insert(screened).second) moves.push_back(move_to(c, i, t, screened));
  }
  std::vector<std::size_t> walking = apply_moves(c, h, moves, r);
  // A delay alone moved to a new number walks on from there, at its new optimum, whose other
  // parameters no longer fit the old number: the best number simulated there, or else its two
  // neighbours calibrated, until neither fits better (5 004 170: 45 -> 43 -> 42 -> 41 -> 40, the
  // truth). The misfit falls at every step, and no number is calibrated twice.
  while (!walking.empty()) {
    moves.clear();
    for (std::size_t i : walking) {
      const Trial& t = r.trials[i];
      if (!t.cand.parts.empty()) continue;
      const int n = best_delay_at_optimum(c, t);
      if (tried[i].insert(n).second) {
        moves.push_back(move_to(c, i, t, n));
        continue;
      }
      for (int step : {-1, 1})
        if (const int m = t.cand.delay_samples + step; m >= 1 && m < c.exact.samples() / 10 && tried[i].insert(m).second)
          moves.push_back(move_to(c, i, t, m));
    }
    walking = apply_moves(c, h, moves, r);
  }
}

}  // namespace sets::diagnosis_stage
