#include "sets/diagnosis/physics_catalogue.hpp"

#include <boost/algorithm/string/classification.hpp>
#include <boost/algorithm/string/replace.hpp>
#include <boost/algorithm/string/trim.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <set>

namespace sets {

const std::vector<PhysicsEffect>& physics_catalogue() {
  static const std::vector<PhysicsEffect> c = {
      {"coulomb_friction", "additive", "force balance of a velocity state v that changes sign", "- Fc*sign(v)",
       "residual force is a square wave in the sign of v: a jump at every reversal, constant in between", {}},
      {"stribeck_friction", "additive", "force balance of a velocity state v that changes sign",
       "- sign(v)*(Fc + Fs*exp(-(v/vs)^2))",
       "like Coulomb friction plus an excess that decays with |v| (breakaway near zero velocity)",
       {{{"coulomb_friction"}, {{"Fs", 0.0}}}}},
      {"viscous_friction", "additive", "force balance of a velocity state v that changes sign", "- Fv*v",
       "residual force proportional to v (a straight line through 0 against v)", {}},
      {"quadratic_drag", "additive", "force balance of a velocity state v that changes sign", "- Cd*v*abs(v)",
       "residual force grows with v^2 and keeps the sign of v; small at low speed", {}},
      {"asymmetric_friction", "additive", "force balance of a velocity state v that changes sign",
       "- (Fc_pos*(v > 0) - Fc_neg*(v < 0) + dFv*v*(v > 0))",
       "friction differs with the direction of motion: the residual force against v has a different step and "
       "slope on the two sides of zero",
       // Fc_pos = Fc_neg, dFv = 0; or dFv = 0 alone: Coulomb friction and an offset (equal but at v = 0).
       {{{"coulomb_friction"}, {{"dFv", 0.0}}, {{"Fc_pos", "Fc"}, {"Fc_neg", "Fc"}}},
        {{"coulomb_friction", "constant_offset"}, {{"dFv", 0.0}}}}},
      {"constant_offset", "additive", "any state equation that is not a kinematic identity q' = v", "- offset",
       "residual of constant sign and size, independent of the operating point", {}},
      {"cubic_stiffness", "additive", "force balance (cubic in the pair's position q) or the equation of a state x "
       "that changes sign", "- k3*q^3", "residual grows with the cube of the displacement: concentrated at large |q|",
       {}},
      {"bouc_wen_hysteresis", "own state", "force balance of a mechanical pair (q, v): a restoring force z with its "
       "own state", "- z, z' = alpha*v - beta*(gamma*abs(v)*abs(z)^(n-1)*z + delta*v*abs(z)^n)",
       "residual force against q is a loop: it depends on the direction of motion and saturates between reversals", {}},
      {"backlash", "actuator", "an actuator signal a (input or sampled signal driving a state equation)",
       "a -> max(a - b, min(a + b, prev(a_bl, 1)))",
       "the effective drive lags by a play band 2b after every reversal of a; error at reversals of the drive", {}},
      {"dead_zone", "actuator", "an actuator signal a", "a -> a - min(max(a, -d), d)",
       "small drives have no effect: residual concentrated where |a| is small", {}},
      {"input_saturation", "actuator", "an actuator signal a", "a -> min(max(a, -umax), umax)",
       "residual only where |a| is large (the model drives harder than the plant can)", {}},
      {"output_saturation", "sensor", "an output y (the sensor)", "y -> min(max(y, y_lo), y_hi)",
       "measured output flat at a level while the model goes beyond it: residual near a limit", {}},
      {"sqrt_outflow", "replaces a*x", "a linear outflow a*x of a level-like state x (x >= 0) replaced by its "
       "square-root law", "a*x -> a_sqrt*sqrt(max(x, 0))",
       "residual depends on the level: a linear outflow is too weak at low level, too strong at high", {}},
      {"state_saturation", "state limit", "the equation of a state that is not a kinematic identity: the state "
       "cannot pass a limit (overflow, end stop)", "x' = f -> f - max(f, 0)*(x >= x_max)  (or min(f, 0)*(x <= x_min))",
       "the measured state stays flat at a level while the model goes beyond it, and leaves it as soon as the "
       "drive turns (unlike a sensor limit, the dynamics after the flat part start from the limit)", {}},
      {"time_delay", "actuator", "an actuator signal a", "a -> prev(a, n)",
       "residual looks like the derivative of the response: largest just after changes of the drive", {}},
      {"hysteresis", "sensor", "an output y (sensor with a play band)", "y -> max(y - w, min(y + w, prev(y_h, 1)))",
       "measured output lags by w with the sign of its rate; offset flips at reversals of the output", {}},
      {"absolute_value_sensor", "sensor", "an output y", "y -> abs(y)",
       "measured output never negative; residual where the model output is negative (mirror image)", {}},
  };
  return c;
}

const PhysicsEffect* find_effect(const std::string& name) {
  for (const auto& e : physics_catalogue())
    if (e.name == name) return &e;
  return nullptr;
}

const SpecialCase* find_special_case(std::vector<std::string> effects, const std::string& general) {
  const PhysicsEffect* g = find_effect(general);
  if (!g) return nullptr;
  std::sort(effects.begin(), effects.end());
  for (const auto& sc : g->special_cases) {
    std::vector<std::string> e = sc.effects;
    std::sort(e.begin(), e.end());
    if (e == effects) return &sc;
  }
  return nullptr;
}

std::string replace_symbol(const std::string& text, const std::string& symbol, const std::string& by) {
  const std::regex re("(^|[^A-Za-z0-9_])" + symbol + "(?![A-Za-z0-9_])");
  return std::regex_replace(text, re, "$1" + by);
}

std::string fresh_name(const ModelFile& model, const std::string& wanted) {
  if (!model.has_symbol(wanted)) return wanted;
  for (int i = 2;; ++i) {
    const std::string n = wanted + "_" + std::to_string(i);
    if (!model.has_symbol(n)) return n;
  }
}

namespace {

constexpr double kHuge = 1e300;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string trim(const std::string& s) { return boost::algorithm::trim_copy_if(s, boost::is_any_of(" \t\n")); }

bool uses(const std::string& text, const std::string& symbol) { return replace_symbol(text, symbol, "\x01") != text; }

// "(inner)/M" -> "(inner - term)/M" so that a force enters in force units; otherwise "text - (term)".
std::string subtract_force(const std::string& text, const std::string& term) {
  const std::string s = trim(text);
  if (!s.empty() && s[0] == '(') {
    int depth = 0;
    std::size_t close = std::string::npos;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s[i] == '(') ++depth;
      if (s[i] == ')' && --depth == 0) {
        close = i;
        break;
      }
    }
    static const std::regex tail(R"(^\s*/\s*[A-Za-z_][A-Za-z0-9_]*\s*$)");
    if (close != std::string::npos && std::regex_match(s.substr(close + 1), tail)) {
      std::string r(1, '(');
      r.append(s, 1, close - 1).append(" - ").append(term).append(s, close);
      return r;
    }
  }
  return s + " - (" + term + ")";
}

// The inertia M of a force balance "(...)/M" (its value), or 1.
double inertia_of(const ModelFile& model, const std::string& text) {
  if (subtract_force(text, "X").find(" - (X)") != std::string::npos) return 1.0;
  static const std::regex tail(R"(/\s*([A-Za-z_][A-Za-z0-9_]*)\s*$)");
  std::smatch m;
  const std::string s = trim(text);
  if (std::regex_search(s, m, tail))
    if (const auto* p = model.parameter(m[1].str())) return std::abs(p->value) > 0 ? std::abs(p->value) : 1.0;
  return 1.0;
}

double rms(const Eigen::VectorXd& x) { return x.size() ? std::sqrt(x.squaredNorm() / static_cast<double>(x.size())) : 0.0; }
double positive(double x, double fallback) { return std::isfinite(x) && x > 0 ? x : fallback; }

Eigen::VectorXd rate(const Eigen::VectorXd& x, double Ts) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(x.size());
  for (Eigen::Index i = 1; i < x.size(); ++i) d[i] = (x[i] - x[i - 1]) / Ts;
  return d;
}

bool changes_sign(const Eigen::VectorXd& x) {
  const double m = x.cwiseAbs().maxCoeff();
  return m > 0 && x.minCoeff() < -0.05 * m && x.maxCoeff() > 0.05 * m;
}

// The product p*x or x*p as a regex (whole words, spaces allowed).
std::regex product_regex(const std::string& p, const std::string& x) {
  return std::regex("(^|[^A-Za-z0-9_])(" + p + "\\s*\\*\\s*" + x + "|" + x + "\\s*\\*\\s*" + p + ")(?![A-Za-z0-9_])");
}

// A candidate under construction: new parameters with their role, scale, bounds and neutral value.
struct Builder {
  Candidate c;
  Builder(const ModelFile& model, const std::string& effect, const std::string& equation) {
    c.effect = effect;
    c.equation = equation;
    c.model = model;
  }
  std::string add(const std::string& role, double start, double scale, bool linear, double neutral, double lo = -kHuge,
                  double hi = kHuge, bool fixed = false) {
    ModelParameter p;
    p.name = fresh_name(c.model, role);
    p.value = start;
    p.min = lo;
    p.max = hi;
    p.fixed = fixed;
    c.model.parameters.push_back(p);
    if (fixed) {
      c.fixed_roles.push_back(role);
      return p.name;
    }
    c.parameters.push_back(p.name);
    c.roles.push_back(role);
    c.scales.push_back(scale);
    c.linear.push_back(linear);
    c.neutral.push_back(neutral);
    return p.name;
  }
};

struct Context {
  const ModelFile& model;
  const SimulationResult& sim;
  const Recording& measured;
  const ModelStructure& st;
  double Ts;
  std::vector<std::string> exclude;
  std::vector<Candidate>& out;
  bool excluded(const std::string& e) const { return std::find(exclude.begin(), exclude.end(), e) != exclude.end(); }
  // The signal of a symbol: its measured column when it is compared with one, else simulated.
  Eigen::VectorXd data_of(const std::string& sym) const {
    for (const auto& [s, col] : model.outputs)
      if (s == sym && measured.has(col)) {
        const auto& v = measured.column(col);
        return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
      }
    return sim.series(sym);
  }
};

// Additive terms in the force balance (or rate equation) of a velocity-like state v.
void friction_candidates(const Context& k, const std::string& v) {
  const std::string text = *k.model.derivative(v);
  const Eigen::VectorXd vv = k.sim.series(v);
  if (!changes_sign(vv)) return;  // one direction only: a friction law is an offset there
  const double vr = positive(rms(vv), 1.0), F = positive(inertia_of(k.model, text) * rms(rate(vv, k.Ts)), inertia_of(k.model, text) * vr);
  auto emit = [&](Builder& b, const std::string& term) {
    b.c.term = term;
    *b.c.model.derivative(v) = subtract_force(text, term);
    k.out.push_back(std::move(b.c));
  };
  // Friction and drag dissipate: their coefficients are >= 0 (a negative one is not that effect).
  if (!k.excluded("coulomb_friction")) {
    Builder b(k.model, "coulomb_friction", v);
    emit(b, b.add("Fc", 0, F, true, 0, 0) + "*sign(" + v + ")");
  }
  if (!k.excluded("stribeck_friction")) {
    Builder b(k.model, "stribeck_friction", v);
    const std::string fc = b.add("Fc", 0, F, true, 0, 0), fs = b.add("Fs", 0, F, true, 0, 0);
    const std::string vs = b.add("vs", 0.3 * vr, vr, false, kNaN, 1e-6 * vr);
    for (double f : {0.05, 0.1, 0.2, 0.4, 0.8}) b.c.grid.push_back({f * vr});
    emit(b, "sign(" + v + ")*(" + fc + " + " + fs + "*exp(-(" + v + "/" + vs + ")^2))");
  }
  if (!k.excluded("viscous_friction")) {
    Builder b(k.model, "viscous_friction", v);
    emit(b, b.add("Fv", 0, F / vr, true, 0, 0) + "*" + v);
  }
  if (!k.excluded("quadratic_drag")) {
    Builder b(k.model, "quadratic_drag", v);
    emit(b, b.add("Cd", 0, F / (vr * vr), true, 0, 0) + "*" + v + "*abs(" + v + ")");
  }
  if (!k.excluded("asymmetric_friction")) {
    Builder b(k.model, "asymmetric_friction", v);
    const std::string p = b.add("Fc_pos", 0, F, true, 0, 0), n = b.add("Fc_neg", 0, F, true, 0, 0);
    const std::string d = b.add("dFv", 0, F / vr, true, 0);
    emit(b, "(" + p + "*(" + v + " > 0) - " + n + "*(" + v + " < 0) + " + d + "*" + v + "*(" + v + " > 0))");
  }
}

void additive_candidates(const Context& k, const std::string& x, const std::string& cubic_in) {
  const std::string text = *k.model.derivative(x);
  const double M = inertia_of(k.model, text);
  const Eigen::VectorXd xx = k.sim.series(x);
  const double F = positive(M * rms(rate(xx, k.Ts)), M * positive(rms(xx), 1.0));
  auto emit = [&](Builder& b, const std::string& term) {
    b.c.term = term;
    *b.c.model.derivative(x) = subtract_force(text, term);
    k.out.push_back(std::move(b.c));
  };
  if (!k.excluded("constant_offset")) {
    Builder b(k.model, "constant_offset", x);
    emit(b, b.add("offset", 0, F, true, 0));
  }
  if (!cubic_in.empty() && !k.excluded("cubic_stiffness")) {
    const double qr = positive(rms(k.sim.series(cubic_in)), 1.0);
    Builder b(k.model, "cubic_stiffness", x);
    emit(b, b.add("k3", 0, F / (qr * qr * qr), true, 0) + "*" + cubic_in + "^3");
  }
}

// z' = alpha v - beta (gamma |v| |z|^(n-1) z + delta v |z|^n), force -z. beta = 1 / range(q) and
// n = 1 are fixed normalisations: then z = alpha * zeta with zeta independent of alpha, so alpha
// is linear; gamma and delta set the yield displacement 1 / (beta (gamma + delta)) and the shape.
void bouc_wen_candidate(const Context& k, const std::string& q, const std::string& v) {
  if (k.excluded("bouc_wen_hysteresis")) return;
  const std::string text = *k.model.derivative(v);
  const Eigen::VectorXd qq = k.sim.series(q), vv = k.sim.series(v);
  const double range = positive(qq.maxCoeff() - qq.minCoeff(), 1.0);
  const double F = positive(inertia_of(k.model, text) * rms(rate(vv, k.Ts)), 1.0);
  Builder b(k.model, "bouc_wen_hysteresis", v);
  const std::string z = fresh_name(b.c.model, "z_bw");
  ModelState zs;
  zs.name = z;
  zs.initial_value = 0.0;
  b.c.model.states.push_back(zs);
  const std::string alpha = b.add("alpha", 0, F / (0.1 * range), true, 0, 0);
  const std::string gamma = b.add("gamma", 5, 5, false, kNaN), delta = b.add("delta", 5, 5, false, kNaN);
  const std::string beta = b.add("beta", 1 / range, 1 / range, false, kNaN, -kHuge, kHuge, true);
  const std::string n = b.add("n", 1, 1, false, kNaN, -kHuge, kHuge, true);
  for (double yield : {0.03, 0.1, 0.3})
    for (double share : {0.25, 0.5, 0.75}) b.c.grid.push_back({share / yield, (1 - share) / yield});
  b.c.model.derivatives.emplace_back(z, alpha + "*" + v + " - " + beta + "*(" + gamma + "*abs(" + v + ")*abs(" + z + ")^(" +
                                            n + " - 1)*" + z + " + " + delta + "*" + v + "*abs(" + z + ")^" + n + ")");
  b.c.term = z + " with " + b.c.model.derivatives.back().first + "' = " + b.c.model.derivatives.back().second;
  *b.c.model.derivative(v) = subtract_force(text, z);
  k.out.push_back(std::move(b.c));
}

// sqrt_outflow: the linear outflow p*x of a level replaced, wherever the product appears, by
// a_sqrt*sqrt(max(x, 0)), starting from the same flow at the mean level.
void sqrt_candidates(const Context& k, const std::string& x) {
  if (k.excluded("sqrt_outflow")) return;
  const Eigen::VectorXd xx = k.sim.series(x);
  if (xx.minCoeff() < -0.05 * xx.cwiseAbs().maxCoeff()) return;  // not a level
  const double xm = positive(xx.mean(), positive(rms(xx), 1.0));
  bool replaced = false;
  for (const auto& lt : k.st.linear_terms) {
    if (lt.state != x || std::find(lt.equations.begin(), lt.equations.end(), x) == lt.equations.end()) continue;
    const double a = k.model.parameter(lt.parameter)->value;
    Builder b(k.model, "sqrt_outflow", x);
    const std::string as = b.add("a_sqrt", a * std::sqrt(xm), positive(std::abs(a) * std::sqrt(xm), 1.0), false, kNaN, 0);
    const std::string by = as + "*sqrt(max(" + x + ", 0))";
    const std::regex re = product_regex(lt.parameter, x);
    for (auto& d : b.c.model.derivatives) d.second = std::regex_replace(d.second, re, "$1" + by);
    for (auto& s : b.c.model.signals) s.second = std::regex_replace(s.second, re, "$1" + by);
    bool still_used = false;
    for (const auto& d : b.c.model.derivatives) still_used = still_used || uses(d.second, lt.parameter);
    for (const auto& s : b.c.model.signals) still_used = still_used || uses(s.second, lt.parameter);
    for (const auto& s : b.c.model.sampled) still_used = still_used || uses(s.second, lt.parameter);
    if (!still_used) b.c.model.parameter(lt.parameter)->fixed = true;  // replaced: no longer in the model
    b.c.term = lt.parameter + "*" + x + " -> " + by;
    b.c.grid.push_back({a * std::sqrt(xm)});
    k.out.push_back(std::move(b.c));
    replaced = true;
  }
  (void)replaced;  // no product a*x to replace: no square-root law here (a balance such as
                   // (T - Ta)/R is not an outflow of a level)
}

// The state cannot pass a limit: the derivative f is cut where it would push beyond it.
void limit_candidates(const Context& k, const std::string& x) {
  if (k.excluded("state_saturation")) return;
  const Eigen::VectorXd xx = k.data_of(x);
  const double hi = xx.maxCoeff(), lo = xx.minCoeff(), range = positive(hi - lo, 1.0);
  const std::string f = "(" + *k.model.derivative(x) + ")";
  for (int upper = 1; upper >= 0; --upper) {
    Builder b(k.model, "state_saturation", x);
    const std::string p = b.add(upper ? "x_max" : "x_min", upper ? hi : lo, range, false, upper ? kHuge : -kHuge);
    for (double frac : {0.0, 0.02, 0.05, 0.1, 0.2}) b.c.grid.push_back({upper ? hi - frac * range : lo + frac * range});
    b.c.term = upper ? f + " - max(" + f + ", 0)*(" + x + " >= " + p + ")" : f + " - min(" + f + ", 0)*(" + x + " <= " + p + ")";
    *b.c.model.derivative(x) = b.c.term;
    b.c.term = x + "' cut at " + p;
    k.out.push_back(std::move(b.c));
  }
}

void actuator_candidates(const Context& k, const std::string& a) {
  const Eigen::VectorXd aa = k.sim.series(a);
  const double amax = positive(aa.cwiseAbs().maxCoeff(), 1.0), arange = positive(aa.maxCoeff() - aa.minCoeff(), amax);
  auto rewire = [&](Candidate& c, const std::string& by) {
    for (auto& d : c.model.derivatives) d.second = replace_symbol(d.second, a, by);
    for (auto& d : c.model.signals) d.second = replace_symbol(d.second, a, by);
  };
  auto emit = [&](Builder& b, const std::string& suffix, const std::string& term) {
    const std::string s = fresh_name(b.c.model, a + suffix);
    b.c.term = term;
    b.c.model.sampled.emplace_back(s, replace_symbol(term, "@self", s));
    b.c.term = replace_symbol(term, "@self", s);
    rewire(b.c, s);
    k.out.push_back(std::move(b.c));
  };
  if (!k.excluded("input_saturation")) {
    Builder b(k.model, "input_saturation", a);
    const std::string p = b.add("umax", 0.9 * amax, amax, false, kHuge, 0);
    // Its cut (1 - umax / max|a|) reaches 2 % of the drive's peak, as the dead zone's grid reaches d
    // of 2 % and below: a drive cut only at its peaks can matter, e.g. into an integrating tank, and from a
    // cut of 10 % Levenberg-Marquardt finds a cut far deeper than the truth's (5 003 468, 564).
    for (double f : {0.3, 0.45, 0.6, 0.75, 0.9, 0.95, 0.98}) b.c.grid.push_back({f * amax});
    emit(b, "_sat", "min(max(" + a + ", -" + p + "), " + p + ")");
  }
  if (!k.excluded("dead_zone")) {
    Builder b(k.model, "dead_zone", a);
    const std::string p = b.add("d", 0.02 * amax, 0.1 * amax, false, 0, 0);
    // The ladder reaches 0.5 % of the drive's peak: a loop's drive peaks at each step far above
    // the levels it settles at, and a zone of 0.7 % or 1.2 % of the peak (random plants 5 003 917,
    // 902) was screened from 2 % only, where it explained nothing and was never refined. Not at
    // quantiles of |a|: the drive simulated without the zone settles at 0, where the true one stalls
    // inside the zone.
    for (double f : {0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.35}) b.c.grid.push_back({f * amax});
    emit(b, "_eff", a + " - min(max(" + a + ", -" + p + "), " + p + ")");
  }
  if (!k.excluded("backlash")) {
    Builder b(k.model, "backlash", a);
    const std::string p = b.add("b", 0.02 * arange, 0.1 * arange, false, 0, 0);
    for (double f : {0.01, 0.02, 0.05, 0.1, 0.2}) b.c.grid.push_back({f * arange});
    emit(b, "_bl", "max(" + a + " - " + p + ", min(" + a + " + " + p + ", prev(@self, 1)))");
  }
  if (!k.excluded("time_delay"))
    for (int n : {1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64}) {
      if (n >= k.sim.values.rows() / 10) break;
      k.out.push_back(delay_candidate(k.model, a, n));
    }
}

void sensor_candidates(const Context& k, std::size_t j) {
  const std::string y = k.model.outputs[j].first, col = k.model.outputs[j].second;  // captured below (Clang 14)
  const auto& mv = k.measured.column(col);
  const double lo = *std::min_element(mv.begin(), mv.end()), hi = *std::max_element(mv.begin(), mv.end());
  const double range = positive(hi - lo, 1.0);
  const Eigen::VectorXd yy = k.sim.series(y);
  auto sensor = [&](Builder& b, const std::string& suffix, const std::string& term) {
    const std::string s = fresh_name(b.c.model, y + suffix);
    b.c.term = replace_symbol(term, "@self", s);
    b.c.model.sampled.emplace_back(s, b.c.term);
    b.c.model.outputs[j].first = s;
    k.out.push_back(std::move(b.c));
  };
  if (!k.excluded("output_saturation")) {
    // Clipped at both ends, or at one: a limit the estimation record does not reach is not seen
    // there and would stay at the record's edge, clipping a validation record that goes further.
    Builder b(k.model, "output_saturation", y);
    const std::string a = b.add("y_lo", lo, range, false, -kHuge), c = b.add("y_hi", hi, range, false, kHuge);
    b.c.grid.push_back({lo, hi});
    sensor(b, "_sensor", "min(max(" + y + ", " + a + "), " + c + ")");
    Builder up(k.model, "output_saturation", y);
    const std::string u = up.add("y_hi", hi, range, false, kHuge);
    up.c.grid.push_back({hi});
    sensor(up, "_sensor", "min(" + y + ", " + u + ")");
    Builder down(k.model, "output_saturation", y);
    const std::string d = down.add("y_lo", lo, range, false, -kHuge);
    down.c.grid.push_back({lo});
    sensor(down, "_sensor", "max(" + y + ", " + d + ")");
  }
  if (!k.excluded("hysteresis")) {
    Builder b(k.model, "hysteresis", y);
    const std::string w = b.add("w", 0.01 * range, 0.05 * range, false, 0, 0);
    for (double f : {0.002, 0.005, 0.01, 0.02, 0.05}) b.c.grid.push_back({f * range});
    sensor(b, "_h", "max(" + y + " - " + w + ", min(" + y + " + " + w + ", prev(@self, 1)))");
  }
  // A mirror only makes sense if the data stay non-negative while the model goes negative.
  if (!k.excluded("absolute_value_sensor") && lo > -0.02 * range && yy.minCoeff() < 0) {
    Builder b(k.model, "absolute_value_sensor", y);
    b.c.restart = true;
    sensor(b, "_abs", "abs(" + y + ")");
  }
}

// How a delay of n samples writes the signal s into a model (delayed_signal reads it back).
std::string delayed(const std::string& s, int n) { return "prev(" + s + ", " + std::to_string(n) + ")"; }

// The delay `d`'s term as it stands in `model`: prev(a, n), or prev(s, n) where a later effect at
// the same actuator put its own signal s in a's place (a sampled signal `d`'s model did not have).
std::string delayed_term(const ModelFile& model, const Candidate& d) {
  auto in_model = [&](const std::string& t) {
    for (const auto* texts : {&model.derivatives, &model.signals})
      for (const auto& x : *texts)
        if (x.second.find(t) != std::string::npos) return true;
    return false;
  };
  if (in_model(d.term)) return d.term;
  for (const auto& s : model.sampled) {
    const bool old = std::any_of(d.model.sampled.begin(), d.model.sampled.end(), [&](const auto& o) { return o.first == s.first; });
    const std::string t = delayed(s.first, d.delay_samples);
    if (!old && in_model(t)) return t;
  }
  return d.term;
}

}  // namespace

Candidate delay_candidate(const ModelFile& model, const std::string& a, int n) {
  Candidate c;
  c.effect = "time_delay";
  c.equation = a;
  c.term = delayed(a, n);
  c.model = model;
  c.delay_samples = n;
  for (auto& d : c.model.derivatives) d.second = replace_symbol(d.second, a, c.term);
  for (auto& d : c.model.signals) d.second = replace_symbol(d.second, a, c.term);
  return c;
}

std::string delayed_signal(const std::string& term) { return term.substr(5, term.rfind(", ") - 5); }

Candidate with_delay_samples(const Candidate& c, int n) {
  Candidate moved = c;
  Candidate* d = c.parts.empty() ? &moved : nullptr;
  for (auto& part : moved.parts)
    if (part.effect == "time_delay") d = &part;
  if (!d || d->effect != "time_delay" || d->delay_samples == n) return c;
  // The delay's term as the model holds it (prev(s, n0), s the actuator or a later effect's signal
  // in its place: delayed_term), and as the pair's own term spells it (prev(a, n0)).
  const std::string held = d->term, plain = delayed(d->equation, d->delay_samples);
  auto rewrite = [n](std::string& text, const std::string& from) {
    boost::algorithm::replace_all(text, from, delayed(delayed_signal(from), n));
  };
  for (auto* texts : {&moved.model.derivatives, &moved.model.signals, &moved.model.sampled})
    for (auto& t : *texts) rewrite(t.second, held);
  rewrite(moved.term, held);
  rewrite(moved.term, plain);
  if (d != &moved) rewrite(d->term, held);
  d->delay_samples = n;
  moved.delay_samples = n;
  for (const auto& part : moved.parts) moved.delay_samples = std::max(moved.delay_samples, part.delay_samples);
  return moved;
}

Candidate combine_candidates(const Candidate& first, const Candidate& second) {
  Candidate c = second;
  c.effect = first.effect + "+" + second.effect;
  c.equation = first.equation + "," + second.equation;
  c.term = first.term + "; " + second.term;
  auto prepend = [](auto& to, const auto& from) { to.insert(to.begin(), from.begin(), from.end()); };
  prepend(c.parameters, first.parameters);
  prepend(c.roles, first.roles);
  prepend(c.scales, first.scales);
  prepend(c.neutral, first.neutral);
  prepend(c.linear, first.linear);
  prepend(c.fixed_roles, first.fixed_roles);
  c.grid.clear();
  c.delay_samples = std::max(first.delay_samples, second.delay_samples);
  c.restart = first.restart || second.restart;
  Candidate a = first, b = second;
  // A second effect at the delayed actuator rewires the delayed signal (prev(u, n) becomes
  // prev(u_sat, n)): the delay's term follows, or switching the delay off would find nothing and
  // read its own share of the pair as 0.
  if (first.effect == "time_delay") a.term = delayed_term(c.model, first);
  a.model = ModelFile();
  b.model = ModelFile();
  c.parts = {a, b};
  return c;
}

ModelStructure analyse_structure(const ModelFile& model) {
  ModelStructure s;
  std::set<std::string> positions, pair_velocities;
  for (const auto& st : model.states) {
    const std::string d = trim(*model.derivative(st.name));
    for (const auto& other : model.states)
      if (other.name == d && other.name != st.name) {
        s.mechanical.emplace_back(st.name, other.name);
        positions.insert(st.name);
        pair_velocities.insert(other.name);
      }
  }
  for (const auto& st : model.states)
    if (!positions.count(st.name) && !pair_velocities.count(st.name)) s.other_states.push_back(st.name);
  // Linear terms p*x of a free parameter and a state.
  for (const auto& p : model.parameters) {
    if (p.fixed) continue;
    for (const auto& st : model.states) {
      LinearTerm lt{p.name, st.name, {}};
      const std::regex re = product_regex(p.name, st.name);
      for (const auto& [x, text] : model.derivatives)
        if (std::regex_search(text, re)) lt.equations.push_back(x);
      if (!lt.equations.empty()) s.linear_terms.push_back(lt);
    }
  }
  for (const auto& st : model.states) {
    bool damped = pair_velocities.count(st.name) > 0;
    for (const auto& lt : s.linear_terms)
      damped = damped || (!positions.count(st.name) && lt.state == st.name &&
                          std::find(lt.equations.begin(), lt.equations.end(), st.name) != lt.equations.end());
    if (damped) s.velocities.push_back(st.name);
  }
  std::vector<std::string> plant_texts;
  for (const auto& d : model.derivatives) plant_texts.push_back(d.second);
  for (const auto& d : model.signals) plant_texts.push_back(d.second);
  auto consider = [&](const std::string& sym) {
    for (const auto& t : plant_texts)
      if (uses(t, sym)) {
        s.actuators.push_back(sym);
        return;
      }
  };
  for (const auto& i : model.inputs) consider(i.first);
  for (const auto& i : model.sampled) consider(i.first);
  return s;
}

std::vector<Candidate> generate_candidates(const ModelFile& model, const SimulationResult& nominal,
                                           const Recording& measured, const std::vector<std::string>& exclude) {
  std::vector<Candidate> out;
  const ModelStructure st = analyse_structure(model);
  double Ts = 1;
  if (!model.time_column.empty() && measured.has(model.time_column)) {
    const auto& t = measured.column(model.time_column);
    Ts = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  } else if (model.sample_time) {
    Ts = *model.sample_time;
  }
  const Context k{model, nominal, measured, st, Ts, exclude, out};
  std::set<std::string> positions;
  for (const auto& [q, v] : st.mechanical) positions.insert(q);
  std::vector<std::string> velocities = st.velocities;
  for (const auto& x : st.other_states)  // a momentum balance (...)/M of a state that changes sign
    if (std::find(velocities.begin(), velocities.end(), x) == velocities.end() &&
        subtract_force(*model.derivative(x), "X").find(" - (X)") == std::string::npos && changes_sign(nominal.series(x)))
      velocities.push_back(x);
  for (const auto& v : velocities) friction_candidates(k, v);
  for (const auto& [q, v] : st.mechanical) {
    additive_candidates(k, v, q);
    bouc_wen_candidate(k, q, v);
  }
  for (const auto& x : st.other_states) {
    const bool velocity = std::find(velocities.begin(), velocities.end(), x) != velocities.end();
    additive_candidates(k, x, !velocity && changes_sign(nominal.series(x)) ? x : "");
    sqrt_candidates(k, x);
    limit_candidates(k, x);
  }
  for (const auto& a : st.actuators) actuator_candidates(k, a);
  for (std::size_t j = 0; j < model.outputs.size(); ++j) sensor_candidates(k, j);
  return out;
}

}  // namespace sets
