// The fixed-seed CI slice of the randomised plant suite (issue 14: a fixed 40-plant subset in CI):
// the first forty plants of the development seed range (3 000 000 on, looked at while the rules
// were chosen; the reported figures come from the held-out ranges 5 000 000 on,
// docs/reproduction/diagnosis.md). One test per plant, so that each stays short and ctest runs
// them side by side. A slice this small says nothing about rates (those are the benchmark's:
// `sets-diagnose --suite random`); it asserts what must hold on every plant: the diagnosis
// completes, a clean plant gets no invented effect, and a concealed effect (drawn strong enough to
// matter) is never answered with "no physics is missing".

#include <gtest/gtest.h>

#include "sets/examples/diagnosis_suite.hpp"
#include "sets/examples/random_plants.hpp"

using namespace sets;

namespace {

// A plant of the suite diagnosed as the slice runs it: on two threads.
SuitePlantResult diagnosis_of(const SyntheticPlant& p) {
  DiagnosisOptions o;
  o.threads = 2;
  return run_suite_plant(p, o);
}

}  // namespace

class RandomSuiteSlice : public ::testing::TestWithParam<unsigned> {};

TEST_P(RandomSuiteSlice, CompletesInventsNothingAndMissesNoConcealedEffect) {
  const SyntheticPlant p = random_plant(GetParam());
  const SuitePlantResult r = diagnosis_of(p);
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

// The first three run under the sanitizers too; the other 37 (SliceOfForty) only in the Release
// suite: under ASan each full diagnosis takes several times as long (the `asan` test preset leaves
// them out, docs/reliability.md). Seed 3 000 003 once aborted inside GLPK (spxprim.c "teta_lim >=
// 0.0", an LP of the varying-parameter stage) before GLPK's error hook turned such an abort into
// an exception, which that stage catches.
INSTANTIATE_TEST_SUITE_P(DevelopmentSeeds, RandomSuiteSlice, ::testing::Range(3000000u, 3000003u));
INSTANTIATE_TEST_SUITE_P(SliceOfForty, RandomSuiteSlice, ::testing::Range(3000003u, 3000040u));

// The report lists every true value outside its bounded-error interval, its linearised estimate or
// their meet, with the sets involved and which one missed, and only those (scored results made by
// hand: no diagnosis run).
TEST(SuiteReport, ListsEveryTrueValueOutsideAnIntervalAndOnlyThose) {
  SuitePlantResult r;
  r.name = "plant-a";
  r.answer = "missing";
  r.truth.push_back({});
  r.truth.back().name = "coulomb_friction";
  r.named = {"coulomb_friction"};
  r.places = {"v"};
  SuiteCoverage fc;  // outside everything
  fc.effect = "coulomb_friction", fc.role = "Fc", fc.truth = 1.5, fc.lo = 1.1, fc.hi = 1.2, fc.estimate = 1.15;
  fc.estimate_oe_lo = 1.1, fc.estimate_oe_hi = 1.2, fc.has_ee = fc.ee_certified = fc.bounded = true, fc.ee_lo = 1.1, fc.ee_hi = 1.2;
  SuiteCoverage fv;  // inside everything
  fv.effect = "coulomb_friction", fv.role = "Fv", fv.truth = 0.3, fv.lo = 0.25, fv.hi = 0.35, fv.estimate = 0.31;
  fv.estimate_oe_lo = 0.2, fv.estimate_oe_hi = 0.4, fv.has_ee = fv.ee_certified = fv.bounded = true, fv.ee_lo = 0.25, fv.ee_hi = 0.35;
  fv.inside = fv.inside_estimate = fv.inside_meet = true;
  r.coverage = {fc, fv};
  const std::string text = suite_report({r}, false);
  EXPECT_NE(text.find("bounded-error interval (certified equation-error PUI): 2 of 2 (100.0 %); inside it: 1 of 2"), std::string::npos) << text;
  const auto at = text.find("True values outside an interval");
  ASSERT_NE(at, std::string::npos);
  const std::string misses = text.substr(at);
  EXPECT_NE(misses.find("| plant-a | coulomb_friction | Fc | 1.5 | [1.1, 1.2] |"), std::string::npos) << misses;
  EXPECT_NE(misses.find("| bounded-error, estimate, meet |"), std::string::npos) << misses;
  EXPECT_EQ(misses.find("| Fv |"), std::string::npos) << misses;
  // Only the linearised estimate misses: listed as such, and not counted against the bounded-error figure.
  r.coverage.front().inside = r.coverage.front().inside_meet = true;
  const std::string again = suite_report({r}, false);
  EXPECT_NE(again.find("inside it: 2 of 2"), std::string::npos) << again;
  EXPECT_NE(again.find("| estimate |"), std::string::npos) << again;
  r.coverage.front().inside_estimate = true;
  EXPECT_EQ(suite_report({r}, false).find("True values outside"), std::string::npos);
}

// The truth column prints each richer law's measure against its nested special case (the
// generator's TrueEffect::detectability_vs_special_case), truncated so that the printed value is
// below the generator's threshold exactly when the measured one is; "unknown" when not measured
// (scored results made by hand: no diagnosis run).
namespace {

TrueEffect nested_law(const std::string& name, std::vector<std::string> special_case, double vs_special_case) {
  TrueEffect t;
  t.name = name, t.where = "v", t.strength = 0.2, t.detectability = 6;
  t.special_case = std::move(special_case);
  t.detectability_vs_special_case = vs_special_case;
  return t;
}

SuitePlantResult scored(const std::string& plant, std::vector<TrueEffect> truth, std::vector<std::string> named) {
  SuitePlantResult r;
  r.name = plant;
  r.answer = "missing";
  r.truth = std::move(truth);
  r.named = std::move(named);
  r.places.assign(r.named.size(), "v");
  return r;
}

}  // namespace

TEST(SuiteReport, PrintsEachRicherLawsMeasureAgainstItsSpecialCase) {
  const std::string report = suite_report(
      {scored("random-1", {nested_law("stribeck_friction", {"coulomb_friction"}, 1.999)}, {"coulomb_friction"}),
       scored("random-2", {nested_law("asymmetric_friction", {"coulomb_friction", "constant_offset"}, 3.2)},
              {"coulomb_friction", "constant_offset"}),
       scored("random-3", {nested_law("stribeck_friction", {"coulomb_friction"}, -1)}, {"stribeck_friction"}),
       scored("random-4", {nested_law("dead_zone", {}, -1)}, {"dead_zone"})});
  EXPECT_NE(report.find("stribeck_friction (v, 20 %, 6 sigma, vs coulomb_friction 1.99 sigma)"), std::string::npos) << report;
  EXPECT_NE(report.find("asymmetric_friction (v, 20 %, 6 sigma, vs coulomb_friction + constant_offset 3.20 sigma)"), std::string::npos);
  EXPECT_NE(report.find("stribeck_friction (v, 20 %, 6 sigma, vs coulomb_friction unknown)"), std::string::npos);
  EXPECT_NE(report.find("dead_zone (v, 20 %, 6 sigma)"), std::string::npos);
  // The strict figure does not move.
  EXPECT_NE(report.find("first named right: 2 of 4"), std::string::npos);
}

// The declared second figure counts a plant whose truth is among the first named effect's equally
// good alternatives; the strict one does not move, and the alternatives per named effect are
// counted beside it (a pair listed counts once; an alternative of the second named effect does not
// help the one-effect figure, it does the two-effect one).
TEST(SuiteReport, LenientFigureCountsTheTruthAmongEquallyGoodAlternativesBesideTheStrictOne) {
  auto with = [](SuitePlantResult r, std::vector<std::vector<EquallyGood>> alike) {
    r.equally_good = std::move(alike);
    r.equally_good.resize(r.named.size());
    return r;
  };
  const EquallyGood offset{{"constant_offset"}, {"v"}, 0.03, 0.02}, pair{{"dead_zone", "constant_offset"}, {"u", "v"}, 0.03, 0.02};
  const std::vector<SuitePlantResult> plants{
      with(scored("random-1", {nested_law("constant_offset", {}, -1)}, {"viscous_friction"}), {{offset}}),
      with(scored("random-2", {nested_law("constant_offset", {}, -1)}, {"viscous_friction", "dead_zone"}), {{}, {offset}}),
      with(scored("random-3", {nested_law("dead_zone", {}, -1)}, {"dead_zone"}), {{pair}}),
      with(scored("random-4", {nested_law("dead_zone", {}, -1), nested_law("constant_offset", {}, -1)}, {"viscous_friction", "dead_zone"}),
           {{offset}, {}})};
  EXPECT_TRUE(plants[0].first_right_or_equally_good());
  EXPECT_FALSE(plants[1].first_right_or_equally_good());
  EXPECT_TRUE(plants[3].all_named_or_equally_good());
  EXPECT_FALSE(plants[3].all_named());
  const std::string report = suite_report(plants);
  EXPECT_NE(report.find("first named right: 1 of 3"), std::string::npos) << report;
  EXPECT_NE(report.find("one-effect 2 of 3"), std::string::npos) << report;
  EXPECT_NE(report.find("two-effect both 1 of 1"), std::string::npos) << report;
  EXPECT_NE(report.find("alternatives listed: 4 for 6 named effects (0.67 per named effect), on 4 plants"), std::string::npos) << report;
  EXPECT_NE(report.find("| random-1 | constant_offset (v) | 1. viscous_friction (v) | constant_offset (v) misfit 3.0 % | constant_offset |"),
            std::string::npos) << report;
}

// The per-family table counts each plant in its own family's row with the same rules as the
// headline (first named right, both named, an invented effect on a clean plant), so that a family
// where the rules are weak shows beside the totals.
TEST(SuiteReport, PerFamilyTableCountsEachPlantInItsFamilyByTheHeadlineRules) {
  auto in = [](SuitePlantResult r, const std::string& family) {
    r.family = family;
    return r;
  };
  const std::vector<SuitePlantResult> plants{
      in(scored("random-1", {nested_law("dead_zone", {}, -1)}, {"dead_zone"}), "position_loop"),
      in(scored("random-2", {nested_law("coulomb_friction", {}, -1)}, {"dead_zone"}), "position_loop"),
      in(scored("random-3", {}, {"constant_offset"}), "position_loop"),
      in(scored("random-4", {nested_law("dead_zone", {}, -1), nested_law("constant_offset", {}, -1)}, {"constant_offset", "dead_zone"}),
         "tanks"),
      in(scored("random-5", {}, {}), "tanks")};
  const std::string report = suite_report(plants, false);
  EXPECT_NE(report.find("| position_loop | 1 of 2 (50.0 %) | 0 of 0 | 1 of 1 (100.0 %) |"), std::string::npos) << report;
  EXPECT_NE(report.find("| tanks | 0 of 0 | 1 of 1 (100.0 %) | 0 of 1 (0.0 %) |"), std::string::npos) << report;
  // The totals are the families' sums.
  EXPECT_NE(report.find("first named right: 1 of 2"), std::string::npos) << report;
  // Plants without a family (the fixed suite's) get no table.
  EXPECT_EQ(suite_report({scored("fixed-1", {}, {})}, false).find("Per family"), std::string::npos);
}

// Random plant 5 004 294 (development since the seventeenth held-out run): a thermal node at 6
// samples per time scale, constant offset + hysteresis, white noise. The reversals' model error
// spreads over every frequency like AR(1) noise of pole 0.9; the noise was read 7.5x too high,
// the residual whitened by that pole looked white, and the answer was "nothing missing". The
// residual's bursts (sets/data/bursts.hpp) do not depend on the noise level read.
TEST(RandomSuiteSlice, ASwitchingMismatchReadAsColouredNoiseIsNotNothingMissing) {
  const SyntheticPlant p = random_plant(5004294u);
  ASSERT_EQ(p.effects.size(), 2u);
  const SuitePlantResult r = diagnosis_of(p);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_NE(r.answer, "nothing_missing");
}

// Random plant 5 009 595 (development since the thirty-third held-out run): one mass, an
// asymmetric friction and a hysteresis. Their model error spreads over the band like AR(1) noise;
// the noise was read 7.3x too high, so the bound held, the residual whitened by the pole read
// (0.49) looked white, it had no bursts, and the answer was "nothing missing". Only the
// independence test saw it (the residual follows |dq9| at 3.2x its threshold), and it decides
// beyond twice the threshold (sets/diagnosis/residual_tests.hpp).
TEST(RandomSuiteSlice, AResidualThatFollowsTheModelsSignalsIsNotNothingMissing) {
  const SyntheticPlant p = random_plant(5009595u);
  ASSERT_EQ(p.effects.size(), 2u);
  const SuitePlantResult r = diagnosis_of(p);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_EQ(r.answer, "missing");
}
