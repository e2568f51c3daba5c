// Stage 3 of the diagnosis, a richer law at the step it needs: the screening step is chosen on the
// nominal, which has no law that switches at a velocity's sign; a law that sticks (Stribeck: Fc + Fs
// at rest, Fc in motion) chatters under RK4 by about one step's force over the mass, and where that
// is not small against the law's own velocity scale the law is not itself at the screening step.

#include <algorithm>
#include <map>
#include <set>

#include "diagnosis/hypothesis_search.hpp"

namespace sets::diagnosis_stage {

namespace {

// `richer` switched on at the optimum of its special case `special` (one effect, or a pair whose
// other member is the same effect at the same place): the points where its extra term acts.
std::vector<Eigen::VectorXd> switched_on_starts(const Context& c, const Candidate& richer, const Trial& special) {
  std::vector<Eigen::VectorXd> on;
  if (richer.parts.empty()) {
    if (special.cand.parts.empty())
      if (auto p = switched_on_start(c, richer, special)) on.push_back(std::move(*p));
    return on;
  }
  for (std::size_t j = 0; j < richer.parts.size() && special.cand.parts.size() == 2; ++j)
    if (auto p = pair_switched_on_start(c, richer, special, j)) on.push_back(std::move(*p));
  return on;
}

// The nominal's own test (the fewest substeps whose fits agree with the final ones) at `p`.
int step_needed(const Context& c, const ModelFile& model, const Eigen::VectorXd& p) {
  try {
    const Simulator exact(model, c.estimation, {c.options.final_substeps});
    return screening_substeps(model, c.estimation, exact, p, c.options.final_substeps, c.options.screening_substeps);
  } catch (const std::exception&) {
    return c.options.screening_substeps;
  }
}

}  // namespace

// Random plant 5 004 303 (Stribeck, 56 noise levels): the truth's structure fits at 1 substep
// (the screening's) to 47.8 % of the nominal's misfit, Coulomb friction to 32.0 %; at 10 substeps
// to 1.2 % against 26.8 %. At a coarse optimum the law is off (Fs near 0) and shows nothing, so each
// richer law is tested where it is on: switched on at each special case's optimum in the round.
// Where the test asks for a finer step, the law, those special cases and every other law nesting
// them are refined again at the final step — from their optima, the law also from its
// switched-on starts — so that the nested rule compares them at one step; each keeps the result
// at that step (the truer number) when it can be computed.
void refine_at_the_step_laws_need(const Context& c, const HypothesisSearch& h, Round& r) {
  if (c.options.screening_substeps >= c.options.final_substeps) return;
  std::map<std::size_t, std::vector<Eigen::VectorXd>> group;  // trial -> its starts at the finer step
  const std::size_t n = r.trials.size();
  for (std::size_t i = 1; i < n; ++i) {
    if (!r.trials[i].ok) continue;
    for (std::size_t j = 1; j < n; ++j) {
      if (j == i || !r.trials[j].ok || !nests(r.list[i - 1]->candidate, r.trials[j].cand)) continue;
      std::vector<Eigen::VectorXd> on = switched_on_starts(c, r.list[i - 1]->candidate, r.trials[j]);
      if (std::none_of(on.begin(), on.end(), [&](const Eigen::VectorXd& p) {
            return step_needed(c, r.list[i - 1]->candidate.model, p) > c.options.screening_substeps;
          }))
        continue;
      auto& starts = group[i];
      starts.insert(starts.end(), on.begin(), on.end());
      group[j];
    }
  }
  if (group.empty()) return;
  // Every other law nesting a special case in the group is compared with it: at the same step.
  for (std::size_t i = 1; i < n; ++i)
    for (std::size_t j = 1; j < n && r.trials[i].ok && !group.count(i); ++j)
      if (j != i && group.count(j) && r.trials[j].ok && nests(r.list[i - 1]->candidate, r.trials[j].cand)) group[i];
  std::vector<std::size_t> which;
  std::vector<ToRefine> again;
  std::string names;
  const int step = c.options.final_substeps;
  for (auto& [i, starts] : group) {
    starts.insert(starts.begin(), values_of(r.trials[i].model));
    which.push_back(i);
    again.push_back({&r.list[i - 1]->candidate, std::move(starts), step});
    names += (names.empty() ? "" : ", ") + r.list[i - 1]->candidate.effect + " (" + r.list[i - 1]->candidate.equation + ")";
  }
  c.say("  refining again at " + std::to_string(step) + " RK4 substeps, where a law switched on needs them: " + names);
  const std::vector<Trial> finer = refine(c, again, h.known_scales);
  for (std::size_t k = 0; k < which.size(); ++k) {
    if (!finer[k].ok) continue;
    Trial& t = r.trials[which[k]];
    const double gain = t.screening_gain;
    t = finer[k];
    t.screening_gain = gain;
  }
}

// The picked hypothesis `t` is the current model of the later rounds: when it was refined at a finer
// step, they search around it at the step the nominal's test chooses at its optimum, as the
// screening step was chosen at the calibrated nominal's (the final step for the whole search cost
// 5 004 387 and 383 five times the CPU). A Coulomb plant's Coulomb friction, refined finely beside a
// switched-on Stribeck law, is exact at the screening step at its own optimum (5 004 423).
int step_after_pick(const Context& c, const Trial& t) {
  if (t.substeps <= c.options.screening_substeps) return c.options.screening_substeps;
  return step_needed(c, t.model, values_of(t.model));
}

}  // namespace sets::diagnosis_stage
