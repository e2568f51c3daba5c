#include "sets/examples/random_plants.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>

#include "sets/core/error.hpp"
#include "sets/data/simulation.hpp"
#include "sets/diagnosis/calibration.hpp"

namespace sets {

namespace {

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

std::string str(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}

std::string replace_word(const std::string& text, const std::string& word, const std::string& by) {
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
      if (attempt > 20) n += "_" + std::to_string(attempt);
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

// ------------------------------------------------------------------ excitation
struct Excitation {
  std::string kind;
  bool rich = true;
};

// A signal of n samples with levels in [lo, hi]; `period` is the plant's dominant time scale.
std::vector<double> excitation(Rng& rng, const std::string& kind, int n, double Ts, double lo, double hi, double period) {
  std::vector<double> u(static_cast<std::size_t>(n));
  const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  if (kind == "steps" || kind == "few_steps" || kind == "prbs") {
    const double total = n * Ts;
    double hold_lo = 0.5 * period, hold_hi = 4 * period;
    if (kind == "few_steps") hold_lo = total / 7, hold_hi = total / 3;
    if (kind == "prbs") hold_lo = hold_hi = std::max(Ts, 0.3 * period);
    double next = 0, value = rng.uniform(lo, hi);
    bool high = rng.chance(0.5);
    for (int k = 0; k < n; ++k) {
      if (k * Ts >= next) {
        high = !high;
        value = kind == "prbs" ? (high ? hi : lo) : rng.uniform(lo, hi);
        next = k * Ts + (kind == "prbs" ? hold_lo * rng.integer(1, 4) : rng.uniform(hold_lo, hold_hi));
      }
      u[static_cast<std::size_t>(k)] = value;
    }
  } else if (kind == "multisine" || kind == "sine") {
    const int lines = kind == "sine" ? 1 : rng.integer(5, 15);
    const double fmax = std::min(0.4 / Ts, 3.0 / period), fmin = 1.0 / (n * Ts);
    std::vector<double> f, phase;
    for (int i = 0; i < lines; ++i) {
      f.push_back(kind == "sine" ? rng.uniform(0.3, 1.5) / period : rng.log_uniform(std::max(fmin * 3, fmax / 100), fmax));
      phase.push_back(rng.uniform(0, 2 * kPi));
    }
    double peak = 0;
    for (int k = 0; k < n; ++k) {
      double s = 0;
      for (int i = 0; i < lines; ++i) s += std::sin(2 * kPi * f[static_cast<std::size_t>(i)] * k * Ts + phase[static_cast<std::size_t>(i)]);
      u[static_cast<std::size_t>(k)] = s;
      peak = std::max(peak, std::abs(s));
    }
    for (auto& x : u) x = mid + half * x / std::max(peak, 1e-12);
  } else {  // filtered Gaussian noise, first order with the plant's time scale
    const double a = std::exp(-Ts / std::max(0.3 * period, Ts));
    double x = 0, peak = 0;
    for (int k = 0; k < n; ++k) {
      x = a * x + std::sqrt(1 - a * a) * rng.normal();
      u[static_cast<std::size_t>(k)] = x;
      peak = std::max(peak, std::abs(x));
    }
    for (auto& v : u) v = mid + half * std::clamp(v / std::max(0.8 * peak, 1e-12), -1.0, 1.0);
  }
  return u;
}

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

// ------------------------------------------------------------------ families
void one_mass(Rng& r, Build& b) {
  Names& N = *b.names;
  const double m = r.log_uniform(1e-2, 1e3), wn = r.log_uniform(0.3, 300), zeta = r.uniform(0.05, 0.7);
  const double K = r.log_uniform(0.1, 10);
  const std::string x = N({"x", "pos", "y", "q", "z"}), v = N({"v", "vel", "xd", "w", "dq"});
  const std::string u = N({"u", "F", "force", "in"});
  const std::string pm = b.param({"m", "M", "mass"}, m, true, 0), pk = b.param({"k", "K", "stiff"}, m * wn * wn, true);
  const std::string pc = b.param({"c", "d", "damp", "b"}, 2 * zeta * m * wn, true), pK = b.param({"g", "kf", "gain"}, K, false);
  b.states = {{x, 0.0, ""}, {v, 0.0, ""}};
  b.inputs = {{u, N({"u", "force", "F_in", "cmd"})}};
  b.eqs = {{x, v, "", {}, ""}, {v, pK + "*" + u + " - " + pk + "*" + x + " - " + pc + "*" + v, pm, {}, ""}};
  b.outputs = {{x, N({"x_meas", "pos", "y", "xm"})}};
  b.velocities = {{v, x, v, pc}};
  b.springs = {{x, v}};
  b.actuators = {u};
  b.offset_eqs = {v};
  b.period = 2 * kPi / wn;
  const double A = r.log_uniform(0.1, 100);
  b.u_lo = -A, b.u_hi = A;
}

void two_mass(Rng& r, Build& b) {
  Names& N = *b.names;
  const double m1 = r.log_uniform(1e-2, 1e3), m2 = m1 * r.log_uniform(0.3, 3);
  const double w12 = r.log_uniform(1, 300), w2 = w12 * r.log_uniform(0.2, 1.0);
  const double k12 = m2 * w12 * w12, k2 = m2 * w2 * w2;
  const double c12 = 2 * r.uniform(0.03, 0.3) * m2 * w12, c2 = 2 * r.uniform(0.05, 0.5) * m2 * w2;
  const double K = r.log_uniform(0.1, 10);
  const std::string x1 = N({"x1", "q1", "p1"}), v1 = N({"v1", "w1", "dq1"}), x2 = N({"x2", "q2", "p2"}), v2 = N({"v2", "w2", "dq2"});
  const std::string u = N({"u", "F", "tau"});
  const std::string pm1 = b.param({"m1", "M1", "J1"}, m1, false), pm2 = b.param({"m2", "M2", "J2"}, m2, true, 0);
  const std::string pk12 = b.param({"k12", "ks", "kc"}, k12, true), pc12 = b.param({"c12", "cs", "dc"}, c12, true);
  const std::string pk2 = b.param({"k2", "kg"}, k2, true), pc2 = b.param({"c2", "dg"}, c2, true);
  const std::string pK = b.param({"g", "kf"}, K, false);
  b.states = {{x1, 0.0, ""}, {v1, 0.0, ""}, {x2, 0.0, ""}, {v2, 0.0, ""}};
  b.inputs = {{u, N({"u", "force", "cmd"})}};
  const std::string coupling = pk12 + "*(" + x1 + " - " + x2 + ") + " + pc12 + "*(" + v1 + " - " + v2 + ")";
  b.eqs = {{x1, v1, "", {}, ""},
           {v1, pK + "*" + u + " - (" + coupling + ")", pm1, {}, ""},
           {x2, v2, "", {}, ""},
           {v2, coupling + " - " + pk2 + "*" + x2 + " - " + pc2 + "*" + v2, pm2, {}, ""}};
  b.outputs = {{x2, N({"x2_meas", "y", "pos2"})}};
  if (r.chance(0.5)) b.outputs.push_back({x1, N({"x1_meas", "pos1", "enc"})});
  b.velocities = {{v2, x2, v2, pc2}, {v1, x1, v1, ""}};
  b.springs = {{x2, v2}};
  b.actuators = {u};
  b.offset_eqs = {v1, v2};
  b.period = 2 * kPi / std::min(w12, w2);
  const double A = r.log_uniform(0.1, 100);
  b.u_lo = -A, b.u_hi = A;
}

void motor(Rng& r, Build& b) {
  Names& N = *b.names;
  const double R = r.log_uniform(0.1, 30), km = r.log_uniform(0.01, 1), tau_m = r.log_uniform(0.01, 10);
  const double J = tau_m * km * km / R, bv = r.uniform(0.05, 0.5) * km * km / R;
  const double rho = r.log_uniform(5, 50), L = R * tau_m / rho;
  const std::string i = N({"i", "cur", "ia"}), w = N({"w", "omega", "n", "speed"}), V = N({"V", "u", "volt"});
  const std::string pR = b.param({"R", "Ra", "res"}, R, false), pL = b.param({"L", "La", "ind"}, L, false);
  const std::string pk = b.param({"km", "kt", "ke", "Kb"}, km, true, 0), pJ = b.param({"J", "Jm", "inertia"}, J, true, 0);
  const std::string pb = b.param({"b", "Bm", "fric"}, bv, true);
  b.states = {{i, 0.0, ""}, {w, 0.0, ""}};
  b.inputs = {{V, N({"V", "u", "volt_cmd"})}};
  b.eqs = {{i, V + " - " + pR + "*" + i + " - " + pk + "*" + w, pL, {}, ""}, {w, pk + "*" + i + " - " + pb + "*" + w, pJ, {}, ""}};
  b.outputs = {{w, N({"speed", "w_meas", "rpm"})}};
  if (r.chance(0.5)) b.outputs.push_back({i, N({"current", "i_meas", "amps"})});
  b.velocities = {{w, "", w, pb}};
  b.actuators = {V};
  b.offset_eqs = {w, i};
  b.period = tau_m;
  const double A = r.log_uniform(1, 30);
  b.u_lo = -A, b.u_hi = A;
}

void thermal(Rng& r, Build& b) {
  Names& N = *b.names;
  const double Ta = r.uniform(-10, 40);
  const std::string P = N({"P", "q", "heat", "u"});
  const std::string pTa = b.param({"Ta", "Tamb", "T0"}, Ta, false);
  b.inputs = {{P, N({"power", "P", "heater"})}};
  const double Pmax = r.log_uniform(1, 1e3);
  b.u_lo = 0, b.u_hi = Pmax;
  b.signed_outputs = false;
  if (r.chance(0.5)) {
    const double R = r.log_uniform(0.01, 10), tau = r.log_uniform(1, 1e3);
    const std::string T = N({"T", "temp", "theta"});
    const std::string pR = b.param({"R", "Rth", "Rt"}, R, true, 0), pC = b.param({"C", "Cth", "cap"}, tau / R, true, 0);
    b.states = {{T, Ta, ""}};
    b.eqs = {{T, P + " - (" + T + " - " + pTa + ")/" + pR, pC, {}, ""}};
    b.outputs = {{T, N({"T_meas", "temp", "thermo"})}};
    b.offset_eqs = {T};
    b.period = tau;
  } else {
    const double R12 = r.log_uniform(0.01, 10), R2 = R12 * r.log_uniform(0.3, 3);
    const double tau1 = r.log_uniform(1, 1e3), tau2 = tau1 * r.log_uniform(1, 10);
    const std::string T1 = N({"T1", "Tcore", "th1"}), T2 = N({"T2", "Tcase", "th2"});
    const std::string pR12 = b.param({"R12", "Rc"}, R12, true, 0), pR2 = b.param({"R2", "Ra"}, R2, true, 0);
    const std::string pC1 = b.param({"C1", "Cc"}, tau1 / R12, true, 0), pC2 = b.param({"C2", "Cs"}, tau2 / R2, true, 0);
    b.states = {{T1, Ta, ""}, {T2, Ta, ""}};
    b.eqs = {{T1, P + " - (" + T1 + " - " + T2 + ")/" + pR12, pC1, {}, ""},
             {T2, "(" + T1 + " - " + T2 + ")/" + pR12 + " - (" + T2 + " - " + pTa + ")/" + pR2, pC2, {}, ""}};
    b.outputs = {{T2, N({"T2_meas", "case_temp", "Ts_meas"})}};
    if (r.chance(0.5)) b.outputs.push_back({T1, N({"T1_meas", "core_temp"})});
    b.offset_eqs = {T1, T2};
    b.period = tau2;
  }
  b.actuators = {P};
}

void tanks(Rng& r, Build& b) {
  Names& N = *b.names;
  const std::string u = N({"u", "pump", "q_in", "flow"});
  const double kin = r.log_uniform(1e-3, 1e-1);
  const std::string pk = b.param({"kin", "kp", "qmax"}, kin, false);
  b.inputs = {{u, N({"pump", "u", "valve"})}};
  b.u_lo = r.uniform(0.05, 0.3), b.u_hi = r.uniform(0.7, 1.0);
  b.signed_outputs = false;
  const double A1 = r.log_uniform(1e-2, 10), tau1 = r.log_uniform(1, 1e3), a1 = A1 / tau1;
  const std::string h1 = N({"h", "h1", "level", "L1"});
  const std::string pA1 = b.param({"A", "A1", "area"}, A1, r.chance(0.5), 0), pa1 = b.param({"a", "a1", "kout"}, a1, true, 0);
  const double h1_eq = kin * 0.5 * (b.u_lo + b.u_hi) / a1;
  b.states = {{h1, h1_eq, ""}};
  b.eqs = {{h1, pk + "*" + u + " - " + pa1 + "*" + h1, pA1, {}, ""}};
  b.levels = {{h1, pa1}};
  b.offset_eqs = {h1};
  b.period = tau1;
  if (r.chance(0.5)) {
    if (!b.params[1].fixed) b.params[1].fixed = true;  // A1 known when the second tank's area is free
    const double A2 = A1 * r.log_uniform(0.3, 3), tau2 = tau1 * r.log_uniform(0.3, 3), a2 = A2 / tau2;
    const std::string h2 = N({"h2", "L2", "level2"});
    const std::string pA2 = b.param({"A2", "area2"}, A2, true, 0), pa2 = b.param({"a2", "kout2"}, a2, true, 0);
    b.states.push_back({h2, kin * 0.5 * (b.u_lo + b.u_hi) / a2, ""});
    b.eqs.push_back({h2, pa1 + "*" + h1 + " - " + pa2 + "*" + h2, pA2, {}, ""});
    b.levels.push_back({h2, pa2});
    b.offset_eqs.push_back(h2);
    b.outputs = {{h2, N({"h2_meas", "level2", "L2m"})}};
    if (r.chance(0.5)) b.outputs.push_back({h1, N({"h1_meas", "level1", "L1m"})});
    b.period = std::max(tau1, tau2);
  } else {
    b.outputs = {{h1, N({"h_meas", "level", "Lm"})}};
  }
  b.actuators = {u};
}

void position_loop(Rng& r, Build& b) {
  Names& N = *b.names;
  const double m = r.log_uniform(0.1, 1e3), g = r.log_uniform(0.1, 100), wc = r.log_uniform(1, 100);
  const double c = m * wc * r.uniform(0.02, 0.5);
  const double Kp = m * wc * wc / g, Kd = std::max(0.0, 1.4 * m * wc - c) / g;
  const std::string q = N({"q", "x", "pos"}), v = N({"v", "qd", "vel"}), ref = N({"r", "ref", "qr"}), u = N({"u", "cmd", "volt"});
  const std::string pm = b.param({"M", "m", "mass"}, m, true, 0), pc = b.param({"Fv", "c", "visc"}, c, true);
  const std::string pg = b.param({"gtau", "kf", "g"}, g, false), pKp = b.param({"kp", "Kp", "P"}, Kp, false);
  const std::string pKd = b.param({"kd", "Kd", "D"}, Kd, false);
  b.states = {{q, 0.0, ""}, {v, 0.0, ""}};
  b.inputs = {{ref, N({"q_ref", "ref", "setpoint"})}};
  b.sampled = {{u, pKp + "*(" + ref + " - " + q + ") - " + pKd + "*(" + q + " - prev(" + q + ", 1))/Ts"}};
  b.eqs = {{q, v, "", {}, ""}, {v, pg + "*" + u + " - " + pc + "*" + v, pm, {}, ""}};
  b.outputs = {{q, N({"q_meas", "pos", "enc"})}};
  if (r.chance(0.5)) b.outputs.push_back({u, N({"u", "cmd_meas", "drive"})});
  b.velocities = {{v, q, v, pc}};
  b.actuators = {u};
  b.offset_eqs = {v};
  b.period = 2 * kPi / wc;
  const double A = r.log_uniform(1e-3, 1);
  b.u_lo = -A, b.u_hi = A;
}

// ------------------------------------------------------------------ model files
std::string derivative_text(const Eq& e, const std::vector<std::string>& removed) {
  std::string body = e.body;
  for (const auto& term : removed) {  // " - c*v" left out of the nominal
    const auto at = body.find(" - " + term);
    if (at != std::string::npos) body.erase(at, term.size() + 3);
  }
  for (const auto& x : e.extra) body += " - " + x;
  std::string d = e.inertia.empty() ? body : "(" + body + ")/" + e.inertia;
  if (!e.wrap.empty()) d = replace_word(e.wrap, "@f", "(" + d + ")");
  return d;
}

ModelFile model_of(const Build& b, const std::vector<Eq>& eqs, const NamedTexts& sampled, const NamedTexts& outputs,
                   const std::vector<ModelState>& states, const std::vector<std::string>& removed,
                   const std::vector<ModelParameter>& params, const std::string& time_col) {
  ModelFile m;
  m.time_column = time_col;
  m.inputs = b.inputs;
  m.parameters = params;
  m.states = states;
  m.sampled = sampled;
  for (const auto& e : eqs) m.derivatives.emplace_back(e.state, derivative_text(e, removed));
  m.outputs = outputs;
  return m;
}

// ------------------------------------------------------------------ effects
struct Scales {  // from a simulation of the plant without effects
  std::map<std::string, double> rms, range, maxabs, mean, rate_rms, min, max;
};

Scales scales_of(const SimulationResult& s, double Ts) {
  Scales sc;
  for (std::size_t i = 0; i < s.names.size(); ++i) {
    const Eigen::VectorXd x = s.values.col(static_cast<Eigen::Index>(i));
    const auto n = static_cast<double>(x.size());
    sc.rms[s.names[i]] = std::sqrt(x.squaredNorm() / n);
    sc.range[s.names[i]] = x.maxCoeff() - x.minCoeff();
    sc.maxabs[s.names[i]] = x.cwiseAbs().maxCoeff();
    sc.mean[s.names[i]] = x.mean();
    sc.min[s.names[i]] = x.minCoeff();
    sc.max[s.names[i]] = x.maxCoeff();
    double r = 0;
    for (Eigen::Index k = 1; k < x.size(); ++k) r += (x[k] - x[k - 1]) * (x[k] - x[k - 1]);
    sc.rate_rms[s.names[i]] = std::sqrt(r / std::max(1.0, n - 1)) / Ts;
  }
  return sc;
}

// One effect put into the truth: `apply(knob)` edits a copy of the truth's parts; the knob scales
// its strength (monotone), or is ignored (fixed strength).
struct Effect {
  std::string name, where;
  bool has_knob = true;
  std::function<void(double knob, std::vector<Eq>&, NamedTexts& sampled, NamedTexts& outputs, std::vector<ModelState>&,
                     std::vector<ModelParameter>&, std::vector<std::pair<std::string, double>>& values)> apply;
};

std::vector<std::string> effects_for(const Build& b) {
  std::vector<std::string> e;
  if (!b.velocities.empty()) {
    for (const char* n : {"coulomb_friction", "stribeck_friction", "quadratic_drag", "asymmetric_friction"}) e.push_back(n);
    if (!b.velocities.front().damping.empty() && b.family != "position_loop") e.push_back("viscous_friction");
  }
  if (!b.springs.empty()) e.push_back("cubic_stiffness"), e.push_back("bouc_wen_hysteresis");
  if (!b.offset_eqs.empty()) e.push_back("constant_offset");
  for (const char* n : {"dead_zone", "input_saturation", "backlash", "time_delay", "output_saturation", "hysteresis"}) e.push_back(n);
  if (b.signed_outputs) e.push_back("absolute_value_sensor");
  if (!b.levels.empty()) e.push_back("sqrt_outflow"), e.push_back("state_saturation");
  return e;
}

// The effects' shared tools: a new fixed parameter of the truth, an equation by its state, and
// the force scale of an equation (its inertia times the RMS rate of its state).
std::string new_fixed_param(Names& names, std::vector<ModelParameter>& ps, const std::vector<std::string>& hints, double v) {
  ModelParameter p;
  p.name = names(hints);
  p.value = v;
  p.fixed = true;
  ps.push_back(p);
  return p.name;
}

Eq& equation_of(std::vector<Eq>& eqs, const std::string& state) {
  for (auto& e : eqs)
    if (e.state == state) return e;
  throw InputError("random plant: no equation " + state);
}

double force_scale(const Build& b, const Scales& sc, const std::string& eq_state) {
  for (const auto& e : b.eqs)
    if (e.state == eq_state) return (e.inertia.empty() ? 1.0 : b.value(e.inertia)) * std::max(sc.rate_rms.at(eq_state), 1e-300);
  return 1.0;
}

// The lambdas below run later, many times: they capture the name generator by pointer.
Effect friction_effect(Rng& r, const Build& b, const std::string& name, const Scales& sc) {
  Effect E;
  E.name = name;
  Names* names = b.names;
  // Friction acts on the first velocity (the measured side of a two-mass drive, or the other one).
  const Velocity vel = name == "viscous_friction" ? b.velocities.front() : r.pick(b.velocities);
  E.where = vel.eq;
  const double F = force_scale(b, sc, vel.eq), vr = std::max(sc.rms.at(vel.v), 1e-300);
  const std::string v = vel.v;
  if (name == "coulomb_friction") {
    const bool smooth = r.chance(0.3);  // a tanh-smoothed law: maps onto Fc but not exactly
    const double eps = r.uniform(0.005, 0.03) * vr;
    E.apply = [=](double k, auto& eqs, auto&, auto&, auto&, auto& ps, auto& values) {
      const std::string Fc = new_fixed_param(*names, ps, {"Fc", "fc", "Fcoul"}, k * F);
      equation_of(eqs, vel.eq).extra.push_back(smooth ? Fc + "*tanh(" + v + "/" + str(eps) + ")" : Fc + "*sign(" + v + ")");
      if (!smooth) values = {{"Fc", k * F}};
    };
  } else if (name == "stribeck_friction") {
    const double ratio = r.uniform(1.0, 3.0), vs = r.uniform(0.1, 0.5) * vr;
    const bool exponent2 = r.chance(0.7);
    E.apply = [=](double k, auto& eqs, auto&, auto&, auto&, auto& ps, auto& values) {
      const std::string Fc = new_fixed_param(*names, ps, {"Fc", "fc"}, k * F);
      const std::string Fs = new_fixed_param(*names, ps, {"Fs", "fs"}, k * F * ratio);
      const std::string law = exponent2 ? "exp(-(" + v + "/" + str(vs) + ")^2)" : "exp(-abs(" + v + ")/" + str(vs) + ")";
      equation_of(eqs, vel.eq).extra.push_back("sign(" + v + ")*(" + Fc + " + " + Fs + "*" + law + ")");
      if (exponent2) values = {{"Fc", k * F}, {"Fs", k * F * ratio}, {"vs", vs}};
    };
  } else if (name == "quadratic_drag") {
    E.apply = [=](double k, auto& eqs, auto&, auto&, auto&, auto& ps, auto& values) {
      const std::string Cd = new_fixed_param(*names, ps, {"Cd", "cd", "drag"}, k * F / (vr * vr));
      equation_of(eqs, vel.eq).extra.push_back(Cd + "*" + v + "*abs(" + v + ")");
      values = {{"Cd", k * F / (vr * vr)}};
    };
  } else if (name == "asymmetric_friction") {
    const double a = r.uniform(0.2, 1.0), bneg = a * r.pick(std::vector<double>{r.uniform(0.1, 0.5), r.uniform(2.0, 5.0)});
    const double dv = (r.chance(0.5) ? 1 : -1) * r.uniform(0.5, 1.5);
    E.apply = [=](double k, auto& eqs, auto&, auto&, auto&, auto& ps, auto& values) {
      const double fp = k * F * a, fn = k * F * bneg, dfv = k * F / vr * dv;
      const std::string P = new_fixed_param(*names, ps, {"Fcp", "fpos"}, fp), M = new_fixed_param(*names, ps, {"Fcn", "fneg"}, fn);
      const std::string D = new_fixed_param(*names, ps, {"dFv", "dvisc"}, dfv);
      equation_of(eqs, vel.eq).extra.push_back("(" + P + "*(" + v + " > 0) - " + M + "*(" + v + " < 0) + " + D + "*" + v + "*(" + v + " > 0))");
      values = {{"Fc_pos", fp}, {"Fc_neg", fn}, {"dFv", dfv}};
    };
  } else {  // viscous_friction: the nominal leaves the damping out
    E.has_knob = false;
    E.apply = [=](double, auto&, auto&, auto&, auto&, auto&, auto& values) { values = {{"Fv", b.value(vel.damping)}}; };
  }
  return E;
}

Effect spring_effect(Rng& r, const Build& b, const std::string& name, const Scales& sc) {
  Effect E;
  E.name = name;
  Names* names = b.names;
  // Named copies, not a structured binding: clang 14 (the sanitizer and fuzz builds) cannot capture one.
  const auto& spring = r.pick(b.springs);
  const std::string q = spring.first, eq = spring.second;
  E.where = eq;
  const double F = force_scale(b, sc, eq), qr = std::max(sc.rms.at(q), 1e-300), qrange = std::max(sc.range.at(q), 1e-300);
  if (name == "cubic_stiffness") {
    E.apply = [=](double k, auto& eqs, auto&, auto&, auto&, auto& ps, auto& values) {
      const double k3 = k * F / (qr * qr * qr);
      equation_of(eqs, eq).extra.push_back(new_fixed_param(*names, ps, {"k3", "kc", "knl"}, k3) + "*" + q + "^3");
      values = {{"k3", k3}};
    };
    return E;
  }
  std::string v;  // bouc_wen_hysteresis
  for (const auto& vel : b.velocities)
    if (vel.q == q) v = vel.v;
  const double yield = r.uniform(0.05, 0.3) * qrange, share = r.uniform(0.3, 0.9), sum = 1.0 / yield;
  E.apply = [=](double k, auto& eqs, auto&, auto&, auto& states, auto& ps, auto& values) {
    // z' = alpha v - beta (gamma |v| |z|^(n-1) z + delta v |z|^n), n = 1, force -z: z saturates
    // at alpha * yield (beta gamma + beta delta = 1 / yield), so the knob scales the force.
    const double alpha = k * F / yield;
    const std::string z = (*names)({"z", "zh", "bw"});
    const std::string pa = new_fixed_param(*names, ps, {"alpha", "kbw"}, alpha);
    const std::string pg = new_fixed_param(*names, ps, {"gam", "gbw"}, share * sum);
    const std::string pd = new_fixed_param(*names, ps, {"del", "dbw"}, (1 - share) * sum);
    states.push_back({z, 0.0, ""});
    Eq ez{z, pa + "*" + v + " - (" + pg + "*abs(" + v + ")*" + z + " + " + pd + "*" + v + "*abs(" + z + "))", "", {}, ""};
    eqs.push_back(ez);
    equation_of(eqs, eq).extra.push_back(z);
    values = {{"alpha", alpha}};
  };
  return E;
}

Effect offset_effect(Rng& r, const Build& b, const Scales& sc) {
  Effect E;
  E.name = "constant_offset";
  Names* names = b.names;
  const std::string eq = r.pick(b.offset_eqs);
  E.where = eq;
  const double F = force_scale(b, sc, eq), sgn = r.chance(0.5) ? 1 : -1;
  E.apply = [=](double k, auto& eqs, auto&, auto&, auto&, auto& ps, auto& values) {
    const double off = sgn * k * F;
    equation_of(eqs, eq).extra.push_back(new_fixed_param(*names, ps, {"off", "bias", "d0"}, off));
    values = {{"offset", off}};
  };
  return E;
}

// dead_zone, input_saturation, backlash, time_delay: a sampled signal between an input and the equations.
Effect actuator_effect(Rng& r, const Build& b, const std::string& name, const Scales& sc) {
  Effect E;
  E.name = name;
  Names* names = b.names;
  const std::string a = r.pick(b.actuators);
  E.where = a;
  const double amax = std::max(sc.maxabs.at(a), 1e-300), arange = std::max(sc.range.at(a), 1e-300);
  const double Ts = b.Ts, period = b.period;
  E.apply = [=](double k, auto& eqs, auto& sampled, auto&, auto&, auto& ps, auto& values) {
    const std::string s = (*names)({a + "_eff", a + "_act", "ua"});
    std::string expr;
    if (name == "dead_zone") {
      const double d = amax * k / (1 + k);
      const std::string p = new_fixed_param(*names, ps, {"d", "dz", "deadband"}, d);
      expr = a + " - min(max(" + a + ", -" + p + "), " + p + ")";
      values = {{"d", d}};
    } else if (name == "input_saturation") {
      const double umax = amax / (1 + k);
      const std::string p = new_fixed_param(*names, ps, {"umax", "sat", "lim"}, umax);
      expr = "min(max(" + a + ", -" + p + "), " + p + ")";
      values = {{"umax", umax}};
    } else if (name == "backlash") {
      const double w = arange * k / (1 + k) / 2;
      const std::string p = new_fixed_param(*names, ps, {"play", "bl", "gap"}, w);
      expr = "max(" + a + " - " + p + ", min(" + a + " + " + p + ", prev(" + s + ", 1)))";
      values = {{"b", w}};
    } else {
      const int n = std::max(1, static_cast<int>(std::lround(k * period / Ts)));
      expr = "prev(" + a + ", " + std::to_string(n) + ")";
      values = {{"n", static_cast<double>(n)}};
    }
    sampled.emplace_back(s, expr);
    for (auto& e : eqs) e.body = replace_word(e.body, a, s);
  };
  return E;
}

// output_saturation, hysteresis, absolute_value_sensor: a sampled signal between a state and an output.
Effect sensor_effect(Rng& r, const Build& b, const std::string& name, const Scales& sc) {
  Effect E;
  E.name = name;
  Names* names = b.names;
  std::vector<std::string> sensed;  // outputs that are states (not a recorded command)
  for (const auto& [sym, col] : b.outputs)
    for (const auto& st : b.states)
      if (st.name == sym) sensed.push_back(sym);
  const std::string y = r.pick(sensed);
  E.where = y;
  const double lo = sc.min.at(y), top = sc.max.at(y), range = std::max(sc.range.at(y), 1e-300);
  const bool both = r.chance(0.5), upper = r.chance(0.5);
  if (name == "absolute_value_sensor") E.has_knob = false;
  E.apply = [=](double k, auto&, auto& sampled, auto& outputs, auto&, auto& ps, auto& values) {
    const std::string s = (*names)({y + "_s", y + "_sens", "ys"});
    std::string expr;
    if (name == "output_saturation") {
      // Clip a fraction k/(1+k) of the range off one end (or at most 45 % off both).
      const double cut = range * k / (1 + k) * (both ? 0.45 : 1.0);
      const double hi = top + (upper || both ? -cut : 1e3 * range);
      const double lo2 = lo + (!upper || both ? cut : -1e3 * range);
      const std::string ph = new_fixed_param(*names, ps, {"ymax", "yhi"}, hi);
      const std::string pl = new_fixed_param(*names, ps, {"ymin", "ylo"}, lo2);
      expr = "min(max(" + y + ", " + pl + "), " + ph + ")";
      values.clear();
      if (upper || both) values.push_back({"y_hi", hi});
      if (!upper || both) values.push_back({"y_lo", lo2});
    } else if (name == "hysteresis") {
      const double w = range * 0.1 * k;
      const std::string p = new_fixed_param(*names, ps, {"w", "play_s", "hw"}, w);
      expr = "max(" + y + " - " + p + ", min(" + y + " + " + p + ", prev(" + s + ", 1)))";
      values = {{"w", w}};
    } else {
      expr = "abs(" + y + ")";
    }
    sampled.emplace_back(s, expr);
    for (auto& o : outputs)
      if (o.first == y) o.first = s;
  };
  return E;
}

// sqrt_outflow (replaces a linear outflow a*h) and state_saturation (a level that cannot pass a limit).
Effect level_effect(Rng& r, const Build& b, const std::string& name, const Scales& sc) {
  Effect E;
  E.name = name;
  Names* names = b.names;
  const auto& level = r.pick(b.levels);  // named copies: see spring_effect
  const std::string h = level.first, a = level.second;
  E.where = h;
  const double hm = std::max(sc.mean.at(h), 1e-300), hmax = sc.max.at(h), hrange = sc.range.at(h);
  if (name == "sqrt_outflow") {
    E.has_knob = false;
    const double av = b.value(a);
    E.apply = [=](double, auto& eqs, auto&, auto&, auto&, auto& ps, auto& values) {
      // Same outflow at the mean level: a h = as sqrt(h) there.
      const double as = av * std::sqrt(hm);
      const std::string p = new_fixed_param(*names, ps, {"as", "cv", "kv"}, as);
      for (auto& e : eqs) e.body = std::regex_replace(e.body, std::regex("\\b" + a + "\\*" + h + "\\b"), p + "*sqrt(max(" + h + ", 0))");
      values = {{"a_sqrt", as}};
    };
    return E;
  }
  E.apply = [=](double k, auto& eqs, auto&, auto&, auto&, auto& ps, auto& values) {
    const double lim = hmax - hrange * k / (1 + k);
    const std::string p = new_fixed_param(*names, ps, {"hmax", "hlim", "top"}, lim);
    equation_of(eqs, h).wrap = "@f - max(@f, 0)*(" + h + " >= " + p + ")";
    values = {{"x_max", lim}};
  };
  return E;
}

Effect make_effect(Rng& r, const Build& b, const std::string& name, const Scales& sc) {
  static const std::set<std::string> friction = {"coulomb_friction", "stribeck_friction", "quadratic_drag",
                                                 "asymmetric_friction", "viscous_friction"};
  static const std::set<std::string> spring = {"cubic_stiffness", "bouc_wen_hysteresis"};
  static const std::set<std::string> actuator = {"dead_zone", "input_saturation", "backlash", "time_delay"};
  static const std::set<std::string> sensor = {"output_saturation", "hysteresis", "absolute_value_sensor"};
  static const std::set<std::string> level = {"sqrt_outflow", "state_saturation"};
  if (friction.count(name)) return friction_effect(r, b, name, sc);
  if (spring.count(name)) return spring_effect(r, b, name, sc);
  if (name == "constant_offset") return offset_effect(r, b, sc);
  if (actuator.count(name)) return actuator_effect(r, b, name, sc);
  if (sensor.count(name)) return sensor_effect(r, b, name, sc);
  if (level.count(name)) return level_effect(r, b, name, sc);
  throw InputError("random plant: effect " + name + " not available here");
}

// ------------------------------------------------------------------ noise
std::vector<double> add_noise(Rng& r, const Eigen::VectorXd& y, const std::string& kind, double sigma) {
  std::vector<double> out(static_cast<std::size_t>(y.size()));
  const double a = r.uniform(0.6, 0.95);
  double e = 0;
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    double v = y[k];
    if (kind == "white") v += sigma * r.normal();
    if (kind == "coloured") {
      e = a * e + std::sqrt(1 - a * a) * sigma * r.normal();  // AR(1) with marginal std sigma
      v += e;
    }
    if (kind == "quantised") {
      const double q = sigma * std::sqrt(12.0);
      v = q * std::round((v + 0.1 * sigma * r.normal()) / q);
    }
    out[static_cast<std::size_t>(k)] = v;
  }
  return out;
}

// ------------------------------------------------------------------ the stages of random_plant
void draw_family(Rng& r, Build& b) {
  if (b.family == "one_mass") one_mass(r, b);
  else if (b.family == "two_mass") two_mass(r, b);
  else if (b.family == "motor") motor(r, b);
  else if (b.family == "thermal") thermal(r, b);
  else if (b.family == "tanks") tanks(r, b);
  else if (b.family == "position_loop") position_loop(r, b);
  else throw InputError("random plant: unknown family \"" + b.family + "\"");
}

// The estimation and validation records: time, excited inputs, outputs still zero.
struct Records {
  std::string time_col, excitation_kind;
  double per_time_scale = 0;  // samples per dominant time scale
  int n = 0;
  Recording est, val;
};

Records draw_records(Rng& r, Names& names, Build& b, const RandomPlantOptions& options) {
  Records rec;
  // Sampling: from about 6 to several hundred samples per dominant time scale.
  rec.per_time_scale = r.log_uniform(6, 300);
  b.Ts = b.period / rec.per_time_scale;
  rec.n = options.samples > 0 ? options.samples : r.integer(2500, 5000);
  rec.time_col = names({"t", "time", "tt"});
  rec.excitation_kind = r.pick(std::vector<std::string>{"steps", "steps", "prbs", "multisine", "noise", "few_steps", "sine"});
  std::vector<double> tcol(static_cast<std::size_t>(rec.n));
  for (int k = 0; k < rec.n; ++k) tcol[static_cast<std::size_t>(k)] = k * b.Ts;
  for (Recording* one : {&rec.est, &rec.val}) {
    one->add(rec.time_col, tcol);
    for (const auto& [sym, col] : b.inputs)
      one->add(col, excitation(r, rec.excitation_kind, rec.n, b.Ts, b.u_lo, b.u_hi, b.period));
    for (const auto& [sym, col] : b.outputs) one->add(col, std::vector<double>(static_cast<std::size_t>(rec.n), 0.0));
  }
  return rec;
}

// Two effects of one kind (two friction laws, two sensor laws, a square-root outflow beside a
// saturated level of another law) would describe one thing twice.
bool clash(const std::string& a, const std::string& c) {
  static const std::set<std::string> friction = {"coulomb_friction", "stribeck_friction", "quadratic_drag",
                                                 "asymmetric_friction", "viscous_friction"};
  static const std::set<std::string> sensor = {"output_saturation", "hysteresis", "absolute_value_sensor"};
  return a == c || (friction.count(a) && friction.count(c)) || (sensor.count(a) && sensor.count(c)) ||
         ((a == "sqrt_outflow") != (c == "sqrt_outflow") && (a == "state_saturation" || c == "state_saturation"));
}

// How many effects, which; nullopt when the forced effect cannot enter the drawn family (draw again).
std::optional<std::vector<std::string>> draw_effect_names(Rng& r, const Build& b, const RandomPlantOptions& options) {
  int count = options.effects;
  if (count < 0) {
    const double u = r.uniform(0, 1);
    count = u < 0.3 ? 0 : u < 0.7 ? 1 : 2;
  }
  std::vector<std::string> avail = effects_for(b), drawn;
  if (!options.effect.empty()) {
    if (std::find(avail.begin(), avail.end(), options.effect) == avail.end()) {
      if (!options.family.empty()) throw InputError("random plant: " + options.effect + " cannot enter a " + b.family + " plant");
      return std::nullopt;
    }
    drawn.push_back(options.effect);
  }
  while (static_cast<int>(drawn.size()) < count) {
    const std::string e = r.pick(avail);
    bool ok = true;
    for (const auto& d : drawn) ok = ok && !clash(d, e);
    if (ok) drawn.push_back(e);
    else if (avail.size() < 3) break;
  }
  return drawn;
}

// The plant without effects simulated on the estimation input (its scales size the effects).
// A plant that grows without bound is not a plant anyone identifies: the second half of every
// signal must stay within 100 x the first half's RMS.
bool simulates_bounded(const Build& b, const Records& rec, SimulationResult& clean) {
  const ModelFile model = model_of(b, b.eqs, b.sampled, b.outputs, b.states, {}, b.params, rec.time_col);
  try {
    Simulator s(model, rec.est, {10});
    clean = s.simulate(s.parameter_values());
  } catch (const std::exception&) {
    return false;
  }
  bool bounded = clean.values.allFinite();
  for (Eigen::Index v = 0; bounded && v < clean.values.cols(); ++v) {
    const Eigen::Index h = clean.values.rows() / 2;
    const double first = clean.values.col(v).head(h).norm(), second = clean.values.col(v).tail(h).norm();
    bounded = second <= 100 * first + 1e-300;
  }
  return bounded;
}

// Noise per output, drawn before the effects' strengths: every effect must move the outputs by
// several noise levels.
struct Noise {
  std::vector<double> fraction;  // of the output's standard deviation
  std::vector<std::string> kind;
  double max_fraction = 0;
};

Noise draw_noise(Rng& r, std::size_t outputs) {
  Noise noise;
  for (std::size_t j = 0; j < outputs; ++j) {
    noise.fraction.push_back(r.log_uniform(0.002, 0.03));
    noise.kind.push_back(r.pick(std::vector<std::string>{"white", "white", "coloured", "quantised"}));
  }
  noise.max_fraction = *std::max_element(noise.fraction.begin(), noise.fraction.end());
  return noise;
}

bool simulate_outputs(const ModelFile& m, const Recording& rec, Eigen::MatrixXd& y) {
  try {
    Simulator s(m, rec, {10});
    return s.simulate_outputs(s.parameter_values(), y);
  } catch (const std::exception&) {
    return false;
  }
}

using EffectValues = std::vector<std::pair<std::string, double>>;

// The truth with the effects at knobs k, one of them left out (skip) or none (-1).
class Truth {
 public:
  Truth(const Build& b, const std::vector<Effect>& effects, std::string time_col)
      : b_(b), effects_(effects), time_col_(std::move(time_col)) {}

  ModelFile with(const std::vector<double>& knobs, int skip, std::vector<EffectValues>* values) const {
    std::vector<Eq> eqs = b_.eqs;
    NamedTexts sampled = b_.sampled, outputs = b_.outputs;
    std::vector<ModelState> states = b_.states;
    std::vector<ModelParameter> ps = b_.params;
    for (std::size_t i = 0; i < effects_.size(); ++i) {
      EffectValues v;
      if (static_cast<int>(i) != skip) effects_[i].apply(knobs[i], eqs, sampled, outputs, states, ps, v);
      if (values) values->push_back(v);
    }
    // The truth has the damping the nominal leaves out; without the viscous effect it goes too.
    std::vector<std::string> removed;
    if (skip >= 0 && effects_[static_cast<std::size_t>(skip)].name == "viscous_friction") removed = b_.removed;
    return model_of(b_, eqs, sampled, outputs, states, removed, ps, time_col_);
  }

  // Strength of effect i: the RMS output deviation it causes (the others present) over the RMS
  // of the output, largest over the outputs; -1 when a simulation fails.
  double strength(const std::vector<double>& knobs, std::size_t i, const Recording& est) const {
    Eigen::MatrixXd y1, y0;
    if (!simulate_outputs(with(knobs, -1, nullptr), est, y1) || !simulate_outputs(with(knobs, static_cast<int>(i), nullptr), est, y0))
      return -1.0;
    double s = 0;
    for (Eigen::Index j = 0; j < y1.cols(); ++j) {
      const double den = std::sqrt((y0.col(j).array() - y0.col(j).mean()).square().mean());
      s = std::max(s, std::sqrt((y1.col(j) - y0.col(j)).array().square().mean()) / std::max(den, 1e-300));
    }
    return s;
  }

  const std::vector<Effect>& effects() const { return effects_; }

 private:
  const Build& b_;
  const std::vector<Effect>& effects_;
  std::string time_col_;
};

// Each effect's knob set by bisection on log(knob) for a drawn strength; false when an effect
// cannot be made strong enough to see or weak enough to hide.
bool set_strengths(Rng& r, const Truth& truth, const Recording& est, const Noise& noise, std::vector<double>& knobs,
                   std::vector<double>& strengths) {
  const double floor = noise.max_fraction;
  for (std::size_t i = 0; i < truth.effects().size(); ++i) {
    const double target = r.log_uniform(std::max(0.04, 4 * floor), 0.4);
    if (!truth.effects()[i].has_knob) {
      strengths[i] = truth.strength(knobs, i, est);
      // A mirror or a square-root law cannot be made weak.
      if (!(strengths[i] >= std::max(0.03, 3 * floor) && strengths[i] <= 1.5)) return false;
      continue;
    }
    double lo = std::log(1e-4), hi = std::log(20.0);
    for (int it = 0; it < 18; ++it) {
      knobs[i] = std::exp(0.5 * (lo + hi));
      const double s = truth.strength(knobs, i, est);
      if (s < 0 || s > target) hi = std::log(knobs[i]);
      else lo = std::log(knobs[i]);
    }
    knobs[i] = std::exp(lo);
    strengths[i] = truth.strength(knobs, i, est);
    if (!(strengths[i] >= 0.6 * target && strengths[i] >= 3 * floor && strengths[i] <= 0.5)) return false;
  }
  return true;
}

// Strong enough to matter: without it, the plant's own structure calibrated on the noise-free
// outputs (from the true values) still misses by at least 2 noise levels RMS on some output.
bool detectable(const Build& b, const Truth& truth_of, const ModelFile& truth, const Recording& est, const Noise& noise,
                const std::vector<double>& knobs, std::vector<double>& detectability) {
  const std::size_t count = truth_of.effects().size();
  detectability.assign(count, 0.0);
  Eigen::MatrixXd y;
  if (!simulate_outputs(truth, est, y)) return false;
  Recording clean_rec = est;
  for (std::size_t j = 0; j < b.outputs.size(); ++j) {
    const Eigen::VectorXd yj = y.col(static_cast<Eigen::Index>(j));
    clean_rec.add(b.outputs[j].second, std::vector<double>(yj.data(), yj.data() + yj.size()));
  }
  for (std::size_t i = 0; i < count; ++i) {
    try {
      Simulator s(truth_of.with(knobs, static_cast<int>(i), nullptr), clean_rec, {2});
      const CalibrationResult cr = calibrate(s, s.parameter_values(), s.free_parameters());
      for (Eigen::Index j = 0; cr.ok && j < y.cols(); ++j) {
        const double sd = std::sqrt((y.col(j).array() - y.col(j).mean()).square().mean());
        const double miss = std::sqrt((y.col(j) - cr.outputs.col(j)).array().square().mean());
        detectability[i] = std::max(detectability[i], miss / std::max(noise.fraction[static_cast<std::size_t>(j)] * sd, 1e-300));
      }
    } catch (const std::exception&) {
    }
    if (detectability[i] < 2.0) return false;
  }
  return true;
}

// The measured outputs: the truth simulated on each record plus the drawn noise; sigma: the true
// noise standard deviation per output on the estimation record.
bool add_measured_outputs(Rng& r, const ModelFile& truth, const Build& b, const Noise& noise, Records& rec,
                          std::vector<double>& sigma) {
  for (Recording* one : {&rec.est, &rec.val}) {
    Eigen::MatrixXd y;
    if (!simulate_outputs(truth, *one, y)) return false;
    for (std::size_t j = 0; j < b.outputs.size(); ++j) {
      const Eigen::VectorXd yj = y.col(static_cast<Eigen::Index>(j));
      const double sd = std::sqrt((yj.array() - yj.mean()).square().mean());
      const double s = std::max(noise.fraction[j] * sd, 1e-300);
      one->add(b.outputs[j].second, add_noise(r, yj, noise.kind[j], s));
      if (one == &rec.est) sigma.push_back(s);
    }
  }
  return true;
}

// The nominal: effects left out, free parameters off by up to a factor 1.8, states measured
// start from their first sample.
ModelFile nominal_of(Rng& r, const Build& b, const std::string& time_col) {
  std::vector<ModelParameter> params;
  for (auto q : b.params) {
    if (std::find(b.removed_params.begin(), b.removed_params.end(), q.name) != b.removed_params.end()) continue;
    if (!q.fixed) q.value *= r.log_uniform(1 / 1.8, 1.8);
    params.push_back(q);
  }
  std::vector<ModelState> states = b.states;
  for (auto& s : states)
    for (const auto& [sym, col] : b.outputs)
      if (sym == s.name && r.chance(0.5)) s.initial_value.reset(), s.initial_column = col;
  return model_of(b, b.eqs, b.sampled, b.outputs, states, b.removed, params, time_col);
}

std::string description(const Build& b, const Records& rec, const Noise& noise) {
  std::ostringstream d;
  d << b.family << ", N = " << rec.n << ", Ts = " << b.Ts << " s (" << std::round(rec.per_time_scale)
    << " samples per time scale), " << rec.excitation_kind << " input, noise";
  for (std::size_t j = 0; j < noise.kind.size(); ++j) {
    std::ostringstream o;
    o.precision(2);
    o << noise.kind[j] << " " << 100 * noise.fraction[j] << " %";
    d << " " << o.str();
  }
  return d.str();
}

}  // namespace

std::vector<std::string> random_plant_families() {
  return {"one_mass", "two_mass", "motor", "thermal", "tanks", "position_loop"};
}

std::vector<std::string> random_plant_effects() {
  return {"coulomb_friction", "stribeck_friction", "viscous_friction", "quadratic_drag", "asymmetric_friction",
          "constant_offset",  "cubic_stiffness",   "bouc_wen_hysteresis", "backlash", "dead_zone", "input_saturation",
          "time_delay",       "output_saturation", "hysteresis", "absolute_value_sensor", "sqrt_outflow", "state_saturation"};
}

SyntheticPlant random_plant(unsigned seed, const RandomPlantOptions& options) {
  for (int attempt = 0; attempt < 40; ++attempt) {
    Rng r(0x9E3779B97F4A7C15ull * (seed + 1) + static_cast<std::uint64_t>(attempt) * 7919u);
    Names names(r);
    Build b;
    b.names = &names;
    b.family = options.family.empty() ? r.pick(random_plant_families()) : options.family;
    draw_family(r, b);
    Records rec = draw_records(r, names, b, options);
    const std::optional<std::vector<std::string>> drawn = draw_effect_names(r, b, options);
    if (!drawn) continue;
    SimulationResult clean;
    if (!simulates_bounded(b, rec, clean)) continue;
    const Scales sc = scales_of(clean, b.Ts);
    std::vector<Effect> effects;
    for (const auto& e : *drawn) effects.push_back(make_effect(r, b, e, sc));
    if (std::find(drawn->begin(), drawn->end(), "viscous_friction") != drawn->end()) {
      const Velocity& vel = b.velocities.front();
      b.removed = {vel.damping + "*" + vel.v};
      b.removed_params = {vel.damping};
    }
    const Noise noise = draw_noise(r, b.outputs.size());
    const Truth truth_of(b, effects, rec.time_col);
    std::vector<double> knobs(effects.size(), 0.1), strengths(effects.size(), 0);
    if (!set_strengths(r, truth_of, rec.est, noise, knobs, strengths)) continue;
    std::vector<EffectValues> values;
    const ModelFile truth = truth_of.with(knobs, -1, &values);
    std::vector<double> detectability;
    if (!detectable(b, truth_of, truth, rec.est, noise, knobs, detectability)) continue;
    SyntheticPlant p;
    if (!add_measured_outputs(r, truth, b, noise, rec, p.noise_sigma)) continue;
    p.family = b.family;
    p.name = "random-" + std::to_string(seed);
    p.nominal = nominal_of(r, b, rec.time_col);
    p.nominal.name = "nominal " + b.family + " model (random plant " + std::to_string(seed) + ")";
    p.truth = truth;
    p.truth.name = "truth of random plant " + std::to_string(seed);
    p.estimation = std::move(rec.est);
    p.validation = std::move(rec.val);
    p.estimation.source = p.name + " (estimation)";
    p.validation.source = p.name + " (validation)";
    for (std::size_t i = 0; i < effects.size(); ++i)
      p.effects.push_back({effects[i].name, effects[i].where, values[i], strengths[i], detectability[i]});
    p.true_effect = p.effects.empty() ? "none" : p.effects.front().name;
    if (!p.effects.empty()) p.true_values = p.effects.front().values;
    p.description = description(b, rec, noise);
    return p;
  }
  throw InputError("random plant " + std::to_string(seed) + ": no admissible plant in 40 attempts");
}

}  // namespace sets
