// Tests of src/diagnosis/judge_round.cpp: the rules applied to a round's refined hypotheses and
// the sparsest of those that pass picked.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "diagnosis/hypothesis_search.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

namespace {

// A round on the Coulomb plant's nominal with hand-set costs (baseline 1 on both records): one
// trial per effect in `effects` (one place each), trial i + 1 for effects[i].
struct HandRound {
  test::StageRun s{synthetic_plant("coulomb_friction"), true, 600};
  HypothesisSearch h;
  Round r;
  NoiseFloor noise;
  explicit HandRound(const std::vector<std::string>& effects) {
    h.current = s.model;
    r.current_simulation = s.fast->simulate(values_of(h.current));
    const std::vector<Candidate> cs = generate_candidates(h.current, r.current_simulation, s.estimation);
    std::string place;
    for (const auto& c : cs)
      if (c.parts.empty() && c.effect == "coulomb_friction") place = c.equation;
    r.cost_cur = r.cost_cur_val = 1;
    r.trials.resize(1);
    r.trials[0].ok = true;
    r.trials[0].cost = r.trials[0].cost_val = 1;
    for (const auto& e : effects)
      for (const auto& c : cs)
        if (c.parts.empty() && c.effect == e && c.equation == place) {
          Trial t;
          t.cand = c;
          t.model = c.model;
          t.ok = true;
          r.trials.push_back(t);
          break;
        }
    noise.sigma.assign(s.d.outputs.size(), 0.0);
    noise.pole.assign(s.d.outputs.size(), 0.0);
    noise.cost = 1e-3;
  }
  void set(std::size_t i, double cost, double cost_val, double cost_neutral) {
    r.trials[i].cost = cost;
    r.trials[i].cost_val = cost_val;
    r.trials[i].cost_neutral = cost_neutral;
  }
};

}  // namespace

TEST(JudgeRound, OnlyHypothesesThatPassEveryRuleAreAccepted) {
  HandRound x({"coulomb_friction", "constant_offset", "cubic_stiffness"});
  ASSERT_EQ(x.r.trials.size(), 4u);
  x.set(1, 0.3, 0.4, 1.0);    // removes 70 % (60 % on validation), its own term matters
  x.set(2, 0.97, 0.9, 1.0);   // 3 % of the misfit: below the 10 % the rules ask
  x.set(3, 0.3, 1.2, 1.0);    // fits estimation, worse on validation
  judge_round(x.s.c(), x.h, x.noise, AcceptanceRules{}, x.r);
  ASSERT_EQ(x.r.ok.size(), 1u);
  EXPECT_EQ(x.r.ok[0], 1u);
  EXPECT_TRUE(x.r.trials[1].accepted);
  EXPECT_FALSE(x.r.trials[2].accepted);
  EXPECT_FALSE(x.r.trials[3].accepted);
}

// Among laws that passed, the sparsest explanation wins (1.25 of misfit per parameter); but a
// richer law that passed every rule against its own special case is picked over it.
TEST(JudgeRound, SparsestPassingLawIsPickedUnlessARicherOnePassedAgainstIt) {
  HandRound x({"coulomb_friction", "stribeck_friction"});
  ASSERT_EQ(x.r.trials.size(), 3u);
  ASSERT_GT(x.r.trials[2].cand.parameters.size(), x.r.trials[1].cand.parameters.size());
  x.set(1, 0.30, 0.30, 1.0);
  x.set(2, 0.29, 0.29, 1.0);
  x.r.ok = {1};
  auto [pick, best] = pick_sparsest(x.s.c(), x.r);
  EXPECT_EQ(pick, 1u);
  x.r.ok = {1, 2};  // Stribeck passed its nested rule too
  std::tie(pick, best) = pick_sparsest(x.s.c(), x.r);
  EXPECT_EQ(pick, 2u);
  EXPECT_EQ(best, 2u);
}
