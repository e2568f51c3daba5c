#include "sets/examples/synthetic_plants.hpp"

#include <cmath>
#include <random>

#include "sets/core/error.hpp"
#include "sets/data/simulation.hpp"

namespace sets {

namespace {

// Piecewise-constant input: random levels in [lo, hi] held for 0.5 .. 3 s.
std::vector<double> steps(int n, double Ts, double lo, double hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> level(lo, hi), hold(0.5, 3.0);
  std::vector<double> u(static_cast<std::size_t>(n));
  double next = 0, value = level(rng);
  for (int k = 0; k < n; ++k) {
    if (k * Ts >= next) {
      value = level(rng);
      next = k * Ts + hold(rng);
    }
    u[static_cast<std::size_t>(k)] = value;
  }
  return u;
}

ModelParameter par(const std::string& n, double v, bool fixed = false) {
  ModelParameter p;
  p.name = n;
  p.value = v;
  p.fixed = fixed;
  return p;
}

// Mechanical axis on a spring: x' = v, v' = (K u - k x - c v)/m, position measured.
ModelFile axis(bool damping = true) {
  return parse_model(std::string(R"({"name": "synthetic axis on a spring", "time": "t", "inputs": {"u": "u"},
    "parameters": {"K": {"value": 1.0, "fixed": true}, "m": 1.2, "k": 3.5)") +
                         (damping ? R"(, "c": 1.0)" : "") + R"(},
    "states": {"x": 0.0, "v": 0.0},
    "derivatives": {"x": "v", "v": ")" + (damping ? "(K*u - k*x - c*v)/m" : "(K*u - k*x)/m") +
                         R"("}, "outputs": {"x": "x_meas"},
    "units": {"x": "m", "v": "m/s", "u": "N", "m": "kg", "k": "N/m"}})",
                     "synthetic axis");
}

ModelFile tank() {
  return parse_model(R"({"name": "synthetic tank with linear outflow", "time": "t", "inputs": {"u": "u"},
    "parameters": {"kin": {"value": 1.0, "fixed": true}, "A": 1.2, "a": 0.7},
    "states": {"h": "h_meas"}, "derivatives": {"h": "(kin*u - a*h)/A"}, "outputs": {"h": "h_meas"},
    "units": {"h": "m", "A": "m^2"}})",
                     "synthetic tank");
}

Recording generate(const ModelFile& truth, const std::string& out_col, int n, double Ts, double ulo, double uhi,
                   unsigned seed, double init_level, double* sigma = nullptr) {
  Recording r;
  r.source = "synthetic";
  std::vector<double> t(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) t[static_cast<std::size_t>(k)] = k * Ts;
  r.add("t", t);
  r.add("u", steps(n, Ts, ulo, uhi, seed));
  r.add(out_col, std::vector<double>(static_cast<std::size_t>(n), init_level));  // initial value for states
  Simulator sim(truth, r, {10});
  const auto res = sim.simulate(sim.parameter_values());
  Eigen::VectorXd y = res.outputs.col(0);
  const double sd = std::sqrt((y.array() - y.mean()).square().mean());
  std::mt19937 rng(seed * 7919u + 13u);
  std::normal_distribution<double> noise(0.0, 0.01 * sd);  // 1 % of the output's spread
  if (sigma) *sigma = 0.01 * sd;
  std::vector<double> meas(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) meas[static_cast<std::size_t>(k)] = y[k] + noise(rng);
  r.add(out_col, meas);
  return r;
}

}  // namespace

std::vector<std::string> synthetic_plant_names() {
  return {"coulomb_friction", "stribeck_friction", "viscous_friction", "quadratic_drag", "constant_offset",
          "cubic_stiffness",  "backlash",          "dead_zone",        "input_saturation", "output_saturation",
          "sqrt_outflow",     "time_delay",        "hysteresis",       "absolute_value_sensor",
          "clean_axis",       "clean_axis_2",      "clean_tank"};
}

SyntheticPlant synthetic_plant(const std::string& name) {
  SyntheticPlant p;
  p.name = name;
  p.true_effect = name.rfind("clean", 0) == 0 ? "none" : name;
  const bool is_tank = name == "sqrt_outflow" || name == "clean_tank";
  ModelFile nominal = is_tank ? tank() : axis(name != "viscous_friction");
  ModelFile truth = is_tank ? tank() : axis(true);
  // True values (the nominal file starts from rounder, wrong ones).
  auto set = [&](const std::string& n, double v) {
    for (auto& q : truth.parameters)
      if (q.name == n) q.value = v;
  };
  if (is_tank) {
    set("A", 1.0);
    set("a", 0.5);
  } else {
    set("m", 1.0);
    set("k", 4.0);
    set("c", 0.8);
  }
  std::string& acc = *truth.derivative(is_tank ? "h" : "v");
  const std::string base = is_tank ? "kin*u - a*h" : "K*u - k*x - c*v";
  const std::string den = is_tank ? "A" : "m";
  auto force = [&](const std::string& extra) { acc = "(" + base + " - " + extra + ")/" + den; };
  if (name == "coulomb_friction") force("0.3*sign(v)"), p.true_values = {{"Fc", 0.3}};
  if (name == "viscous_friction") p.true_values = {{"Fv", 0.8}};
  if (name == "stribeck_friction") force("sign(v)*(0.15 + 0.35*exp(-(v/0.05)^2))");
  if (name == "quadratic_drag") force("1.5*v*abs(v)"), p.true_values = {{"Cd", 1.5}};
  if (name == "constant_offset") force("0.3"), p.true_values = {{"offset", 0.3}};
  if (name == "cubic_stiffness") force("12*x^3"), p.true_values = {{"k3", 12.0}};
  if (name == "sqrt_outflow") {
    truth.parameters.push_back(par("b", 0.6));
    acc = "(kin*u - b*sqrt(max(h, 0)))/A";
    p.true_values = {{"a_sqrt", 0.6}};
    set("a", 0.0);
  }
  if (name == "backlash") {
    truth.sampled = {{"u_bl", "max(u - 0.3, min(u + 0.3, prev(u_bl, 1)))"}};
    acc = "(K*u_bl - k*x - c*v)/m";
  }
  if (name == "dead_zone") {
    truth.sampled = {{"u_dz", "u - min(max(u, -0.5), 0.5)"}};
    acc = "(K*u_dz - k*x - c*v)/m";
  }
  if (name == "input_saturation") {
    truth.sampled = {{"u_sat", "min(max(u, -1.0), 1.0)"}};
    acc = "(K*u_sat - k*x - c*v)/m";
  }
  if (name == "time_delay") acc = "(K*prev(u, 12) - k*x - c*v)/m";
  if (name == "output_saturation") {
    truth.sampled = {{"x_s", "min(max(x, -0.25), 0.3)"}};
    truth.outputs = {{"x_s", "x_meas"}};
  }
  if (name == "hysteresis") {
    truth.sampled = {{"x_h", "max(x - 0.04, min(x + 0.04, prev(x_h, 1)))"}};
    truth.outputs = {{"x_h", "x_meas"}};
  }
  if (name == "absolute_value_sensor") {
    truth.sampled = {{"x_a", "abs(x)"}};
    truth.outputs = {{"x_a", "x_meas"}};
  }
  const auto names = synthetic_plant_names();
  bool known = false;
  unsigned seed = 1;
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) known = true, seed = static_cast<unsigned>(11 + 2 * i);
  if (!known) throw InputError("unknown synthetic plant \"" + name + "\"");
  const int n = is_tank ? 4000 : 4000;
  const double Ts = is_tank ? 0.05 : 0.01;
  const double ulo = is_tank ? 0.1 : -2.0, uhi = is_tank ? 1.5 : 2.0;
  const std::string col = is_tank ? "h_meas" : "x_meas";
  const double h0 = is_tank ? 0.5 : 0.0;
  double sigma = 0;
  p.estimation = generate(truth, col, n, Ts, ulo, uhi, seed, h0, &sigma);
  p.noise_sigma = {sigma};
  p.validation = generate(truth, col, n, Ts, ulo, uhi, seed + 1000, h0, &sigma);
  p.noise_sigma_validation = {sigma};
  p.estimation.source = name + " (estimation)";
  p.validation.source = name + " (validation)";
  truth.name = "truth of synthetic plant " + name;
  nominal.name = "nominal model for synthetic plant " + name + " (effect left out)";
  p.nominal = nominal;
  p.truth = truth;
  if (p.true_effect != "none") {
    const bool actuator = name == "backlash" || name == "dead_zone" || name == "input_saturation" || name == "time_delay";
    const bool sensor = name == "output_saturation" || name == "hysteresis" || name == "absolute_value_sensor";
    const std::string where = is_tank ? "h" : actuator ? "u" : sensor ? "x" : "v";
    p.effects.push_back({name, where, p.true_values, 0.0, 0.0, {}, -1.0});
  }
  return p;
}

}  // namespace sets
