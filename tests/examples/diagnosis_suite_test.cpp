// The fixed-seed CI slice of the randomised plant suite (issue 14): the first three plants of the
// development seed range (3 000 000 on, looked at while the rules were chosen; the reported
// figures come from the held-out range 5 000 000 on, docs/reproduction/diagnosis.md). One test
// per plant, so that each stays short. A slice this small says nothing about rates (those are the
// benchmark's: `sets-diagnose --suite random`); it asserts what must hold on every plant: the
// diagnosis completes, a clean plant gets no invented effect, and a concealed effect (drawn strong
// enough to matter) is never answered with "no physics is missing".

#include <gtest/gtest.h>

#include "sets/examples/diagnosis_suite.hpp"
#include "sets/examples/random_plants.hpp"

using namespace sets;

class RandomSuiteSlice : public ::testing::TestWithParam<unsigned> {};

TEST_P(RandomSuiteSlice, CompletesInventsNothingAndMissesNoConcealedEffect) {
  const SyntheticPlant p = random_plant(GetParam());
  DiagnosisOptions o;
  o.threads = 2;
  const SuitePlantResult r = run_suite_plant(p, o);
  std::string truth, named;
  for (const auto& t : r.truth) truth += t.name + " ";
  for (const auto& n : r.named) named += n + " ";
  SCOPED_TRACE(p.name + " (" + p.family + "): true " + truth + "named " + named + "answer " + r.answer);
  ASSERT_TRUE(r.error.empty()) << r.error;
  if (r.truth.empty()) {
    EXPECT_TRUE(r.named.empty());
  } else {
    EXPECT_NE(r.answer, "nothing_missing");
  }
  ASSERT_EQ(r.noise_ratio.size(), p.nominal.outputs.size());
  for (double q : r.noise_ratio) EXPECT_GT(q, 0.0);
}

// Seed 3000003, the fourth, is left out while GLPK can abort the process: an internal assertion
// (spxprim.c "teta_lim >= 0.0") in an LP of the tv_bound jump search that the varying-parameter
// stage calls, depending on the run (the search has a 10 s guard); no error hook turns it into an
// exception yet (GUIDE: known traps).
INSTANTIATE_TEST_SUITE_P(DevelopmentSeeds, RandomSuiteSlice, ::testing::Range(3000000u, 3000003u));
