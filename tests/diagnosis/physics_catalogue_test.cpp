// The catalogue enters models by their structure, whatever the symbols are called, and its new
// entries (bouc_wen_hysteresis, state_saturation, asymmetric_friction) are named right on plants
// simulated with them and diagnosed from a model without them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sets/data/simulation.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/diagnosis/physics_catalogue.hpp"
#include "sets/examples/random_plants.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "support/plant_fixtures.hpp"

using namespace sets;

namespace {

std::vector<Candidate> candidates_of(const ModelFile& m, const Recording& r) {
  Simulator s(m, r, {2});
  return generate_candidates(m, s.simulate(s.parameter_values()), r);
}

const Candidate* find(const std::vector<Candidate>& cs, const std::string& effect, const std::string& where) {
  for (const auto& c : cs)
    if (c.effect == effect && c.equation == where) return &c;
  return nullptr;
}

std::string names_of(const Diagnosis& d) {
  std::string s;
  for (const auto& e : d.effects) s += e.name + " (" + e.equation + ") ";
  return s.empty() ? "none: " + d.verdict : s;
}

// The plant diagnosed for its first effect only, on one thread.
Diagnosis first_effect_of(const SyntheticPlant& p) {
  DiagnosisOptions o;
  o.max_effects = 1;
  return test::diagnosed(p, o);
}

}  // namespace

TEST(PhysicsCatalogue, PlacementFollowsStructureNotNames) {
  // Two tanks in cascade with names an engineer would not use for levels.
  const std::string model = R"j({"time": "t", "inputs": {"w": "u"},
    "parameters": {"zz": {"value": 0.05, "fixed": true}, "k": 0.3, "p": 0.2, "M": 1.0},
    "states": {"q": 0.1, "vv": 0.1},
    "derivatives": {"q": "zz*w - k*q", "vv": "(k*q - p*vv)/M"}, "outputs": {"vv": "y"}})j";
  const SyntheticPlant pl = test::simulated_plant(model, model, 2000, 0.5, {"u", 0.2, 1.0, 10, 40}, 0.01, 1);
  const auto cs = candidates_of(pl.nominal, pl.estimation);
  // The linear outflow k*q is replaced everywhere it appears (out of q, into vv).
  const Candidate* sq = find(cs, "sqrt_outflow", "q");
  ASSERT_NE(sq, nullptr);
  EXPECT_EQ(sq->model.derivative("q")->find("k*q"), std::string::npos) << *sq->model.derivative("q");
  EXPECT_EQ(sq->model.derivative("vv")->find("k*q"), std::string::npos) << *sq->model.derivative("vv");
  EXPECT_NE(sq->model.derivative("vv")->find("sqrt(max(q, 0))"), std::string::npos);
  EXPECT_TRUE(sq->model.parameter("k")->fixed);  // replaced: no longer in the model
  EXPECT_NE(find(cs, "sqrt_outflow", "vv"), nullptr);
  // Levels that never change sign get no friction law; both get limits and offsets; the input is an actuator.
  EXPECT_EQ(find(cs, "coulomb_friction", "q"), nullptr);
  EXPECT_NE(find(cs, "state_saturation", "vv"), nullptr);
  EXPECT_NE(find(cs, "constant_offset", "q"), nullptr);
  EXPECT_NE(find(cs, "dead_zone", "w"), nullptr);
  EXPECT_NE(find(cs, "hysteresis", "vv"), nullptr);
  // A mechanical pair, with its velocity named "T": friction in its force balance, Bouc-Wen with a state.
  const std::string axis = R"j({"time": "t", "inputs": {"u": "u"}, "parameters": {"a": 1.0, "b": 4.0, "cc": 0.5},
    "states": {"h": 0.0, "T": 0.0}, "derivatives": {"h": "T", "T": "(u - b*h - cc*T)/a"}, "outputs": {"h": "y"}})j";
  const SyntheticPlant ax = test::simulated_plant(axis, axis, 2000, 0.01, {}, 0.01, 2);
  const auto ca = candidates_of(ax.nominal, ax.estimation);
  const Candidate* cf = find(ca, "coulomb_friction", "T");
  ASSERT_NE(cf, nullptr);
  EXPECT_EQ(*cf->model.derivative("T"), "(u - b*h - cc*T - Fc*sign(T))/a");
  const Candidate* bw = find(ca, "bouc_wen_hysteresis", "T");
  ASSERT_NE(bw, nullptr);
  EXPECT_EQ(bw->model.states.size(), 3u);
  EXPECT_EQ(bw->roles, (std::vector<std::string>{"alpha", "gamma", "delta"}));
  EXPECT_EQ(find(ca, "sqrt_outflow", "h"), nullptr);  // a position is not a level
}

TEST(PhysicsCatalogue, BoucWenHysteresisIsNamed) {
  const std::string truth = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.0, "k": 2.0, "c": 0.6},
    "states": {"x": 0.0, "v": 0.0, "z": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v - z)/m", "z": "6*v - 12*(0.5*abs(v)*z + 0.5*v*abs(z))"},
    "outputs": {"x": "x_meas"}})j";
  const std::string nominal = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.2, "k": 2.5, "c": 0.8},
    "states": {"x": 0.0, "v": 0.0}, "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})j";
  const SyntheticPlant p = test::simulated_plant(truth, nominal, 4000, 0.01, {"u", -2, 2, 1, 4}, 0.01, 7);
  const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation);
  ASSERT_FALSE(d.effects.empty()) << d.verdict;
  EXPECT_EQ(d.effects.front().name, "bouc_wen_hysteresis") << names_of(d);
  EXPECT_EQ(d.effects.front().equation, "v");
  EXPECT_GT(d.fit_augmented_validation.at(0), d.fit_nominal_validation.at(0) + 2);
}

TEST(PhysicsCatalogue, StateSaturationIsNamed) {
  // A tank that overflows at h = 0.8 (it would reach 1.4).
  const std::string truth = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"A": 2.0, "a": 0.5},
    "states": {"h": 0.3}, "derivatives": {"h": "(u - a*h)/A - max((u - a*h)/A, 0)*(h >= 0.8)"}, "outputs": {"h": "h_meas"}})j";
  const std::string nominal = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"A": 2.4, "a": 0.4},
    "states": {"h": "h_meas"}, "derivatives": {"h": "(u - a*h)/A"}, "outputs": {"h": "h_meas"}})j";
  const SyntheticPlant p = test::simulated_plant(truth, nominal, 3000, 0.1, {"u", 0.05, 0.7, 10, 40}, 0.01, 11);
  const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation);
  ASSERT_FALSE(d.effects.empty()) << d.verdict;
  EXPECT_EQ(d.effects.front().name, "state_saturation") << names_of(d);
  const auto& lim = d.effects.front().parameters.front();
  EXPECT_EQ(lim.role, "x_max");
  EXPECT_NEAR(lim.estimate, 0.8, 0.05);
}

TEST(PhysicsCatalogue, AsymmetricFrictionIsNamed) {
  const std::string truth = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.0, "k": 4.0, "c": 0.5},
    "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v - (0.15*(v > 0) - 0.6*(v < 0) + 1.5*v*(v > 0)))/m"},
    "outputs": {"x": "x_meas"}})j";
  const std::string nominal = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.2, "k": 3.5, "c": 0.7},
    "states": {"x": 0.0, "v": 0.0}, "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})j";
  const SyntheticPlant p = test::simulated_plant(truth, nominal, 4000, 0.01, {"u", -2, 2, 0.5, 3}, 0.01, 13);
  const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation);
  ASSERT_FALSE(d.effects.empty()) << d.verdict;
  EXPECT_EQ(d.effects.front().name, "asymmetric_friction") << names_of(d);
  for (const auto& ep : d.effects.front().parameters) {
    const double truth_value = ep.role == "Fc_pos" ? 0.15 : ep.role == "Fc_neg" ? 0.6 : 1.5;
    EXPECT_NEAR(ep.estimate, truth_value, 0.25 * truth_value + 0.05) << ep.role;
  }
}

// Nested hypotheses (hypotheses.cpp): every special case a law declares is made of catalogue
// effects that enter at the law's own place, and the parameters it fixes are the law's own roles.
TEST(PhysicsCatalogue, SpecialCasesAreCatalogueEffectsAtTheSamePlace) {
  const std::string model = R"j({"time": "t", "inputs": {"u": "u"},
    "parameters": {"m": 1.0, "k": 4.0, "c": 0.5},
    "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": "(u - k*x - c*v)/m"}, "outputs": {"x": "x_meas"}})j";
  const SyntheticPlant pl = test::simulated_plant(model, model, 2000, 0.01, {"u", -2, 2, 0.5, 3}, 0.01, 5);
  const auto cs = candidates_of(pl.nominal, pl.estimation);
  int declared = 0;
  for (const auto& e : physics_catalogue())
    for (const auto& sc : e.special_cases) {
      ++declared;
      const Candidate* general = find(cs, e.name, "v");
      ASSERT_NE(general, nullptr) << e.name;
      for (const auto& s : sc.effects) {
        EXPECT_NE(find_effect(s), nullptr) << s;
        EXPECT_NE(find(cs, s, "v"), nullptr) << s << " does not enter where " << e.name << " does";
      }
      EXPECT_EQ(find_special_case(sc.effects, e.name), &sc);
      for (const auto& [role, value] : sc.fixed) {
        const auto it = std::find(general->roles.begin(), general->roles.end(), role);
        ASSERT_NE(it, general->roles.end()) << e.name << " has no parameter " << role;
        EXPECT_EQ(general->neutral[static_cast<std::size_t>(it - general->roles.begin())], value) << role;
      }
    }
  EXPECT_GE(declared, 3);
  EXPECT_EQ(find_special_case({"coulomb_friction"}, "viscous_friction"), nullptr);
  EXPECT_NE(find_special_case({"constant_offset", "coulomb_friction"}, "asymmetric_friction"), nullptr);  // any order
}

// A sensor that clips at one end only: the two-sided law keeps its other limit at the estimation
// record's edge, which the data do not show, and clips the validation record where it goes further
// (validation 4.4 times the nominal's misfit: "unexplained"). The one-sided law is the sensor.
// (Seed 5 001 299: held out in the eighth session, development since; docs/reproduction/diagnosis.md.)
TEST(PhysicsCatalogue, OutputSaturationAtOneEndIsNamedWithItsOneLimit) {
  const SyntheticPlant p = random_plant(5001299);
  ASSERT_EQ(p.effects.size(), 1u);
  ASSERT_EQ(p.effects[0].name, "output_saturation");
  const Diagnosis d = first_effect_of(p);
  ASSERT_FALSE(d.effects.empty()) << d.verdict;
  EXPECT_EQ(d.effects.front().name, "output_saturation") << names_of(d);
  ASSERT_EQ(d.effects.front().parameters.size(), 1u);
  EXPECT_EQ(d.effects.front().parameters.front().role, "y_hi");
}

TEST(PhysicsCatalogue, OutputSaturationComesClippedAtBothEndsAndAtEitherOne) {
  const SyntheticPlant p = random_plant(5001299);
  std::vector<std::vector<std::string>> roles;
  for (const auto& c : candidates_of(p.nominal, p.estimation))
    if (c.effect == "output_saturation") roles.push_back(c.roles);
  std::sort(roles.begin(), roles.end());
  const std::vector<std::vector<std::string>> expected = {{"y_hi"}, {"y_lo"}, {"y_lo", "y_hi"}};
  EXPECT_EQ(roles, expected);
}

// A saturation that cuts only the drive's peaks: random plant 5 003 468 (tanks, one sine into an
// integrating level), umax = 0.93 where max|e| = 0.95 on the record, a cut of 2 %. With the grid's
// finest cut at 10 % (umax = 0.9 max|a|) Levenberg-Marquardt went from there to a deeper cut
// where the model's parameters make up for it (1.5 times the nominal's misfit), and the answer was
// "unexplained". The grid now reaches a cut of 2 %, as the dead zone's starts at 2 % of max|a|.
// (Seed 5 003 468: held out in the fifteenth session, development since.)
TEST(PhysicsCatalogue, InputSaturationCuttingOnlyTheDrivesPeaksIsNamed) {
  const SyntheticPlant p = random_plant(5003468);
  ASSERT_EQ(p.effects.size(), 1u);
  ASSERT_EQ(p.effects[0].name, "input_saturation");
  const auto cs = candidates_of(p.nominal, p.estimation);
  const Candidate* c = find(cs, "input_saturation", p.effects[0].where);
  ASSERT_NE(c, nullptr);
  double amax = 0;
  for (double v : p.estimation.column(p.nominal.inputs.front().second)) amax = std::max(amax, std::abs(v));
  double finest = 0;
  for (const auto& g : c->grid) finest = std::max(finest, g.front() / amax);
  EXPECT_NEAR(finest, 0.98, 1e-9);
  const Diagnosis d = first_effect_of(p);
  ASSERT_FALSE(d.effects.empty()) << d.verdict;
  EXPECT_EQ(d.effects.front().name, "input_saturation") << names_of(d);
  EXPECT_EQ(d.effects.front().equation, "e");
}

// A pair's delay keeps a term that is in the pair's model, also when the second effect sits at
// the delayed input and rewires it (prev(u, n) -> prev(u_sat, n)).
TEST(PhysicsCatalogue, APairsDelayTermFollowsALawAtTheSameInput) {
  const SyntheticPlant p = synthetic_plant("time_delay");
  const std::vector<Candidate> cs = candidates_of(p.nominal, p.estimation);
  const Candidate* delay = nullptr;
  for (const auto& c : cs)
    if (c.effect == "time_delay") delay = &c;
  ASSERT_NE(delay, nullptr);
  int laws = 0;
  for (const auto& second : candidates_of(delay->model, p.estimation)) {
    if (second.equation != delay->equation || second.effect == "time_delay") continue;
    const Candidate pair = combine_candidates(*delay, second);
    ASSERT_EQ(pair.parts.size(), 2u);
    const std::string& term = pair.parts[0].term;
    bool found = false;
    for (const auto& d : pair.model.derivatives) found = found || d.second.find(term) != std::string::npos;
    for (const auto& d : pair.model.signals) found = found || d.second.find(term) != std::string::npos;
    EXPECT_TRUE(found) << second.effect << ": " << term;
    ++laws;
  }
  EXPECT_GE(laws, 2);  // input saturation, dead zone, backlash
}

// A pair's delay moved to another number of samples is the pair built at that number: the same
// model text and counts, whether the second effect sits at the delayed input (and rewires it) or
// elsewhere; a candidate without a delay is left as it is.
TEST(PhysicsCatalogue, APairsDelayMovedIsThePairBuiltAtThatNumber) {
  const SyntheticPlant p = synthetic_plant("time_delay");
  const std::vector<Candidate> cs = candidates_of(p.nominal, p.estimation);
  const Candidate* delay = nullptr;
  for (const auto& c : cs)
    if (c.effect == "time_delay" && c.delay_samples == 3) delay = &c;
  ASSERT_NE(delay, nullptr);
  const Candidate other = delay_candidate(p.nominal, delay->equation, 5);
  const std::vector<Candidate> on_other = candidates_of(other.model, p.estimation);
  EXPECT_EQ(with_delay_samples(*delay, 5).model.derivatives, other.model.derivatives);
  int pairs = 0;
  for (const auto& second : candidates_of(delay->model, p.estimation)) {
    if (second.effect == "time_delay") continue;
    const Candidate* twin = nullptr;
    for (const auto& s : on_other)
      if (s.effect == second.effect && s.equation == second.equation && s.term == second.term) twin = &s;
    if (!twin) continue;
    const Candidate moved = with_delay_samples(combine_candidates(*delay, second), 5);
    const Candidate built = combine_candidates(other, *twin);
    EXPECT_EQ(moved.model.derivatives, built.model.derivatives) << second.effect;
    EXPECT_EQ(moved.model.signals, built.model.signals) << second.effect;
    EXPECT_EQ(moved.model.sampled, built.model.sampled) << second.effect;
    EXPECT_EQ(moved.parts[0].term, built.parts[0].term) << second.effect;
    EXPECT_EQ(moved.parts[0].delay_samples, 5) << second.effect;
    EXPECT_EQ(moved.delay_samples, 5) << second.effect;
    EXPECT_EQ(with_delay_samples(second, 5).model.derivatives, second.model.derivatives);
    ++pairs;
  }
  EXPECT_GE(pairs, 10);  // laws at the delayed input (which rewire it) and elsewhere
}
