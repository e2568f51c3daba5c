// The effects of the randomised suite (src/examples/random_plant_effects.cpp): the signal scales
// they are sized by, which effects a plant's structure admits, and that each admitted effect
// changes the truth it is applied to (viscous friction: the nominal leaves it out instead).

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "examples/random_plant_builder.hpp"
#include "sets/core/error.hpp"
#include "sets/examples/random_plants.hpp"

using namespace sets;
using namespace sets::random_plant_detail;

TEST(RandomPlantEffects, ScalesOfARampAndASquareWave) {
  SimulationResult s;
  s.names = {"ramp", "square"};
  const int n = 101;
  s.values.resize(n, 2);
  for (int k = 0; k < n; ++k) {
    s.values(k, 0) = 0.5 * k;               // slope 0.5 per sample
    s.values(k, 1) = k % 2 == 0 ? 3 : -3;   // RMS 3, mean 3/101
  }
  const Scales sc = scales_of(s, 0.1);
  EXPECT_DOUBLE_EQ(sc.range.at("ramp"), 50);
  EXPECT_NEAR(sc.rate_rms.at("ramp"), 5, 1e-12);  // 0.5 per sample / 0.1 s
  EXPECT_DOUBLE_EQ(sc.maxabs.at("square"), 3);
  EXPECT_NEAR(sc.rms.at("square"), 3, 1e-12);
  EXPECT_NEAR(sc.mean.at("square"), 3.0 / n, 1e-12);
  EXPECT_DOUBLE_EQ(sc.min.at("square"), -3);
}

TEST(RandomPlantEffects, EveryAdmittedEffectChangesTheTruth) {
  const std::vector<std::string> catalogue = random_plant_effects();
  for (const std::string& family : random_plant_families()) {
    Rng r(7);
    Names names(r);
    Build b;
    b.family = family;
    b.names = &names;
    draw_family(r, b);
    SimulationResult flat;  // unit scales: enough to size every effect
    for (const auto& s : b.states) flat.names.push_back(s.name);
    for (const auto& [sym, text] : b.sampled) flat.names.push_back(sym);
    for (const auto& [sym, col] : b.inputs) flat.names.push_back(sym);
    flat.values.resize(50, static_cast<Eigen::Index>(flat.names.size()));
    for (Eigen::Index k = 0; k < flat.values.rows(); ++k) flat.values.row(k).setConstant(k % 2 == 0 ? 1.0 : -1.0);
    const Scales sc = scales_of(flat, b.Ts);
    for (const std::string& name : effects_for(b)) {
      SCOPED_TRACE(family + ": " + name);
      EXPECT_NE(std::find(catalogue.begin(), catalogue.end(), name), catalogue.end());
      const Effect e = make_effect(r, b, name, sc);
      EXPECT_EQ(e.name, name);
      std::vector<Eq> eqs = b.eqs;
      NamedTexts sampled = b.sampled, outputs = b.outputs;
      std::vector<ModelState> states = b.states;
      std::vector<ModelParameter> params = b.params;
      std::vector<std::pair<std::string, double>> values;
      e.apply(1.0, eqs, sampled, outputs, states, params, values);
      bool changed = sampled != b.sampled || outputs != b.outputs || states.size() != b.states.size() ||
                     params.size() != b.params.size();
      for (std::size_t i = 0; i < eqs.size(); ++i)
        changed = changed || eqs[i].body != b.eqs[i].body || eqs[i].extra != b.eqs[i].extra || eqs[i].wrap != b.eqs[i].wrap;
      if (name == "viscous_friction") {  // in the truth already: the nominal leaves the damping out instead
        EXPECT_FALSE(changed);
        EXPECT_FALSE(e.has_knob);
        ASSERT_EQ(values.size(), 1u);
        EXPECT_EQ(values.front().second, b.value(b.velocities.front().damping));
      } else {
        EXPECT_TRUE(changed);
      }
    }
    EXPECT_THROW(make_effect(r, b, "not_an_effect", sc), InputError);
  }
}

TEST(RandomPlantEffects, StructureDecidesWhatIsAdmitted) {
  Rng r(3);
  Names names(r);
  Build tanks;
  tanks.family = "tanks";
  tanks.names = &names;
  draw_family(r, tanks);
  const std::vector<std::string> t = effects_for(tanks);
  EXPECT_NE(std::find(t.begin(), t.end(), "sqrt_outflow"), t.end());                // a linear outflow a*h
  EXPECT_EQ(std::find(t.begin(), t.end(), "coulomb_friction"), t.end());           // no velocity
  EXPECT_EQ(std::find(t.begin(), t.end(), "absolute_value_sensor"), t.end());      // levels never change sign
}
