// Tests of src/diagnosis/refine_trials.cpp: each hypothesis calibrated by output error from its
// starts, the best kept, and its cost with its own term switched off.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "diagnosis/hypothesis_search.hpp"
#include "sets/diagnosis/calibration.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

namespace {

const Candidate* find(const std::vector<Candidate>& cs, const std::string& effect) {
  for (const auto& c : cs)
    if (c.parts.empty() && c.effect == effect) return &c;
  return nullptr;
}

// Two starts of `cand`: its screening value and its new parameters at three times their scale.
std::vector<Eigen::VectorXd> two_starts(const Candidate& cand) {
  ModelFile far = cand.model;
  for (std::size_t k = 0; k < cand.parameters.size(); ++k) far.parameter(cand.parameters[k])->value = 3 * cand.scales[k];
  return {values_of(cand.model), values_of(far)};
}

}  // namespace

TEST(RefineTrials, NoHypothesisEndsWorseThanItsBestStartAndItsOwnTermMatters) {
  test::StageRun s(synthetic_plant("coulomb_friction"), true, 800);
  const std::vector<Candidate> cs = generate_candidates(s.model, s.fast->simulate(values_of(s.model)), s.estimation);
  const Candidate* coulomb = find(cs, "coulomb_friction");
  ASSERT_NE(coulomb, nullptr);
  const std::vector<Eigen::VectorXd> starts = two_starts(*coulomb);
  const std::vector<Trial> t = refine(s.c(), {{coulomb, starts}}, {});
  ASSERT_EQ(t.size(), 1u);
  ASSERT_TRUE(t[0].ok);
  const Simulator sim(coulomb->model, s.estimation, {s.options.screening_substeps});
  for (const auto& p : starts) {
    const CalibrationResult at = evaluate(sim, p);
    if (at.ok) {
      EXPECT_LE(t[0].cost, at.cost);
    }
  }
  // On a Coulomb plant, Coulomb's own term switched off at its optimum fits worse, on both records.
  EXPECT_GT(t[0].cost_neutral, t[0].cost);
  EXPECT_TRUE(std::isfinite(t[0].cost_val));
}

// Every (hypothesis, start) pair is one job of the worker pool; the result must be the serial one.
TEST(RefineTrials, TwoThreadsGiveTheSerialResult) {
  test::StageRun s(synthetic_plant("coulomb_friction"), true, 800);
  const std::vector<Candidate> cs = generate_candidates(s.model, s.fast->simulate(values_of(s.model)), s.estimation);
  std::vector<ToRefine> hypotheses;
  for (const char* e : {"coulomb_friction", "constant_offset", "cubic_stiffness"})
    if (const Candidate* c = find(cs, e)) hypotheses.push_back({c, two_starts(*c)});
  ASSERT_GE(hypotheses.size(), 2u);
  s.options.threads = 1;
  const std::vector<Trial> serial = refine(s.c(), hypotheses, {});
  s.options.threads = 2;
  const std::vector<Trial> pooled = refine(s.c(), hypotheses, {});
  ASSERT_EQ(serial.size(), pooled.size());
  for (std::size_t i = 0; i < serial.size(); ++i) {
    EXPECT_EQ(serial[i].ok, pooled[i].ok) << serial[i].cand.effect;
    EXPECT_EQ(serial[i].cost, pooled[i].cost) << serial[i].cand.effect;
    if (serial[i].ok) {
      EXPECT_EQ(values_of(serial[i].model), values_of(pooled[i].model)) << serial[i].cand.effect;
    }
  }
}

// A delay paired with a second effect at the same input (an input saturation written on the
// delayed model rewires prev(u, n) into prev(u_sat, n)): switching the delay off alone must still
// take it out. Before, the delay's term was looked for as written before the rewiring, nothing
// was switched off and the delay's own share of the pair read 0 (the pair failed own_term).
TEST(RefineTrials, DelaySwitchedOffInAPairWithALawAtTheSameInput) {
  test::StageRun s(synthetic_plant("time_delay"), true, 800);
  const std::vector<Candidate> cs = generate_candidates(s.model, s.fast->simulate(values_of(s.model)), s.estimation);
  const Candidate* delay = nullptr;
  for (const auto& c : cs)
    if (c.effect == "time_delay" && (!delay || std::abs(c.delay_samples - 12) < std::abs(delay->delay_samples - 12))) delay = &c;
  ASSERT_NE(delay, nullptr);
  const Simulator on_delay(delay->model, s.estimation, {s.options.screening_substeps});
  const std::vector<Candidate> second = generate_candidates(delay->model, on_delay.simulate(values_of(delay->model)), s.estimation);
  const Candidate* saturation = nullptr;
  for (const auto& c : second)
    if (c.effect == "input_saturation" && c.equation == delay->equation) saturation = &c;
  ASSERT_NE(saturation, nullptr);
  const Candidate pair = combine_candidates(*delay, *saturation);
  const std::vector<Trial> t = refine(s.c(), {{&pair, {values_of(pair.model)}}}, {});
  ASSERT_EQ(t.size(), 1u);
  ASSERT_TRUE(t[0].ok);
  ASSERT_EQ(t[0].part_neutral.size(), 2u);
  // On a plant with a 12-sample delay, the pair without its delay fits worse than the pair.
  EXPECT_GT(t[0].part_neutral[0], 1.01 * t[0].cost);
}
