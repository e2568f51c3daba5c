// The randomised plant generator: deterministic per seed, magnitudes and sample times over
// decades, random names, effects of the strength asked for, clean plants without effects.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "sets/data/simulation.hpp"
#include "sets/core/error.hpp"
#include "sets/examples/random_plants.hpp"

using namespace sets;

TEST(RandomPlants, SameSeedSamePlant) {
  const SyntheticPlant a = random_plant(17), b = random_plant(17);
  EXPECT_EQ(to_json_text(a.nominal), to_json_text(b.nominal));
  EXPECT_EQ(to_json_text(a.truth), to_json_text(b.truth));
  EXPECT_EQ(a.estimation.columns, b.estimation.columns);
  EXPECT_NE(to_json_text(random_plant(18).truth), to_json_text(a.truth));
}

TEST(RandomPlants, SpanDecadesFamiliesNamesAndEffects) {
  std::set<std::string> families, effects, first_params;
  double ts_lo = 1e300, ts_hi = 0, y_lo = 1e300, y_hi = 0;
  int clean = 0;
  RandomPlantOptions o;
  o.samples = 1000;  // what is drawn does not depend on the length; generating 5000 samples took a minute
  for (unsigned seed = 501; seed < 561; ++seed) {
    const SyntheticPlant p = random_plant(seed, o);
    families.insert(p.family);
    for (const auto& e : p.effects) {
      effects.insert(e.name);
      EXPECT_GT(e.strength, 0.02) << seed << " " << e.name;
      EXPECT_LT(e.strength, 1.6) << seed << " " << e.name;
    }
    clean += p.effects.empty();
    first_params.insert(p.nominal.parameters.front().name);
    const auto& t = p.estimation.column(p.nominal.time_column);
    const double Ts = t[1] - t[0];
    ts_lo = std::min(ts_lo, Ts), ts_hi = std::max(ts_hi, Ts);
    const auto& y = p.estimation.column(p.nominal.outputs.front().second);
    const double spread = *std::max_element(y.begin(), y.end()) - *std::min_element(y.begin(), y.end());
    y_lo = std::min(y_lo, spread), y_hi = std::max(y_hi, spread);
    // The nominal leaves the effects out: it has no more states than the truth and simulates.
    EXPECT_LE(p.nominal.states.size(), p.truth.states.size());
    Simulator s(p.nominal, p.estimation, {10});
    EXPECT_NO_THROW(s.simulate(s.parameter_values())) << seed;
  }
  EXPECT_EQ(families.size(), random_plant_families().size());
  EXPECT_GE(effects.size(), 12u);
  EXPECT_GT(clean, 5);
  EXPECT_GT(first_params.size(), 20u);  // names are drawn, not fixed
  EXPECT_GT(ts_hi / ts_lo, 1e4);        // sample times over four decades
  EXPECT_GT(y_hi / y_lo, 1e4);          // output magnitudes over four decades
}

TEST(RandomPlants, ForcedEffectIsInTheTruthAndNotInTheNominal) {
  RandomPlantOptions o;
  o.effect = "bouc_wen_hysteresis";
  o.effects = 1;
  o.family = "one_mass";
  const SyntheticPlant p = random_plant(3, o);
  ASSERT_EQ(p.effects.size(), 1u);
  EXPECT_EQ(p.effects.front().name, "bouc_wen_hysteresis");
  EXPECT_EQ(p.truth.states.size(), 3u);
  EXPECT_EQ(p.nominal.states.size(), 2u);
  ASSERT_EQ(p.effects.front().values.size(), 1u);
  EXPECT_EQ(p.effects.front().values.front().first, "alpha");
  EXPECT_THROW(random_plant(3, RandomPlantOptions{1, "thermal", "bouc_wen_hysteresis", 0}), InputError);
}

// A richer friction law is measured against its nested special case (Stribeck: Coulomb friction;
// asymmetric friction: Coulomb friction + an offset), calibrated on the noise-free outputs. The
// special case nests "without the law" (Fc = 0, no offset), so it never misses by more. Forced
// development seeds (docs/reproduction/diagnosis.md, seed table), one effect each; on 700 079 (asymmetric
// friction) the calibration from the law's start ends above `detectability` (7.99 against 7.60).
// The measure is tested on the plants drawn without the rule that draws such a plant again.
TEST(RandomPlants, RicherFrictionLawIsMeasuredAgainstItsNestedSpecialCase) {
  RandomPlantOptions o;
  o.effects = 1;
  o.effect = "stribeck_friction";
  o.distinct_from_special_cases = false;
  // 700 065: a Stribeck part within the noise of Coulomb friction, though far from "no friction".
  const TrueEffect small = random_plant(700065, o).effects.at(0);
  EXPECT_EQ(small.special_case, std::vector<std::string>{"coulomb_friction"});
  EXPECT_GE(small.detectability, 4.0);
  EXPECT_GE(small.detectability_vs_special_case, 0.0);
  EXPECT_LT(small.detectability_vs_special_case, kDetectableInNoiseLevels);
  // 700 061: a Stribeck part no Coulomb friction can stand for.
  const TrueEffect big = random_plant(700061, o).effects.at(0);
  EXPECT_GT(big.detectability_vs_special_case, 5 * kDetectableInNoiseLevels);
  const std::vector<std::pair<std::string, unsigned>> forced = {
      {"stribeck_friction", 700062}, {"stribeck_friction", 700067}, {"asymmetric_friction", 700052},
      {"asymmetric_friction", 700053}, {"asymmetric_friction", 700079}};
  for (const auto& [effect, seed] : forced) {
    o.effect = effect;
    const TrueEffect e = random_plant(seed, o).effects.at(0);
    EXPECT_GE(e.detectability_vs_special_case, 0.0) << effect << " " << seed;
    EXPECT_LE(e.detectability_vs_special_case, e.detectability) << effect << " " << seed;
  }
  o.effect = "asymmetric_friction";
  EXPECT_EQ(random_plant(700053, o).effects.at(0).special_case, (std::vector<std::string>{"coulomb_friction", "constant_offset"}));
  o.effect = "coulomb_friction";
  const TrueEffect plain = random_plant(700041, o).effects.at(0);
  EXPECT_TRUE(plain.special_case.empty());
  EXPECT_EQ(plain.detectability_vs_special_case, -1.0);
}

// A dead zone is measured against a constant offset at its input, what it is on data whose input
// stays on one side of the band (u - dz(u) = d or -d throughout). Forced development seeds of two
// families whose input is a recorded column: where the estimation record stays on one side the
// offset stands in for the law within the noise; where it spends a fifth of its samples inside the
// band, it cannot. An input that jumps across the band without a sample inside is neither: the
// offset's sign would have to follow the input's (motor 700 004: 20.7 noise levels). Drawn
// without the rule that draws the one-sided ones again.
TEST(RandomPlants, DeadZoneIsMeasuredAgainstAnOffsetAtItsInput) {
  RandomPlantOptions o;
  o.effects = 1;
  o.effect = "dead_zone";
  o.distinct_from_special_cases = false;
  int one_sided = 0, often = 0;
  for (const char* family : {"tanks", "motor"})
    for (unsigned seed = 700000; seed < 700006; ++seed) {
      o.family = family;
      const SyntheticPlant p = random_plant(seed, o);
      const TrueEffect& e = p.effects.at(0);
      EXPECT_EQ(e.special_case, std::vector<std::string>{"constant_offset"});
      ASSERT_GE(e.detectability_vs_special_case, 0.0) << family << " " << seed;
      EXPECT_LE(e.detectability_vs_special_case, e.detectability) << family << " " << seed;
      std::string column;
      for (const auto& [symbol, col] : p.truth.inputs)
        if (symbol == e.where) column = col;
      if (column.empty()) continue;  // a sampled signal, not a recorded input
      const auto& u = p.estimation.column(column);
      const double d = e.values.at(0).second;
      const double inside = static_cast<double>(std::count_if(u.begin(), u.end(), [&](double x) { return std::abs(x) < d; })) /
                            static_cast<double>(u.size());
      const bool one_side = std::all_of(u.begin(), u.end(), [&](double x) { return x > d; }) ||
                            std::all_of(u.begin(), u.end(), [&](double x) { return x < -d; });
      if (one_side) {
        ++one_sided;
        EXPECT_LT(e.detectability_vs_special_case, kDetectableInNoiseLevels) << family << " " << seed;
      } else if (inside >= 0.2) {
        ++often;
        EXPECT_GE(e.detectability_vs_special_case, kDetectableInNoiseLevels) << family << " " << seed;
      }
    }
  EXPECT_GT(one_sided, 0);
  EXPECT_GT(often, 0);
}

// Strong enough to matter as itself: a law within the noise of its nested special case is drawn
// again. The forced seeds whose law was within it now draw a plant whose law is not; a plant
// whose laws all pass is the plant drawn without the rule (the measure comes after every other
// draw). Thermal, not tanks: a dead zone at a pump that hides in the loop is an offset (forced
// tank dead zones of 700 000 - 003 and 700 065 find no admissible plant in 40 attempts).
TEST(RandomPlants, LawWithinTheNoiseOfItsSpecialCaseIsDrawnAgain) {
  // -1: no measure, kept.
  const auto distinct = [](const TrueEffect& e) {
    return e.detectability_vs_special_case < 0 || e.detectability_vs_special_case >= kDetectableInNoiseLevels;
  };
  RandomPlantOptions o;
  o.effects = 1;
  int redrawn = 0;
  for (const char* effect : {"stribeck_friction", "dead_zone"})
    for (unsigned seed : {700000u, 700001u, 700002u, 700003u, 700065u}) {
      o.effect = effect;
      o.family = std::string(effect) == "dead_zone" ? "thermal" : "";
      RandomPlantOptions without_rule = o;
      without_rule.distinct_from_special_cases = false;
      const SyntheticPlant p = random_plant(seed, o), before = random_plant(seed, without_rule);
      const TrueEffect& e = p.effects.at(0);
      ASSERT_EQ(e.name, effect);
      EXPECT_TRUE(distinct(e)) << effect << " " << seed << ": " << e.detectability_vs_special_case;
      const bool kept = distinct(before.effects.at(0));
      EXPECT_EQ(to_json_text(p.truth) == to_json_text(before.truth), kept) << effect << " " << seed;
      redrawn += !kept;
    }
  EXPECT_GE(redrawn, 2);  // the rule was exercised, not only passed
}
