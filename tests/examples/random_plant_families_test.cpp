// The plant families of the randomised suite (src/examples/random_plant_families.cpp): every
// family draws a consistent plant under construction — an equation per state in state order,
// outputs and effect sites that name its own symbols, distinct names, a positive time scale.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "examples/random_plant_builder.hpp"
#include "sets/core/error.hpp"
#include "sets/examples/random_plants.hpp"

using namespace sets;
using namespace sets::random_plant_detail;

namespace {

Build drawn(const std::string& family, Rng& r, Names& names) {
  Build b;
  b.family = family;
  b.names = &names;
  draw_family(r, b);
  return b;
}

}  // namespace

TEST(RandomPlantFamilies, EveryFamilyBuildsAConsistentPlant) {
  for (const std::string& family : random_plant_families()) {
    for (unsigned seed = 1; seed <= 8; ++seed) {
      Rng r(seed);
      Names names(r);
      const Build b = drawn(family, r, names);
      SCOPED_TRACE(family + ", seed " + std::to_string(seed));
      ASSERT_FALSE(b.states.empty());
      ASSERT_EQ(b.eqs.size(), b.states.size());
      std::set<std::string> states, symbols;
      for (std::size_t i = 0; i < b.states.size(); ++i) {
        EXPECT_EQ(b.eqs[i].state, b.states[i].name);  // one equation per state, in state order
        states.insert(b.states[i].name);
      }
      symbols = states;
      for (const auto& [sym, text] : b.sampled) symbols.insert(sym);
      for (const auto& [sym, col] : b.outputs) EXPECT_TRUE(symbols.count(sym)) << "output " << sym;
      for (const Velocity& v : b.velocities) {
        EXPECT_TRUE(states.count(v.v)) << v.v;
        EXPECT_TRUE(states.count(v.eq)) << v.eq;
      }
      for (const auto& [level, outflow] : b.levels) EXPECT_NO_THROW((void)b.value(outflow)) << level;
      std::set<std::string> params;
      for (const ModelParameter& p : b.params) EXPECT_TRUE(params.insert(p.name).second) << "parameter " << p.name;
      EXPECT_GT(b.period, 0);
      EXPECT_LT(b.u_lo, b.u_hi);
      EXPECT_FALSE(b.actuators.empty());
    }
  }
}

TEST(RandomPlantFamilies, UnknownFamilyIsAnInputError) {
  Rng r(1);
  Names names(r);
  EXPECT_THROW(drawn("three_mass", r, names), InputError);
}
