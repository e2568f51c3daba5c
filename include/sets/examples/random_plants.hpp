#pragma once
// The randomised plant suite of the diagnosis (issue 14): plants that no rule can be tuned to.
// Each seed draws a family (one- and two-mass mechanics, DC motors, thermal nodes, tanks, a mass
// in a sampled PD position loop), physical magnitudes over at least four decades, random symbol
// and column names, a random sample time (from about 6 samples per period of the fastest mode to
// several hundred), an excitation from rich (random steps, PRBS, multisine, filtered noise) to
// poor (a few steps, one sine), white, coloured (AR(1)) or quantised measurement noise, and 0, 1
// or 2 effects from the whole catalogue. Each effect is weak enough to hide (scaled so that it moves
// the outputs by a drawn 4-40 % of their RMS before any calibration) and strong enough to matter
// (the plant's own structure without it, calibrated on the noise-free outputs, still misses by at
// least 2 noise levels RMS); a draw that cannot satisfy both is drawn again. The nominal model
// leaves the effects out and starts from values off by up to a factor 1.8.
// A richer friction law is also measured against its nested special case (Stribeck friction:
// Coulomb friction; asymmetric friction: Coulomb friction + a constant offset), and a dead zone
// against a constant offset at its input (what it is while the input stays on one side of the
// band; the name `special_case` covers both): the truth with the law replaced by it, its
// parameters and the plant's own free, calibrated on the noise-free outputs, RMS miss / noise
// level (TrueEffect::detectability_vs_special_case). Below the same 2 noise levels the plant is a
// plant of the special case within the noise: on its estimation record no diagnosis can tell the
// law from the special case, so such a draw is drawn again, as one that misses "without it" by
// less (RandomPlantOptions::distinct_from_special_cases; until 2026-11-29 the measure was a record
// only). It is measured after every other draw of the plant, so a plant whose laws all pass is the
// plant drawn before.
// The suite report prints it in the truth column ("vs coulomb_friction 3.37 sigma").
// See docs/reproduction/diagnosis.md.

#include <string>
#include <vector>

#include "sets/examples/synthetic_plants.hpp"

namespace sets {

/// Strong enough to matter: an effect's truth without it, calibrated on the noise-free outputs,
/// must miss by at least this many noise levels RMS (TrueEffect::detectability), and so must
/// the truth with a richer law replaced by its nested special case.
constexpr double kDetectableInNoiseLevels = 2.0;

struct RandomPlantOptions {
  int effects = -1;         // -1: 0, 1 or 2 drawn (30 / 40 / 30 %)
  std::string family;       // empty: drawn; else one of random_plant_families()
  std::string effect;       // force this effect first (tests); empty: drawn
  int samples = 0;          // 0: drawn in [2500, 5000]
  // Draw again when a law is within kDetectableInNoiseLevels of its nested special case; false
  // keeps such a plant (the generator before 2026-11-29; tests of the measure itself).
  bool distinct_from_special_cases = true;
};

std::vector<std::string> random_plant_families();
/// Every catalogue effect the generator can put into some family.
std::vector<std::string> random_plant_effects();

/// The plant of this seed (deterministic). Throws InputError when `options` ask for a family or
/// effect combination that cannot be drawn.
SyntheticPlant random_plant(unsigned seed, const RandomPlantOptions& options = {});

}  // namespace sets
