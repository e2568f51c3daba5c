// Tests of src/diagnosis/refine_again.cpp: hypotheses whose first refinement ended in the wrong
// basin refined again from other starts.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "diagnosis/hypothesis_search.hpp"
#include "sets/diagnosis/calibration.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/examples/random_plants.hpp"
#include "sets/models/model_file.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"
#include "support/plant_fixtures.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

// A hypothesis adds a term to the current model, so it cannot end worse than it: one that did (its
// trial here made worse by hand) is refined again from the current model with its term switched
// off, and ends no worse than that model; one that already beat it is left as it was.
TEST(RefineAgain, HypothesisThatEndedWorseThanTheModelItNestsIsRefinedFromThatModel) {
  test::StageRun s(synthetic_plant("coulomb_friction"), true, 800);
  HypothesisSearch h;
  h.current = s.model;
  const std::vector<Candidate> cs = generate_candidates(h.current, s.fast->simulate(values_of(h.current)), s.estimation);
  std::vector<ScreenedHypothesis> screened;
  for (const auto& c : cs)
    if (c.parts.empty() && (c.effect == "coulomb_friction" || c.effect == "constant_offset") && screened.size() < 2) {
      screened.emplace_back();
      screened.back().candidate = c;
    }
  ASSERT_EQ(screened.size(), 2u);
  Round r;
  r.cost_cur = evaluate(*s.fast, values_of(h.current)).cost;
  r.trials.resize(3);
  r.trials[0].ok = true;
  r.trials[0].cost = r.cost_cur;
  for (std::size_t i = 0; i < 2; ++i) {
    r.list.push_back(&screened[i]);
    r.trials[i + 1].cand = screened[i].candidate;
    r.trials[i + 1].ok = true;
    r.trials[i + 1].model = screened[i].candidate.model;
  }
  r.trials[1].cost = 7 * r.cost_cur;    // ended worse than the model it nests
  r.trials[2].cost = 0.5 * r.cost_cur;  // already beat it
  ASSERT_TRUE(refine_worse_than_the_baseline(s.c(), h, r));
  EXPECT_TRUE(r.trials[1].ok);
  EXPECT_LE(r.trials[1].cost, r.cost_cur * (1 + 1e-12));
  EXPECT_EQ(r.trials[2].cost, 0.5 * r.cost_cur);
  r.trials[1].cost = 0.9 * r.cost_cur;  // now nothing is worse than the baseline: nothing to do
  EXPECT_FALSE(refine_worse_than_the_baseline(s.c(), h, r));
}

// A delay alone competes at its best whole number of samples, as a pair with a delay does: on
// these two delay-only plants the pair's delay reached the true number while the delay alone
// stayed a number or more off, and the pair's partner was named for fitting the difference (main
// 77bd0dd: 5 004 216, 5 samples, alone stuck in the current model's basin, named with a viscous
// friction; 5 004 170, 40 samples, reached 43 from the grid's 45, named with an offset). Now the
// delay alone is also calibrated from the file's values and walks on from a new number: only the
// delay is named, at the true number. (Seeds of the seventeenth held-out range, development since.)
TEST(RefineAgain, DelayAloneReachesTheTrueNumberAndNoPartnerIsNamed) {
  for (unsigned seed : {5004216u, 5004170u}) {
    const SyntheticPlant plant = random_plant(seed);
    ASSERT_EQ(plant.effects.size(), 1u);
    ASSERT_EQ(plant.effects[0].name, "time_delay");
    const std::string truth = to_json_text(plant.truth);
    const Diagnosis d = test::diagnosed(plant);
    ASSERT_EQ(d.effects.size(), 1u) << "seed " << seed << ": a partner named beside the delay";
    EXPECT_EQ(d.effects[0].name, "time_delay");
    EXPECT_NE(truth.find("prev(" + d.effects[0].equation + ", " + std::to_string(d.effects[0].delay_samples) + ")"),
              std::string::npos)
        << "seed " << seed << ": delay of " << d.effects[0].delay_samples << " samples";
  }
}
