#include "sets/diagnosis/physics_catalogue.hpp"

#include <boost/algorithm/string/classification.hpp>
#include <boost/algorithm/string/trim.hpp>
#include <algorithm>
#include <cmath>
#include <regex>
#include <set>

namespace sets {

const std::vector<PhysicsEffect>& physics_catalogue() {
  static const std::vector<PhysicsEffect> c = {
      {"coulomb_friction", "force balance of a velocity state v (q' = v)", "- Fc*sign(v)",
       "residual force is a square wave in the sign of v: a jump at every reversal, constant in between"},
      {"stribeck_friction", "force balance of a velocity state v", "- sign(v)*(Fc + Fs*exp(-(v/vs)^2))",
       "like Coulomb friction plus an excess that decays with |v| (breakaway near zero velocity)"},
      {"viscous_friction", "force balance of a velocity state v", "- Fv*v",
       "residual force proportional to v (a straight line through 0 against v)"},
      {"quadratic_drag", "force balance of a velocity state v", "- Cd*v*abs(v)",
       "residual force grows with v^2 and keeps the sign of v; small at low speed"},
      {"constant_offset", "any state equation (a force bias in a force balance)", "- offset",
       "residual of constant sign and size, independent of the operating point"},
      {"cubic_stiffness", "force balance (position q) or any state equation (state x)", "- k3*q^3",
       "residual grows with the cube of the displacement: concentrated at large |q|"},
      {"backlash", "an actuator signal a (input or sampled signal driving a state equation)",
       "a -> max(a - b, min(a + b, prev(a_bl, 1)))",
       "the effective drive lags by a play band 2b after every reversal of a; error at reversals of the drive"},
      {"dead_zone", "an actuator signal a", "a -> a - min(max(a, -d), d)",
       "small drives have no effect: residual concentrated where |a| is small"},
      {"input_saturation", "an actuator signal a", "a -> min(max(a, -umax), umax)",
       "residual only where |a| is large (the model drives harder than the plant can)"},
      {"output_saturation", "an output y (the sensor)", "y -> min(max(y, ylo), yhi)",
       "measured output flat at a level while the model goes beyond it: residual near a limit"},
      {"sqrt_outflow", "the equation of a level-like state x (a tank)", "- a*sqrt(max(x, 0))",
       "residual depends on the level: a linear outflow is too weak at low level, too strong at high"},
      {"time_delay", "an actuator signal a", "a -> prev(a, n)",
       "residual looks like the derivative of the response: largest just after changes of the drive"},
      {"hysteresis", "an output y (sensor with a play band)", "y -> max(y - w, min(y + w, prev(y_h, 1)))",
       "measured output lags by w with the sign of its rate; offset flips at reversals of the output"},
      {"absolute_value_sensor", "an output y", "y -> abs(y)",
       "measured output never negative; residual where the model output is negative (mirror image)"},
  };
  return c;
}

const PhysicsEffect* find_effect(const std::string& name) {
  for (const auto& e : physics_catalogue())
    if (e.name == name) return &e;
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
    if (close != std::string::npos && std::regex_match(s.substr(close + 1), tail))
    {
      std::string r(1, '(');
      r.append(s, 1, close - 1).append(" - ").append(term).append(s, close);
      return r;
    }
  }
  return s + " - (" + term + ")";
}

bool is_force_form(const std::string& text) { return subtract_force(text, "X").find(" - (X)") == std::string::npos; }

double rms(const Eigen::VectorXd& x) { return x.size() ? std::sqrt(x.squaredNorm() / static_cast<double>(x.size())) : 0.0; }
double positive(double x, double fallback) { return std::isfinite(x) && x > 0 ? x : fallback; }

Eigen::VectorXd rate(const Eigen::VectorXd& x, double Ts) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(x.size());
  for (Eigen::Index i = 1; i < x.size(); ++i) d[i] = (x[i] - x[i - 1]) / Ts;
  return d;
}

}  // namespace

Candidate delay_candidate(const ModelFile& model, const std::string& a, int n) {
  Candidate c;
  c.effect = "time_delay";
  c.equation = a;
  c.term = "prev(" + a + ", " + std::to_string(n) + ")";
  c.model = model;
  c.delay_samples = n;
  for (auto& d : c.model.derivatives) d.second = replace_symbol(d.second, a, c.term);
  for (auto& d : c.model.signals) d.second = replace_symbol(d.second, a, c.term);
  return c;
}

ModelStructure analyse_structure(const ModelFile& model) {
  ModelStructure s;
  std::set<std::string> positions;
  for (const auto& st : model.states) {
    const std::string d = trim(*model.derivative(st.name));
    for (const auto& other : model.states)
      if (other.name == d && other.name != st.name) {
        s.mechanical.emplace_back(st.name, other.name);
        positions.insert(st.name);
      }
  }
  for (const auto& st : model.states) {
    bool velocity = false;
    for (const auto& m : s.mechanical) velocity = velocity || m.second == st.name;
    if (!positions.count(st.name) && !velocity) s.other_states.push_back(st.name);
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
  const auto excluded = [&](const std::string& e) { return std::find(exclude.begin(), exclude.end(), e) != exclude.end(); };
  const ModelStructure st = analyse_structure(model);
  const auto N = nominal.values.rows();
  double Ts = 1;
  if (!model.time_column.empty() && measured.has(model.time_column)) {
    const auto& t = measured.column(model.time_column);
    Ts = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  } else if (model.sample_time) {
    Ts = *model.sample_time;
  }
  auto add_param = [](Candidate& c, const std::string& name, double value, double scale, double lo = -1e300,
                      double hi = 1e300, double neutral = 0.0) {
    c.neutral.push_back(neutral);
    ModelParameter p;
    p.name = name;
    p.value = value;
    p.min = lo;
    p.max = hi;
    c.model.parameters.push_back(p);
    c.parameters.push_back(name);
    c.scales.push_back(scale);
  };
  // --- force balances of mechanical pairs
  for (const auto& pair : st.mechanical) {
    const std::string& q = pair.first;  // named, not bound: lambdas below capture them (Clang 14)
    const std::string& v = pair.second;
    const std::string text = *model.derivative(v);
    const Eigen::VectorXd vv = nominal.series(v), qq = nominal.series(q);
    const double vrms = positive(rms(vv), 1.0), qrms = positive(rms(qq), 1.0);
    double mass = 1;
    if (is_force_form(text)) {
      static const std::regex tail(R"(/\s*([A-Za-z_][A-Za-z0-9_]*)\s*$)");
      std::smatch m;
      const std::string s = trim(text);
      if (std::regex_search(s, m, tail))
        if (const auto* p = model.parameter(m[1].str())) mass = std::abs(p->value) > 0 ? std::abs(p->value) : 1.0;
    }
    const double force = positive(mass * rms(rate(vv, Ts)), mass * vrms) ;
    auto make = [&](const std::string& effect, const std::vector<std::tuple<std::string, double, double, double>>& params,
                    auto term_of) {
      if (excluded(effect)) return;
      Candidate c;
      c.effect = effect;
      c.equation = v;
      c.model = model;
      std::vector<std::string> names;
      for (const auto& [n, val, sc, lo] : params) {
        names.push_back(fresh_name(c.model, n));
        add_param(c, names.back(), val, sc, lo);
      }
      c.term = term_of(names);
      if (effect == "stribeck_friction") c.neutral[2] = std::nan("");  // vs: irrelevant once Fc = Fs = 0
      *c.model.derivative(v) = subtract_force(text, c.term);
      out.push_back(std::move(c));
    };
    // Friction and drag dissipate: their coefficients are >= 0 (a negative one is not that effect).
    make("coulomb_friction", {{"Fc", 0.0, force, 0.0}}, [&](auto& n) { return n[0] + "*sign(" + v + ")"; });
    make("stribeck_friction", {{"Fc", 0.0, force, 0.0}, {"Fs", 0.0, force, 0.0}, {"vs", 0.3 * vrms, vrms, 1e-9 * vrms}},
         [&](auto& n) { return "sign(" + v + ")*(" + n[0] + " + " + n[1] + "*exp(-(" + v + "/" + n[2] + ")^2))"; });
    make("viscous_friction", {{"Fv", 0.0, force / vrms, 0.0}}, [&](auto& n) { return n[0] + "*" + v; });
    make("quadratic_drag", {{"Cd", 0.0, force / (vrms * vrms), 0.0}},
         [&](auto& n) { return n[0] + "*" + v + "*abs(" + v + ")"; });
    make("constant_offset", {{"offset", 0.0, force, -1e300}}, [&](auto& n) { return n[0]; });
    make("cubic_stiffness", {{"k3", 0.0, force / (qrms * qrms * qrms), -1e300}},
         [&](auto& n) { return n[0] + "*" + q + "^3"; });
  }
  // --- other state equations (tanks, thermal, first-order lags)
  for (const auto& x : st.other_states) {
    const std::string text = *model.derivative(x);
    const Eigen::VectorXd xx = nominal.series(x);
    const double xrms = positive(rms(xx), 1.0);
    const double drms = positive(rms(rate(xx, Ts)), xrms);
    auto make = [&](const std::string& effect, const std::string& pname, double scale, auto term_of) {
      if (excluded(effect)) return;
      Candidate c;
      c.effect = effect;
      c.equation = x;
      c.model = model;
      const std::string n = fresh_name(c.model, pname);
      add_param(c, n, 0.0, scale);
      c.term = term_of(n);
      *c.model.derivative(x) = trim(text) + " - " + c.term;
      out.push_back(std::move(c));
    };
    make("constant_offset", "offset_" + x, drms, [&](const std::string& n) { return n; });
    make("cubic_stiffness", "k3_" + x, drms / (xrms * xrms * xrms),
         [&](const std::string& n) { return n + "*" + x + "^3"; });
    if (xx.minCoeff() > -0.05 * xx.cwiseAbs().maxCoeff())
      make("sqrt_outflow", "a_" + x, drms / std::sqrt(xrms),
           [&](const std::string& n) { return n + "*sqrt(max(" + x + ", 0))"; });
  }
  // --- actuators
  for (const auto& a : st.actuators) {
    const Eigen::VectorXd aa = nominal.series(a);
    const double amax = positive(aa.cwiseAbs().maxCoeff(), 1.0);
    auto rewire = [&](Candidate& c, const std::string& by) {
      for (auto& d : c.model.derivatives) d.second = replace_symbol(d.second, a, by);
      for (auto& d : c.model.signals) d.second = replace_symbol(d.second, a, by);
    };
    if (!excluded("input_saturation")) {
      Candidate c{"input_saturation", a, "", {}, {}, {}, model, 0};
      const std::string p = fresh_name(c.model, a + "_max");
      add_param(c, p, 0.9 * amax, amax, 0.0, 1e300, 1e300);
      const std::string s = fresh_name(c.model, a + "_sat");
      c.term = "min(max(" + a + ", -" + p + "), " + p + ")";
      c.model.sampled.emplace_back(s, c.term);
      rewire(c, s);
      out.push_back(std::move(c));
    }
    if (!excluded("dead_zone")) {
      Candidate c{"dead_zone", a, "", {}, {}, {}, model, 0};
      const std::string p = fresh_name(c.model, a + "_dz");
      add_param(c, p, 0.02 * amax, 0.1 * amax, 0.0);
      const std::string s = fresh_name(c.model, a + "_eff");
      c.term = a + " - min(max(" + a + ", -" + p + "), " + p + ")";
      c.model.sampled.emplace_back(s, c.term);
      rewire(c, s);
      out.push_back(std::move(c));
    }
    if (!excluded("backlash")) {
      Candidate c{"backlash", a, "", {}, {}, {}, model, 0};
      const std::string p = fresh_name(c.model, a + "_play");
      add_param(c, p, 0.02 * amax, 0.1 * amax, 0.0);
      const std::string s = fresh_name(c.model, a + "_bl");
      c.term = "max(" + a + " - " + p + ", min(" + a + " + " + p + ", prev(" + s + ", 1)))";
      c.model.sampled.emplace_back(s, c.term);
      rewire(c, s);
      out.push_back(std::move(c));
    }
    if (!excluded("time_delay"))
      for (int n : {1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64}) {
        if (n >= N / 10) break;
        out.push_back(delay_candidate(model, a, n));
      }
  }
  // --- sensors
  for (std::size_t j = 0; j < model.outputs.size(); ++j) {
    const std::string y = model.outputs[j].first, col = model.outputs[j].second;  // captured below (Clang 14)
    const auto& mv = measured.column(col);
    const double lo = *std::min_element(mv.begin(), mv.end()), hi = *std::max_element(mv.begin(), mv.end());
    const double range = positive(hi - lo, 1.0);
    const Eigen::VectorXd yy = nominal.series(y);
    auto sensor = [&](const std::string& effect, const std::string& suffix, auto setup) {
      if (excluded(effect)) return;
      Candidate c{effect, y, "", {}, {}, {}, model, 0};
      const std::string s = fresh_name(c.model, y + suffix);
      setup(c, s);
      c.model.sampled.emplace_back(s, c.term);
      c.model.outputs[j].first = s;
      out.push_back(std::move(c));
    };
    sensor("output_saturation", "_sensor", [&](Candidate& c, const std::string&) {
      const std::string a = fresh_name(c.model, y + "_lo");
      add_param(c, a, lo, range, -1e300, 1e300, -1e300);
      const std::string b = fresh_name(c.model, y + "_hi");
      add_param(c, b, hi, range, -1e300, 1e300, 1e300);
      c.term = "min(max(" + y + ", " + a + "), " + b + ")";
    });
    sensor("hysteresis", "_h", [&](Candidate& c, const std::string& s) {
      const std::string w = fresh_name(c.model, y + "_w");
      add_param(c, w, 0.01 * range, 0.05 * range, 0.0);
      c.term = "max(" + y + " - " + w + ", min(" + y + " + " + w + ", prev(" + s + ", 1)))";
    });
    // A mirror only makes sense if the data stay non-negative while the model goes negative.
    if (lo > -0.02 * range && yy.minCoeff() < 0)
      sensor("absolute_value_sensor", "_abs", [&](Candidate& c, const std::string&) {
        c.term = "abs(" + y + ")";
        c.restart = true;
      });
  }
  return out;
}

}  // namespace sets
