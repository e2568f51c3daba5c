// The hypothesis search of the diagnosis (src/diagnosis/hypotheses.cpp): on the Coulomb-friction
// plant the catalogue's Coulomb law is chosen first, with its parameter added to the model; on a
// clean plant nothing is chosen; a mirror sensor (calibrated from the file's values) is refined
// even when its screening, linearised at the nominal calibrated on mirrored data, ranks it last; a
// delay that ends worse than the current model is refined again from the file's values.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "sets/diagnosis/diagnosis.hpp"
#include "sets/diagnosis/residual_tests.hpp"
#include "sets/examples/random_plants.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/diagnosis_stages.hpp"
#include "support/plant_fixtures.hpp"

using namespace sets;
using namespace sets::diagnosis_stage;

namespace {

HypothesisSearch search(test::StageRun& s) {
  s.options.max_effects = 1;
  s.options.refine = 1;
  s.options.varying_segments = 10;
  const NominalFit nominal = calibrate_nominal(s.c(), s.d);
  const NoiseFloor noise = noise_floor(s.c(), nominal, s.d);
  s.d.nominal_tests = test_residual(*s.exact, nominal.calibration.parameters, nominal.simulation, noise.sigma, noise.pole);
  return search_hypotheses(s.c(), nominal, noise, s.d);
}

// What the search names on a random plant, one effect at most, after the stages before it.
std::vector<DiagnosedEffect> named_alone(const SyntheticPlant& plant) {
  test::StageRun s(plant);
  s.options.max_effects = 1;
  const NominalFit nominal = calibrate_nominal(s.c(), s.d);
  const NoiseFloor noise = noise_floor(s.c(), nominal, s.d);
  s.d.nominal_tests = test_residual(*s.exact, nominal.calibration.parameters, nominal.simulation, noise.sigma, noise.pole);
  search_hypotheses(s.c(), nominal, noise, s.d);
  return s.d.effects;
}

// Random plant `seed`, whose one effect must be `effect`: what the search names alone, checked to
// be that effect in its true equation; returned for the test's own further checks.
std::vector<DiagnosedEffect> expect_named_alone_in_place(unsigned seed, const std::string& effect) {
  const SyntheticPlant plant = random_plant(seed);
  if (plant.effects.size() != 1u || plant.effects[0].name != effect) {
    ADD_FAILURE() << "random plant " << seed << " no longer draws " << effect << " alone";
    return {};
  }
  const std::vector<DiagnosedEffect> named = named_alone(plant);
  EXPECT_EQ(named.size(), 1u);
  if (named.size() != 1u) return named;
  EXPECT_EQ(named[0].name, effect);
  EXPECT_EQ(named[0].equation, plant.effects[0].where);
  return named;
}

// A thermal node whose ambient is fixed and known: T' = (u - (T - Ta)/R)/C, R and C free; the
// truth adds a constant heat flow q < 0. With Ta fixed, -(T - Ta)/R ties the equation's slope in T
// and its intercept: a constant offset frees the intercept, a viscous term -Fv*T the slope, and
// either reaches the truth exactly (1/R + Fv = 1/R_true, Ta/R = Ta/R_true + q: Fv = -q/Ta = 0.5).
// T swings through 0, so the friction laws are candidates there.
SyntheticPlant thermal_node_with_heat_flow() {
  auto model = [](const std::string& flow) {
    return parse_model(R"({"name": "thermal node", "time": "t", "inputs": {"u": "u"},
      "parameters": {"Ta": {"value": 2.0, "fixed": true}, "R": 0.6, "C": 2.5},
      "states": {"T": "T_meas"}, "derivatives": {"T": "(u)" + flow + R"( - (T - Ta)/R)/C"}, "outputs": {"T": "T_meas"}})",
                       "thermal node");
  };
  SyntheticPlant p;
  p.name = "thermal node";
  p.nominal = model("");
  p.truth = model(" - 1.0");
  for (auto& q : p.truth.parameters) q.value = q.name == "R" ? 0.5 : q.name == "C" ? 2.0 : q.value;
  auto record = [&](unsigned seed) {
    const int n = 1500;
    const double Ts = 0.1;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> level(-12, 12), hold(0.5, 3.0);
    Recording r;
    std::vector<double> t(n), u(n);
    double next = 0, value = 0;
    for (int k = 0; k < n; ++k) {
      if (k * Ts >= next) value = level(rng), next = k * Ts + hold(rng);
      t[k] = k * Ts, u[k] = value;
    }
    r.add("t", t);
    r.add("u", u);
    r.add("T_meas", std::vector<double>(n, 1.0));  // the initial state
    Simulator sim(p.truth, r, {10});
    const Eigen::VectorXd y = sim.simulate(sim.parameter_values()).outputs.col(0);
    std::normal_distribution<double> noise(0.0, 0.01 * std::sqrt((y.array() - y.mean()).square().mean()));
    std::vector<double> meas(n);
    for (int k = 0; k < n; ++k) meas[k] = y[k] + noise(rng);
    r.add("T_meas", meas);
    return r;
  };
  p.estimation = record(11);
  p.validation = record(12);
  return p;
}

bool lists(const DiagnosedEffect& e, const std::string& effect, const std::string& equation) {
  for (const auto& a : e.equally_good)
    for (std::size_t k = 0; k < a.effects.size(); ++k)
      if (a.effects[k] == effect && a.equations[k] == equation) return true;
  return false;
}

}  // namespace

// The two hypotheses explain the data equally well: whichever is named (rounding decides), the other
// is listed beside it as equally good, with its misfit.
TEST(Hypotheses, EquivalentHypothesisIsListedAsEquallyGood) {
  test::StageRun s(thermal_node_with_heat_flow());
  search(s);
  ASSERT_EQ(s.d.effects.size(), 1u);
  const DiagnosedEffect& e = s.d.effects[0];
  ASSERT_TRUE(e.name == "viscous_friction" || e.name == "constant_offset") << e.name;
  EXPECT_EQ(e.equation, "T");
  const std::string other = e.name == "viscous_friction" ? "constant_offset" : "viscous_friction";
  EXPECT_TRUE(lists(e, other, "T")) << e.equally_good.size() << " listed";
  // Coulomb friction in T passes every rule too (47 % of the misfit left, against 0.3 %): the named
  // law is beyond it, so it is not listed; the list is not "everything that passed".
  const auto at = e.evidence.rfind(" passed every rule");
  ASSERT_NE(at, std::string::npos) << e.evidence;
  EXPECT_GT(std::stoul(e.evidence.substr(e.evidence.rfind(' ', at - 1) + 1)), e.equally_good.size() + 1) << e.evidence;
  EXPECT_FALSE(lists(e, "coulomb_friction", "T"));
  for (const auto& a : e.equally_good) {
    EXPECT_FALSE(a.effects.size() == 1 && a.effects[0] == e.name && a.equations[0] == e.equation);  // not itself
    EXPECT_LT(a.misfit, 1 - s.options.min_cost_reduction);  // it passed the rules on its own
  }
}

TEST(Hypotheses, CoulombLawIsChosenForTheCoulombPlant) {
  test::StageRun s(synthetic_plant("coulomb_friction"), true, 1500);
  const HypothesisSearch h = search(s);
  ASSERT_EQ(h.chosen.size(), 1u);
  ASSERT_EQ(s.d.effects.size(), 1u);
  EXPECT_EQ(s.d.effects[0].name, "coulomb_friction");
  EXPECT_FALSE(s.d.nothing_missing);
  EXPECT_GT(s.d.effects[0].cost_reduction_estimation, s.options.min_cost_reduction);
  EXPECT_GT(s.d.hypotheses_screened, 1);
  EXPECT_GE(s.d.hypotheses_screened, s.d.hypotheses_refined);
  // The chosen effect's parameter is in the current model, and it passed every rule it reports.
  EXPECT_GT(h.current.parameters.size(), s.model.parameters.size());
  for (const auto& r : s.d.effects[0].rules) EXPECT_TRUE(r.passed || !r.applies) << r.name;
  // Asymmetric friction and the pair Coulomb + offset fit as closely (0.5 % of the misfit), but the
  // one is not beyond its special case and the other's offset does nothing (own_term): neither
  // passes every rule, so neither is equally good.
  EXPECT_TRUE(s.d.effects[0].equally_good.empty()) << equally_good_text(s.d.effects[0].equally_good.front());
}

TEST(Hypotheses, NothingIsChosenForACleanPlant) {
  test::StageRun s(synthetic_plant("clean_axis"), true, 1500);
  const HypothesisSearch h = search(s);
  EXPECT_TRUE(h.chosen.empty());
  EXPECT_TRUE(s.d.effects.empty()) << s.d.effects.front().name;
  EXPECT_EQ(h.current.parameters.size(), s.model.parameters.size());
}

// The nominal calibrated on |y| data shrinks its response toward the data's mean, so the mirror
// screened there (abs of an almost non-negative output) explains nothing and a constant offset
// ranks first; only refined from the file's values does the mirror show what it explains. Without
// the shortlist's rule for such candidates this plant is diagnosed `constant_offset`. (Seed
// 700 034 is a development seed of docs/reproduction/diagnosis.md, effect forced.)
TEST(Hypotheses, MirrorSensorCalibratedFromTheFileValuesIsRefinedWhateverItsScreeningRank) {
  RandomPlantOptions ro;
  ro.effect = "absolute_value_sensor";
  ro.effects = 1;
  test::StageRun s(random_plant(700034, ro));
  s.options.refine = 1;
  s.options.max_effects = 1;
  const NominalFit nominal = calibrate_nominal(s.c(), s.d);
  const NoiseFloor noise = noise_floor(s.c(), nominal, s.d);
  s.d.nominal_tests = test_residual(*s.exact, nominal.calibration.parameters, nominal.simulation, noise.sigma, noise.pole);
  search_hypotheses(s.c(), nominal, noise, s.d);
  ASSERT_FALSE(s.d.effects.empty());
  EXPECT_EQ(s.d.effects[0].name, "absolute_value_sensor");
}

namespace {

// A forced one-effect random plant diagnosed as sets-diagnose does (default options, one thread,
// one round), with its progress lines. `distinct` false: the plant drawn before the generator
// drew a law within the noise of its special case again.
Diagnosis diagnose_forced(unsigned seed, const std::string& effect, std::vector<std::string>* lines = nullptr,
                          bool distinct = true) {
  RandomPlantOptions ro;
  ro.effect = effect;
  ro.effects = 1;
  ro.distinct_from_special_cases = distinct;
  const SyntheticPlant p = random_plant(seed, ro);
  DiagnosisOptions o;
  o.threads = 1;
  o.max_effects = 1;
  if (lines) o.progress = [lines](const std::string& s) { lines->push_back(s); };
  return diagnose(p.nominal, p.estimation, &p.validation, o);
}

// The misfits (% of the current model's) of a hypothesis's progress lines in round 1, one per
// trial of it (a hypothesis can be refined twice, e.g. from a pair's optimum).
std::vector<double> refined_misfits(const std::vector<std::string>& lines, const std::string& hypothesis) {
  std::vector<double> out;
  for (const auto& l : lines) {
    if (l.find("round 2:") != std::string::npos) break;
    if (const auto at = l.find("    " + hypothesis + ": misfit "); at != std::string::npos)
      out.push_back(std::stod(l.substr(at + hypothesis.size() + 13)));
  }
  return out;
}

// The first of them; NaN when it was not refined.
double refined_misfit(const std::vector<std::string>& lines, const std::string& hypothesis) {
  const std::vector<double> all = refined_misfits(lines, hypothesis);
  return all.empty() ? std::numeric_limits<double>::quiet_NaN() : all.front();
}

}  // namespace

// Stribeck friction contains Coulomb friction (Fs = 0): refined beside it, it must be refined
// from Coulomb's optimum too, so that it never fits worse than the law it contains. On main
// b36761a the Stribeck law of this plant ended at 4.4 % of the misfit, Coulomb at 4.3 %. (Seed
// 700 067: development, docs/reproduction/diagnosis.md, effect forced; its Stribeck part within
// the noise of Coulomb friction, so drawn again by the generator since 2026-11-29: the plant before.)
TEST(Hypotheses, RicherLawIsRefinedFromItsSpecialCasesOptimumAndFitsAtLeastAsWell) {
  std::vector<std::string> lines;
  diagnose_forced(700067, "stribeck_friction", &lines, false);
  const double coulomb = refined_misfit(lines, "coulomb_friction (vel)");
  const double stribeck = refined_misfit(lines, "stribeck_friction (vel)");
  ASSERT_TRUE(std::isfinite(coulomb));
  ASSERT_TRUE(std::isfinite(stribeck)) << "the Stribeck law was not refined beside Coulomb's";
  EXPECT_LE(stribeck, coulomb);
}

// A richer law never ends worse than a special case of it calibrated in the same round, whenever
// that special case was found. On this plant Coulomb friction reached 29.6 % of the misfit from
// the optimum of a pair whose hysteresis does nothing, after the Stribeck law had been refined
// from Coulomb's own optimum (33.5 %) and ended at 31.5 %: Coulomb was named (main a7df121).
// Refined again from the better Coulomb optimum, the Stribeck law passes the nested rule against
// it. (Seed 5 002 818: held out in the thirteenth session, development since,
// docs/reproduction/diagnosis.md.)
TEST(Hypotheses, RicherLawIsRefinedAgainFromASpecialCaseFoundLaterThatFitsBetter) {
  const SyntheticPlant plant = random_plant(5002818);
  ASSERT_EQ(plant.effects.size(), 1u);
  ASSERT_EQ(plant.effects[0].name, "stribeck_friction");
  std::vector<std::string> lines;
  DiagnosisOptions o;
  o.max_effects = 1;
  o.progress = [&lines](const std::string& s) { lines.push_back(s); };
  const Diagnosis d = test::diagnosed(plant, o);
  const std::string at = " (" + plant.effects[0].where + ")";
  const std::vector<double> coulomb = refined_misfits(lines, "coulomb_friction" + at);
  const std::vector<double> stribeck = refined_misfits(lines, "stribeck_friction" + at);
  ASSERT_GE(coulomb.size(), 2u) << "Coulomb friction is no longer also reached from a pair's optimum";
  ASSERT_EQ(stribeck.size(), 1u);
  EXPECT_LE(stribeck[0], *std::min_element(coulomb.begin(), coulomb.end()));
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects[0].name, "stribeck_friction");
  EXPECT_EQ(d.effects[0].equation, plant.effects[0].where);
}

// The guard: a Coulomb plant whose Stribeck law fits a little better (6.7 % against 7.6 % of the
// misfit) but by less than the noise stays Coulomb (seed 700 048, effect forced).
TEST(Hypotheses, CoulombPlantIsNotNamedStribeck) {
  const Diagnosis d = diagnose_forced(700048, "coulomb_friction");
  ASSERT_FALSE(d.effects.empty());
  EXPECT_EQ(d.effects[0].name, "coulomb_friction");
}

// From Coulomb's optimum with Fs = 0 the Stribeck velocity does nothing and Levenberg-Marquardt
// stays next to Coulomb; switched half on there (Fc and Fs each half Coulomb's Fc, vs at the grid
// point whose start simulates best) it reaches its own basin: 5.0 % of the misfit against
// Coulomb's 14.2 %. This plant's Stribeck law was not even in the shortlist, only Coulomb was; it
// was named coulomb_friction on main 12004db. (Seed 5 001 597: held out in the tenth session,
// development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, StribeckLawIsReachedFromCoulombsOptimumSwitchedOn) {
  expect_named_alone_in_place(5001597, "stribeck_friction");
}

// The guard of the switched-on start: a Coulomb plant beside another effect stays Coulomb, where
// Stribeck's extra terms could fit what the other effect's law leaves. 800 015 (Coulomb friction
// and a dead zone) is one of the two drawn plants the tenth session's variant (a switched-on start
// at every grid vs, Stribeck always refined; not landed) was reported to turn Stribeck.
// (Seed 800 015: development, docs/reproduction/diagnosis.md, tenth session.)
TEST(Hypotheses, CoulombPlantBesideAnotherEffectIsNotNamedStribeck) {
  const SyntheticPlant plant = random_plant(800015);
  ASSERT_EQ(plant.effects.size(), 2u);
  const Diagnosis d = test::diagnosed(plant);
  std::vector<std::string> named;
  for (const auto& e : d.effects) named.push_back(e.name);
  EXPECT_NE(std::find(named.begin(), named.end(), "coulomb_friction"), named.end());
  EXPECT_EQ(std::find(named.begin(), named.end(), "stribeck_friction"), named.end());
}

// Stribeck friction beside another effect: the pair Coulomb friction + cubic stiffness passed every
// rule in round 1 (18.0 % of the misfit) and was named, the Stribeck law having been refined only
// alone, beside a model that still missed the cubic stiffness; afterwards one friction law per
// place excluded it, and a quadratic drag took part of what was left. Refined as the pair Stribeck
// friction + cubic stiffness from the Coulomb pair's optimum with the Stribeck term switched on, it
// removes 46 % of that pair's misfit and the data exclude the Coulomb pair. Named Coulomb friction,
// cubic stiffness, quadratic drag on main 043b8f0. (Seed 5 002 617: held out in the twelfth
// session, development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, StribeckLawBesideAnotherEffectIsReachedFromThePairsOptimumSwitchedOn) {
  const SyntheticPlant plant = random_plant(5002617);
  ASSERT_EQ(plant.effects.size(), 2u);
  ASSERT_EQ(plant.effects[0].name, "stribeck_friction");
  ASSERT_EQ(plant.effects[1].name, "cubic_stiffness");
  const Diagnosis d = test::diagnosed(plant);
  auto named_at = [&](const TrueEffect& t) {
    for (const auto& e : d.effects)
      if (e.name == t.name && e.equation == t.where) return true;
    return false;
  };
  EXPECT_TRUE(named_at(plant.effects[0]));
  EXPECT_TRUE(named_at(plant.effects[1]));
  for (const auto& e : d.effects) EXPECT_NE(e.name, "coulomb_friction") << e.equation;
}

// A pair one of whose members does nothing at the pair's optimum found the other member alone in a
// basin that member's own starts missed: without refining that member again from the pair's
// optimum, every hypothesis of this plant fails a rule (the pairs their own-term rule, the single
// effects the gain rules) and the diagnosis ends "unexplained". (Seed 5 000 856: held out in the
// seventh session, development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, MemberOfAPairWhoseOtherMemberDoesNothingIsJudgedAlone) {
  const SyntheticPlant plant = random_plant(5000856);
  ASSERT_EQ(plant.effects.size(), 1u);
  ASSERT_EQ(plant.effects[0].name, "hysteresis");
  const std::vector<DiagnosedEffect> named = named_alone(plant);
  ASSERT_EQ(named.size(), 1u);
  EXPECT_EQ(named[0].name, "hysteresis");
  for (const auto& r : named[0].rules) EXPECT_TRUE(r.passed || !r.applies) << r.name;
}

// A delay competes at its best whole number of samples: this plant's delay of 5 samples lies
// between the screening grid's 4 and 6, and at a grid value an offset beside the delay fitted the
// grid step's error, so the pair was named (offset first, delay second) on main 44215f1. (Seed
// 5 001 140: held out in the eighth session, development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, DelayBetweenTheGridsValuesIsNamedAloneAtItsNumberOfSamples) {
  const SyntheticPlant plant = random_plant(5001140);
  ASSERT_EQ(plant.effects.size(), 1u);
  ASSERT_EQ(plant.effects[0].name, "time_delay");
  const double true_samples = plant.effects[0].values.at(0).second;
  const std::vector<DiagnosedEffect> named = named_alone(plant);
  std::string names;
  for (const auto& e : named) names += e.name + " ";
  ASSERT_EQ(named.size(), 1u) << names;
  EXPECT_EQ(named[0].name, "time_delay");
  EXPECT_EQ(named[0].delay_samples, static_cast<int>(true_samples));
}

// A law that replaces a term (the tank's linear outflow a*x by a square-root law) has no value of
// its parameters that gives back the current model: screened at a finite change from the point of
// the linearisation, it ranked below an offset (sqrt(x) is about a + b*x near the operating level)
// and was never refined; the plant was named constant_offset on main 44215f1. (Seed 5 001 335:
// held out in the eighth session, development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, LawThatReplacesATermIsRefinedWhateverItsScreeningRank) {
  expect_named_alone_in_place(5001335, "sqrt_outflow");
}

// A richer law is named when the data exclude its special case itself: the special case,
// linearised at its own optimum with every parameter free, fits within no point of the bound the
// richer law meets. This motor's asymmetric friction (Fc_pos 0.0048, Fc_neg 0.0023) fits to the
// noise, Coulomb friction leaves 30 times the noise's misfit, but dFv's interval, linearised at the
// asymmetric law's optimum, reached 0 where the motor's other parameters were barely determined
// (Kb in [-4.8, 5.1]): on main 12004db nothing was named ("unexplained"). (Seed 5 001 955: held
// out in the tenth session, development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, RicherLawIsNamedWhenTheDataExcludeItsSpecialCaseItself) {
  const std::vector<DiagnosedEffect> named = expect_named_alone_in_place(5001955, "asymmetric_friction");
  ASSERT_EQ(named.size(), 1u);
  EXPECT_NE(named[0].evidence.find("constant_offset+coulomb_friction, its special case"), std::string::npos)
      << named[0].evidence;
}

// A hypothesis adds a term to the current model, so at its optimum it cannot fit worse than that
// model (its term switched off). On this two-mass plant (a constant offset and a cubic stiffness;
// the nominal calibrates to a fit of 15 %) the screening's starts put every hypothesis of the
// first round where it fitted worse than the current model (the offset at 6.8x its misfit) and
// nothing was named on main f9dab8c; refined again from the current point with the term switched
// off, both are named. The stages run with the steps diagnose() chooses for this plant (the
// nominal calibrated at the coarse step, the search at the finer one its optimum needs): with
// one step for both, the calibrated nominal is another and main named both too. (Seed 5 001 938:
// held out in the tenth session, development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, HypothesisThatEndsWorseThanTheModelItNestsIsRefinedFromThatModel) {
  const SyntheticPlant plant = random_plant(5001938);
  ASSERT_EQ(plant.effects.size(), 2u);
  test::StageRun s(plant, true, 0, 10);
  s.options.max_effects = 2;
  DiagnosisOptions coarse = s.options;
  coarse.screening_substeps = screening_substeps(s.model, s.estimation, *s.exact, s.exact->parameter_values(), 10);
  const Simulator fast(s.model, s.estimation, {coarse.screening_substeps});
  const Context calibration{s.model, s.estimation, &s.validation, coarse, *s.exact, fast, s.exact_validation.get(), s.c().say};
  const NominalFit nominal = calibrate_nominal(calibration, s.d);
  DiagnosisOptions fine = s.options;
  fine.screening_substeps = evaluate(fast, nominal.calibration.parameters).ok
                                ? coarse.screening_substeps
                                : screening_substeps(s.model, s.estimation, *s.exact, nominal.calibration.parameters, 10,
                                                     coarse.screening_substeps + 1);
  const Simulator fine_fast(s.model, s.estimation, {fine.screening_substeps});
  const Context search{s.model, s.estimation, &s.validation, fine, *s.exact, fine_fast, s.exact_validation.get(), s.c().say};
  const NoiseFloor noise = noise_floor(search, nominal, s.d);
  s.d.nominal_tests = test_residual(*s.exact, nominal.calibration.parameters, nominal.simulation, noise.sigma, noise.pole);
  search_hypotheses(search, nominal, noise, s.d);
  std::string names;
  for (const auto& e : s.d.effects) names += e.name + " ";
  for (const auto& truth : plant.effects)
    EXPECT_NE(names.find(truth.name), std::string::npos) << truth.name << " not named; named: " << names;
}

// A nominal that calibration cannot bring near the data hides the missing effect from screening:
// on these motors (a mirror sensor |omega|, 140 - 147 % of the signal) the calibrated nominal
// collapses (5 003 182: Kb at its bound, negative damping, fit -72.6 %), its simulated speed no
// longer goes negative, so the mirror sensor is not even a candidate there, and an output or state
// saturation was named (main 8ef3221). Round 1 also screens at the file's values, where it is.
// (Seeds 5 003 182 and 5 003 286: held out in the fourteenth session, development since,
// docs/reproduction/diagnosis.md.)
TEST(Hypotheses, MirrorSensorBehindANominalFarFromTheDataIsScreenedAtTheFilesValues) {
  for (unsigned seed : {5003182u, 5003286u}) {
    SCOPED_TRACE(seed);
    expect_named_alone_in_place(seed, "absolute_value_sensor");
  }
}

// The calibration can absorb an effect into the nominal's parameters: on this position loop a
// backlash of the drive (11 sigma) was taken up by a negative damping (c = -24 against the file's
// 8.4); at that point the backlash screens at nothing, round 1 named nothing and the answer was
// "unexplained" (main 9403f68). Screened at the file's values it explains 99 % of the misfit, so a
// round 1 that names nothing is run again with those candidates. (Seed 5 004 395: held out in the
// eighteenth session, development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, EffectTheCalibrationAbsorbedIsScreenedAtTheFilesValues) {
  expect_named_alone_in_place(5004395, "backlash");
}

// A delay has no value that switches it off, so when its refinement ends worse than the current
// model it is refined again from the file's values: the calibrated nominal has absorbed the missing
// delay into its other parameters, and on this motor (a delay of the drive and a weak quadratic
// drag) the delay added at that point ended at 3.1 times the current misfit, its pairs diverged,
// and nothing was named ("unexplained", main 48acb72); from the file's values the delay removes
// 89 % of the misfit. (Seed 5 003 041: held out in the thirteenth session, development since,
// docs/reproduction/diagnosis.md.)
TEST(Hypotheses, DelayThatEndsWorseThanTheModelIsRefinedFromTheFilesValues) {
  const SyntheticPlant plant = random_plant(5003041);
  ASSERT_EQ(plant.effects.size(), 2u);
  ASSERT_EQ(plant.effects[0].name, "time_delay");
  const std::vector<DiagnosedEffect> named = named_alone(plant);
  ASSERT_EQ(named.size(), 1u);
  EXPECT_EQ(named[0].name, "time_delay");
  EXPECT_EQ(named[0].equation, plant.effects[0].where);
}

// A pair holding a delay that ends worse than the current model from the file's values too is
// refined without its partner: on this motor (a one-sample delay of the drive, 76 noise levels,
// at 8 samples per time constant) the calibration absorbed the delay into a negative damping and
// gains 40 - 70 times the file's; the shortlist held the delay only beside a viscous term, whose
// screening value, fitted against that damping, kept the pair at 130 % of the current misfit from
// the file's values, and nothing was named ("unexplained", main 0ab6e10). The delay alone from
// the file's values removes 99.9 %. (Seed 5 010 869: held out in the thirty-sixth session, run
// in the thirty-ninth, development since, docs/reproduction/diagnosis.md.)
TEST(Hypotheses, DelayOfAPairThatEndsWorseFromTheFilesValuesIsRefinedAlone) {
  expect_named_alone_in_place(5010869, "time_delay");
}

// Random plant `seed` diagnosed whole (one thread), with or without the shortlist's slots: whether
// every true effect is named at its true place.
bool every_true_effect_named(unsigned seed, bool slots, const RandomPlantOptions& ro = {}) {
  const SyntheticPlant plant = random_plant(seed, ro);
  DiagnosisOptions o;
  o.shortlist_slots = slots;
  const Diagnosis d = test::diagnosed(plant, o);
  for (const auto& truth : plant.effects) {
    const auto at = std::find_if(d.effects.begin(), d.effects.end(), [&](const DiagnosedEffect& e) {
      return e.name == truth.name && e.equation == truth.where;
    });
    if (at == d.effects.end()) return false;
  }
  return true;
}

// A richer law beyond its special case on the validation record's noise: on this motor (a dead
// zone at the drive and asymmetric friction, 2.7 noise levels from Coulomb + offset) the estimation
// record cannot tell asymmetric friction (23.4 % of the misfit) from Coulomb + offset (35.1 %):
// 0.51 of its noise misfit between them. On validation the special case leaves 335 % of the
// current model's misfit and the law 55 %, but the nested rule read the noise on estimation only,
// and only the dead zone was named (main f3a2865). (Seed 5 003 830: held out in the sixteenth
// session, development since.)
TEST(Hypotheses, RicherLawBeyondItsSpecialCaseOnValidationIsNamed) {
  const SyntheticPlant plant = random_plant(5003830);
  ASSERT_EQ(plant.effects.size(), 2u);
  ASSERT_EQ(plant.effects[0].name, "asymmetric_friction");
  EXPECT_TRUE(every_true_effect_named(5003830, true));
}

// The shortlist refines the best single effect of every place that has none in it: on this motor
// (viscous friction and an input saturation, 3.1 and 2.5 noise levels) the saturation's
// linearised gain is small, the best four by score were laws of the two equations, and the
// saturation was never refined (named: viscous friction and a cubic stiffness; main e1ac151).
// (Seed 5 002 871: held out in the thirteenth session, development since.)
TEST(Hypotheses, BestLawOfAPlaceTheShortlistLeftOutIsRefined) {
  ASSERT_EQ(random_plant(5002871).effects.size(), 2u);
  EXPECT_TRUE(every_true_effect_named(5002871, true));
  EXPECT_FALSE(every_true_effect_named(5002871, false)) << "the plant no longer needs the slot";
}

// The shortlist refines the hypothesis of the largest linearised gain whatever its number of
// parameters: on this plant (a delay and asymmetric friction) an offset and the delay were named
// and in round 3 asymmetric friction, the round's largest gain, ranked 24th by score (3 parameters)
// and was never refined (main e1ac151). (Seed 5 002 962, as above.)
TEST(Hypotheses, HypothesisOfTheLargestGainIsRefinedWhateverItsParameters) {
  ASSERT_EQ(random_plant(5002962).effects.size(), 2u);
  EXPECT_TRUE(every_true_effect_named(5002962, true));
  EXPECT_FALSE(every_true_effect_named(5002962, false)) << "the plant no longer needs the slot";
}

// A dead zone at a position loop's drive whose evidence is on the measured drive (0.35 % noise)
// while the position is noisy (2.8 %): it removes 31 times the drive's noise misfit, 0.1 times the
// position's. The noise rule summed over outputs by their spread gave 0.57 < 1 and the answer was
// "unexplained" (main f3a2865); in units of each output's noise it is 15. (Seed 5 003 724: held
// out in the sixteenth session, development since.)
TEST(Hypotheses, DeadZoneSeenOnAQuietOutputBesideANoisyOneIsNamed) {
  expect_named_alone_in_place(5003724, "dead_zone");
}

// A thermal node with an offset in the case's equation and a dead zone at the heater, measured on
// two outputs whose noise differs 16-fold for their spread. Calibrated with the offset, the model
// trades the quiet output's fit for the noisy one's: counted per output in units of its own noise
// the offset's gain was -2.5 < 1 and the answer was "unexplained" (main 79fb76d); pooled, in the
// units the calibration minimises, it is 4.0. (Seed 5 004 998: held out in the twentieth range,
// development since. Its dead zone is an offset at the heater on these data, 0.00 noise levels
// from one: the generator now draws such a plant again, so the test asks for the plant drawn
// before, distinct_from_special_cases = false.)
TEST(Hypotheses, GainTheCalibrationTradesAcrossOutputsStillCounts) {
  RandomPlantOptions ro;
  ro.distinct_from_special_cases = false;
  const SyntheticPlant plant = random_plant(5004998, ro);
  ASSERT_EQ(plant.effects.size(), 2u);
  EXPECT_TRUE(every_true_effect_named(5004998, true, ro));
}

// A dead zone at a position loop's drive of 0.7 % of the drive's peak (the drive peaks at each
// step and spends half the record inside the zone): screened from 2 % of the peak only, its
// linearised gain was 0.02, it was never refined and a hysteresis of the measured drive was named
// (main f3a2865). From 0.5 % its gain is 0.9, first of the round. (Seed 5 003 917, as above.)
TEST(Hypotheses, DeadZoneFarBelowTheDrivesPeakIsScreenedWhereItIs) {
  expect_named_alone_in_place(5003917, "dead_zone");
}
