// Stage 3 of the diagnosis, after the greedy rounds: a law named as the special case of a richer
// one (Coulomb friction is Stribeck friction with Fs = 0 and asymmetric friction with Fc_pos =
// Fc_neg, dFv = 0; Coulomb friction + an offset is asymmetric friction with dFv = 0) was judged
// against the richer law in the round that named it, beside a model that still missed the effects
// named after it, and one friction law per place kept the richer law out of every later round.
// Once another effect is in the model, that place is judged again in the final model's context.

#include <algorithm>
#include <optional>
#include <set>

#include "diagnosis/hypothesis_search.hpp"

namespace sets::diagnosis_stage {

namespace {

// `m` without the named additive effect `part`: its term as subtract_force wrote it and its
// parameters. Empty when the term is not found as written (the model was changed around it).
std::optional<ModelFile> without(ModelFile m, const Candidate& part) {
  std::string* text = m.derivative(part.equation);
  const PhysicsEffect* e = find_effect(part.effect);
  if (!text || !e || e->placement != "additive") return {};
  for (const std::string& written : {" - (" + part.term + ")", " - " + part.term}) {
    const std::size_t at = text->find(written);
    if (at == std::string::npos) continue;
    text->erase(at, written.size());
    const std::set<std::string> own(part.parameters.begin(), part.parameters.end());
    m.parameters.erase(std::remove_if(m.parameters.begin(), m.parameters.end(), [&](const ModelParameter& q) { return own.count(q.name) > 0; }),
                       m.parameters.end());
    return m;
  }
  return {};
}

// `cand` (built on the model without the named effects `named`) at the final model's point: the
// model's parameters by name, its own by role from the named effect of the same name.
Eigen::VectorXd at_final_point(const Candidate& cand, const std::vector<Candidate>& named, const ModelFile& final_model) {
  ModelFile m = cand.model;
  for (auto& q : m.parameters)
    if (const auto* v = final_model.parameter(q.name)) q.value = v->value;
  for (const Candidate& part : parts_of(cand))
    for (const Candidate& n : named) {
      if (n.effect != part.effect || n.equation != part.equation) continue;
      for (std::size_t k = 0; k < part.parameters.size(); ++k) {
        const auto role = std::find(n.roles.begin(), n.roles.end(), part.roles[k]);
        if (role == n.roles.end()) continue;
        if (const auto* v = final_model.parameter(n.parameters[static_cast<std::size_t>(role - n.roles.begin())]))
          m.parameter(part.parameters[k])->value = v->value;
      }
    }
  return values_of(m);
}

// The named effects that together are a catalogue special case of a richer law at one place: one
// named effect, or two at the same equation; with every richer law of them not already named there.
struct Upgrade {
  std::vector<std::size_t> named;   // indices into h.chosen
  std::vector<std::string> richer;  // effect names
};

std::vector<Upgrade> upgrades_of(const HypothesisSearch& h) {
  std::vector<Upgrade> out;
  const std::size_t n = h.chosen.size();
  auto consider = [&](std::vector<std::size_t> set) {
    std::vector<std::string> effects;
    for (std::size_t k : set) effects.push_back(h.chosen[k].effect);
    if (h.chosen.size() <= set.size()) return;  // no other effect in the model: the round that named it judged this
    Upgrade u{set, {}};
    for (const PhysicsEffect& e : physics_catalogue()) {
      const bool here = std::any_of(h.chosen.begin(), h.chosen.end(), [&](const Candidate& k) {
        return k.effect == e.name && k.equation == h.chosen[set[0]].equation;
      });
      if (!here && find_special_case(effects, e.name)) u.richer.push_back(e.name);
    }
    if (!u.richer.empty()) out.push_back(std::move(u));
  };
  for (std::size_t a = 0; a < n; ++a) {
    consider({a});
    for (std::size_t b = a + 1; b < n; ++b)
      if (h.chosen[b].equation == h.chosen[a].equation) consider({a, b});
  }
  return out;
}

// One place judged again: the final model without the named special case is the current model of
// a round whose hypotheses are that special case (from the final model's point) and its richer
// laws (refined from its optimum, embedded and switched on, by the round's own stages). Returns
// the richer law's trial when the round picks it.
std::optional<Trial> judge_place_again(const Context& c, const HypothesisSearch& h, const NoiseFloor& noise,
                                       const AcceptanceRules& rules, const Upgrade& u, Diagnosis& d) {
  std::vector<Candidate> named;
  std::optional<ModelFile> m0 = h.current;
  for (std::size_t k : u.named) {
    named.push_back(h.chosen[k]);
    if (m0) m0 = without(*m0, h.chosen[k]);
  }
  if (!m0) return {};
  const std::string& place = named.front().equation;
  Round r;
  r.index = static_cast<int>(h.chosen.size());
  std::vector<Candidate> cands;
  try {
    const Simulator s(*m0, c.estimation, {c.options.screening_substeps});
    r.current_simulation = s.simulate(values_of(*m0));
    if (!r.current_simulation.outputs.allFinite()) return {};
    cands = generate_candidates(*m0, r.current_simulation, c.estimation);
  } catch (const std::exception&) {
    return {};
  }
  auto find = [&](const std::vector<Candidate>& in, const std::string& effect) -> const Candidate* {
    for (const auto& k : in)
      if (k.parts.empty() && k.effect == effect && k.equation == place) return &k;
    return nullptr;
  };
  std::optional<Candidate> special;
  if (const Candidate* first = find(cands, named[0].effect); first && named.size() == 1) special = *first;
  else if (first)
    special = pair_on(c, *first, [&](const std::vector<Candidate>& on_first) { return find(on_first, named[1].effect); });
  if (!special) return {};
  auto list = [&](const Candidate& k, Eigen::VectorXd start) {
    ScreenedHypothesis sh;
    sh.candidate = k;
    sh.starts = {std::move(start)};
    r.built.push_back(std::move(sh));
    r.list.push_back(&r.built.back());
  };
  list(*special, at_final_point(*special, named, h.current));
  for (const std::string& e : u.richer)
    if (const Candidate* k = find(cands, e)) list(*k, values_of(k->model));
  if (r.list.size() < 2) return {};
  HypothesisSearch h0 = h;
  h0.current = *m0;
  c.say("after the rounds: " + named.front().effect + (named.size() > 1 ? " + " + named[1].effect : "") + " (" + place +
        ") judged again against its richer laws beside every other effect named");
  refine_round(c, h0, r, d);
  refine_richer_below_special_cases(c, h0, r);
  refine_at_the_step_laws_need(c, h0, r);
  judge_round(c, h0, noise, rules, r);
  say_round(c, r);
  if (r.ok.empty()) return {};
  const std::size_t pick = pick_sparsest(c, r).first;
  if (!r.trials[pick].cand.parts.empty() || !nests(r.trials[pick].cand, *special)) return {};
  Trial t = r.trials[pick];
  t.not_beyond = r.beats.count(pick) ? r.beats.at(pick) : std::string();
  return t;
}

// The named special case replaced by the richer law `t` in the search and the diagnosis (the
// first named member's entry takes it; a second member's entry goes).
void replace(const Context& c, const Trial& t, const Upgrade& u, const std::string& was, HypothesisSearch& h, Diagnosis& d) {
  DiagnosedEffect& e = d.effects[u.named[0]];
  e.name = t.cand.effect;
  e.term = t.cand.term;
  e.placement = find_effect(e.name)->placement;
  e.rules = t.rules;
  e.cost_reduction_estimation = t.rules[0].value;
  e.cost_reduction_validation = t.rules[3].applies ? t.rules[3].value : 0;
  e.equally_good.clear();  // they were alternatives to the law replaced
  e.evidence = "in place of " + was + " named earlier: judged again beside every other effect named, adding " + t.cand.term +
               " to " + t.cand.equation + " removes " + fixed1(100 * e.cost_reduction_estimation) +
               " % of the squared misfit the final model without it leaves" +
               (c.validation ? " and " + fixed1(100 * e.cost_reduction_validation) + " % on validation" : std::string()) +
               (t.not_beyond.empty() ? "" : "; preferred to " + t.not_beyond + ", its special case, by the same rules");
  for (std::size_t q = 0; q < t.cand.parameters.size(); ++q) h.known_scales.emplace_back(t.cand.parameters[q], t.cand.scales[q]);
  h.chosen[u.named[0]] = t.cand;
  for (std::size_t k = u.named.size(); k-- > 1;) {
    h.chosen.erase(h.chosen.begin() + static_cast<std::ptrdiff_t>(u.named[k]));
    d.effects.erase(d.effects.begin() + static_cast<std::ptrdiff_t>(u.named[k]));
  }
  h.current = t.model;
  c.say("  " + e.name + " (" + e.equation + ") in place of " + was);
}

}  // namespace

void upgrade_named_laws(const Context& c, HypothesisSearch& h, const NoiseFloor& noise, const AcceptanceRules& rules, Diagnosis& d) {
  if (d.effects.size() != h.chosen.size()) return;
  std::set<std::string> judged;  // each named set once (an upgrade moves the indices: the rest again)
  for (bool moved = true; moved;) {
    moved = false;
    for (const Upgrade& u : upgrades_of(h)) {
      std::string was;
      for (std::size_t k : u.named) was += (was.empty() ? "" : " + ") + h.chosen[k].effect;
      if (!judged.insert(was + " in " + h.chosen[u.named[0]].equation).second) continue;
      const std::optional<Trial> t = judge_place_again(c, h, noise, rules, u, d);
      if (!t) continue;
      replace(c, *t, u, was, h, d);
      moved = true;
      break;
    }
  }
}

}  // namespace sets::diagnosis_stage
