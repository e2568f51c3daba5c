#pragma once
// The plant under construction of the randomised suite (src/examples/random_plants.cpp), shared
// with its two stages that live in files of their own: the families (random_plant_families.cpp)
// and the effects put into a plant's truth (random_plant_effects.cpp). Private to src/examples.

#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sets/core/error.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"

namespace sets::random_plant_detail {

constexpr double kPi = 3.14159265358979323846;

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }
  double log_uniform(double a, double b) { return std::exp(uniform(std::log(a), std::log(b))); }
  int integer(int a, int b) { return std::uniform_int_distribution<int>(a, b)(g); }
  bool chance(double p) { return uniform(0, 1) < p; }
  double normal() { return std::normal_distribution<double>(0, 1)(g); }
  template <class T>
  const T& pick(const std::vector<T>& v) { return v[static_cast<std::size_t>(integer(0, static_cast<int>(v.size()) - 1))]; }
};

inline std::string str(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}

inline std::string replace_word(const std::string& text, const std::string& word, const std::string& by) {
  const std::regex re("(^|[^A-Za-z0-9_])" + word + "(?![A-Za-z0-9_])");
  return std::regex_replace(text, re, "$1" + by);
}

// ------------------------------------------------------------------ names
// Symbol and column names: a hint an engineer might use, or random letters, decorated with digits
// or suffixes, never a muparser function or constant, t, Ts or prev.
class Names {
 public:
  explicit Names(Rng& rng) : rng_(rng) {}
  std::string operator()(const std::vector<std::string>& hints) {
    static const std::set<std::string> reserved = {
        "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "log2", "log10",
        "log", "ln", "exp", "sqrt", "sign", "rint", "abs", "min", "max", "sum", "avg", "t", "Ts", "prev", "_pi", "_e"};
    for (int attempt = 0;; ++attempt) {
      std::string n;
      const int style = rng_.integer(0, 3);
      if (style == 0 || hints.empty()) {
        const int len = rng_.integer(1, 4);
        for (int i = 0; i < len; ++i) n += static_cast<char>('a' + rng_.integer(0, 25));
      } else {
        n = rng_.pick(hints);
      }
      if (style == 2) n += std::to_string(rng_.integer(0, 9));
      if (style == 3) n += rng_.pick(std::vector<std::string>{"_", "_x", "_m", "_1", "_a"});
      if (attempt > 20) n.append("_").append(std::to_string(attempt));  // not "_" + ...: GCC 12 -Wrestrict false positive
      if (reserved.count(n) || used_.count(n)) continue;
      used_.insert(n);
      return n;
    }
  }
  void reserve(const std::string& n) { used_.insert(n); }

 private:
  Rng& rng_;
  std::set<std::string> used_;
};

// ------------------------------------------------------------------ plant under construction
struct Eq {
  std::string state;
  std::string body;     // the nominal right-hand side (inside the bracket when there is an inertia)
  std::string inertia;  // parameter dividing the bracket, or empty
  std::vector<std::string> extra;  // terms subtracted inside the bracket (effects)
  std::string wrap;     // state_saturation: a limit expression on the whole derivative
};

struct Velocity {
  std::string v, q, eq;  // friction on v in the equation eq; q its position ("" none)
  std::string damping;   // the viscous parameter of v in eq ("" none)
};

struct Build {
  std::string family;
  Names* names = nullptr;
  std::vector<ModelParameter> params;  // true values
  std::map<std::string, double> start; // nominal starting value of each free parameter
  std::vector<ModelState> states;
  NamedTexts inputs, sampled, outputs;
  std::vector<Eq> eqs;                 // one per state, in state order
  std::vector<Velocity> velocities;
  std::vector<std::pair<std::string, std::string>> springs;  // (position q, equation) with a linear k*q
  std::vector<std::pair<std::string, std::string>> levels;   // (level h, outflow parameter a) with a*h
  std::vector<std::string> actuators;  // inputs / sampled signals driving the equations
  std::vector<std::string> offset_eqs; // non-kinematic equations
  std::vector<std::string> input_cols; // recording columns of the inputs, in order
  double period = 1;                   // dominant time scale (s)
  double Ts = 0.01;
  double u_lo = -1, u_hi = 1;          // excitation levels of each input
  bool signed_outputs = true;          // outputs take both signs (absolute_value_sensor possible)
  std::vector<std::string> removed;    // nominal leaves these terms out (viscous_friction drawn)
  std::vector<std::string> removed_params;

  std::string param(const std::vector<std::string>& hints, double value, bool free, double lo = -1e300, double hi = 1e300) {
    ModelParameter p;
    p.name = (*names)(hints);
    p.value = value;
    p.fixed = !free;
    p.min = lo;
    p.max = hi;
    params.push_back(p);
    return p.name;
  }
  double value(const std::string& n) const {
    for (const auto& p : params)
      if (p.name == n) return p.value;
    throw InputError("random plant: no parameter " + n);
  }
  Eq& eq(const std::string& state) {
    for (auto& e : eqs)
      if (e.state == state) return e;
    throw InputError("random plant: no equation " + state);
  }
};

// ------------------------------------------------------------------ effects
struct Scales {  // from a simulation of the plant without effects
  std::map<std::string, double> rms, range, maxabs, mean, rate_rms, min, max;
};

// One effect put into the truth: `apply(knob)` edits a copy of the truth's parts; the knob scales
// its strength (monotone), or is ignored (fixed strength).
struct Effect {
  std::string name, where;
  bool has_knob = true;
  std::function<void(double knob, std::vector<Eq>&, NamedTexts& sampled, NamedTexts& outputs, std::vector<ModelState>&,
                     std::vector<ModelParameter>&, std::vector<std::pair<std::string, double>>& values)> apply;
  // A richer law's nested special case (Stribeck friction: Coulomb friction; asymmetric friction:
  // Coulomb friction + a constant offset), or the simpler law it equals on data that never reach
  // its nonlinearity (dead zone: a constant offset at the input while the input stays on one side
  // of the band); empty for other effects: its catalogue effects, and how to put it into the truth
  // in the law's place, its parameters free, starting at a level in [0, 1] between the ends of the
  // law at knob k.
  std::vector<std::string> special_case;
  std::function<void(double knob, double level, std::vector<Eq>&, std::vector<ModelParameter>&)> apply_special_case;
};

/// Fills b with the states, equations, outputs and true parameters of the family b.family.
void draw_family(Rng& r, Build& b);

/// Magnitudes of every simulated signal of the plant without effects.
Scales scales_of(const SimulationResult& s, double Ts);
/// The catalogue effects the plant's structure admits.
std::vector<std::string> effects_for(const Build& b);
/// The effect `name` drawn for this plant; InputError when the plant has no place for it.
Effect make_effect(Rng& r, const Build& b, const std::string& name, const Scales& sc);

}  // namespace sets::random_plant_detail
