#pragma once
// The catalogue of physics a model may have left out, with stable names, and the rewriting of a
// model file that adds one of them (a "candidate"). Where an effect can enter follows from the
// model's structure, not from symbol names: an additive term in a state equation, a linear term
// a*x replaced by its nonlinear counterpart, an input or sampled signal (actuator), an output
// (sensor), a state limit, or an effect with a state of its own. See docs/physics-catalogue.md.

#include <string>
#include <vector>

#include "sets/models/model_file.hpp"
#include "sets/data/simulation.hpp"

namespace sets {

/// A catalogue effect, alone or together with others at the same place, that a richer effect
/// becomes when some of its parameters are fixed (coulomb_friction is stribeck_friction with Fs = 0).
struct SpecialCase {
  std::vector<std::string> effects;
  /// Parameters (by role) fixed at a value to get there: the data exclude the special case when
  /// the bounded-error interval of one of them excludes its value. A special case that also needs
  /// an equality between parameters (Fc_pos = Fc_neg) lists only the fixed values here.
  std::vector<std::pair<std::string, double>> fixed;
  /// (richer law's role, special case's role): parameters that equal one of the special case's
  /// there (asymmetric friction's Fc_pos = Fc_neg = Coulomb's Fc), so that the richer law can be
  /// started exactly at the special case's optimum. Only where the special case is one effect.
  std::vector<std::pair<std::string, std::string>> equal = {};
};

struct PhysicsEffect {
  std::string name;        // stable name, e.g. "coulomb_friction"
  std::string placement;   // structural place: "additive", "replaces a*x", "actuator", "sensor",
                           // "state limit", "own state"
  std::string enters;      // where it can enter a model, in words
  std::string term;        // the added term with its parameters
  std::string signature;   // what the residual looks like when it is missing
  /// What this effect becomes with some of its parameters fixed. The diagnosis names the richer
  /// law only when it passes the acceptance rules against each of them and the data exclude them
  /// (judge_round.cpp, docs/methods/diagnosis.md "Nested hypotheses").
  std::vector<SpecialCase> special_cases;
};

/// Every entry, in a fixed order.
const std::vector<PhysicsEffect>& physics_catalogue();
const PhysicsEffect* find_effect(const std::string& name);
/// The special case of `general` that `effects` (together, at one place, in any order) are; null if none.
const SpecialCase* find_special_case(std::vector<std::string> effects, const std::string& general);

/// One way of adding one effect to one place of a model.
struct Candidate {
  std::string effect;                    // catalogue name
  std::string equation;                  // the state equation, input or output it enters
  std::string term;                      // the term as written into the model
  std::vector<std::string> parameters;   // new parameter names (in the augmented model)
  std::vector<std::string> roles;        // catalogue role of each (e.g. "Fc"), independent of naming
  std::vector<double> scales;            // typical size of each new parameter (data units)
  std::vector<double> neutral;           // values of the new parameters that switch the effect off
                                         // (NaN: irrelevant once the others are neutral)
  std::vector<bool> linear;              // enters linearly with neutral 0: fitted by least squares
  /// Values of the nonlinear new parameters (in order) to screen, in units of the data
  /// (fractions of a signal's range, of a velocity's RMS); empty when every one is linear.
  std::vector<std::vector<double>> grid;
  std::vector<std::string> fixed_roles;  // roles held fixed (normalisations, e.g. Bouc-Wen beta, n)
  ModelFile model;                       // the augmented model file
  int delay_samples = 0;                 // time_delay only
  bool restart = false;  // calibrate from the file's values: the calibrated nominal may have been
                         // pulled far off by the missing structure (e.g. a mirrored sensor)
  /// Two effects at once (combine_candidates): the members, each with its own parameters; the
  /// lists above are their concatenation and `model` holds both. Empty for one effect.
  std::vector<Candidate> parts;
};

/// Two effects at once: `second` must have been generated on `first.model`.
Candidate combine_candidates(const Candidate& first, const Candidate& second);

/// The time_delay candidate for actuator `a` delayed by n samples.
Candidate delay_candidate(const ModelFile& model, const std::string& actuator, int n);

/// The signal s of a delay's term prev(s, n) as the catalogue writes it (delay_candidate, or a
/// pair's delay rewired to a later effect's signal).
std::string delayed_signal(const std::string& term);

/// `c` (a delay, or a pair with a delay member) with that delay moved to n samples, in its model,
/// terms and counts; `c` itself when it has no delay.
Candidate with_delay_samples(const Candidate& c, int n);

/// A product p*x (or x*p) of a free parameter and a state in the model's equations.
struct LinearTerm {
  std::string parameter, state;
  std::vector<std::string> equations;  // the state equations it appears in
};

/// Structure the catalogue needs: which states are positions/velocities, which symbols drive
/// the state equations (actuators), and the linear terms a*x.
struct ModelStructure {
  std::vector<std::pair<std::string, std::string>> mechanical;  // (position, velocity): q' = v
  std::vector<std::string> other_states;                        // neither a position nor a pair's velocity
  std::vector<std::string> velocities;  // a pair's velocity, or a state damped by a term p*x in its own equation
  std::vector<std::string> actuators;   // inputs/sampled used by derivatives or signals
  std::vector<LinearTerm> linear_terms;
};
ModelStructure analyse_structure(const ModelFile& model);

/// Every candidate for `model` (which may already contain earlier effects). `nominal` is a
/// simulation of it (typical sizes, grids in units of the data); `measured` the recording.
std::vector<Candidate> generate_candidates(const ModelFile& model, const SimulationResult& nominal,
                                           const Recording& measured,
                                           const std::vector<std::string>& exclude_effects = {});

/// Replaces whole-word occurrences of `symbol` in `text`.
std::string replace_symbol(const std::string& text, const std::string& symbol, const std::string& by);
/// A name not yet used in the model, starting from `wanted`.
std::string fresh_name(const ModelFile& model, const std::string& wanted);

}  // namespace sets
