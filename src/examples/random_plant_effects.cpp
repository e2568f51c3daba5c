// The effects the randomised suite hides in a plant's truth: each builder decides where the effect
// enters (from the plant's structure) and returns how to apply it at a given strength.

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "random_plant_builder.hpp"

namespace sets::random_plant_detail {

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

namespace {

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

// A parameter the calibration of a nested special case adjusts, from `v`.
std::string new_free_param(Names& names, std::vector<ModelParameter>& ps, const std::vector<std::string>& hints, double v,
                           double lo = -1e300) {
  const std::string n = new_fixed_param(names, ps, hints, v);
  ps.back().fixed = false;
  ps.back().min = lo;
  return n;
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
    // Fs = 0: Coulomb friction, from a level between the law's ends (Fc at speed, Fc + Fs at rest).
    E.special_case = {"coulomb_friction"};
    E.apply_special_case = [=](double k, double level, auto& eqs, auto& ps) {
      const std::string Fc = new_free_param(*names, ps, {"Fc", "fc"}, k * F * (1 + level * ratio), 0.0);
      equation_of(eqs, vel.eq).extra.push_back(Fc + "*sign(" + v + ")");
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
    // dFv = 0: Coulomb friction and a constant offset, from the law's levels with the forward side
    // at a level between its ends (fp at rest, fp + dFv v at the velocity's RMS).
    E.special_case = {"coulomb_friction", "constant_offset"};
    E.apply_special_case = [=](double k, double level, auto& eqs, auto& ps) {
      const double fp = k * F * a + level * k * F * dv, fn = k * F * bneg;
      const std::string Fc = new_free_param(*names, ps, {"Fc", "fc"}, std::max(0.0, 0.5 * (fp + fn)), 0.0);
      const std::string off = new_free_param(*names, ps, {"off", "bias"}, 0.5 * (fp - fn));
      equation_of(eqs, vel.eq).extra.push_back("(" + Fc + "*sign(" + v + ") + " + off + ")");
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
  const auto dead_band = [amax](double k) { return amax * k / (1 + k); };  // the law and its stand-in
  E.apply = [=](double k, auto& eqs, auto& sampled, auto&, auto&, auto& ps, auto& values) {
    const std::string s = (*names)({a + "_eff", a + "_act", "ua"});
    std::string expr;
    if (name == "dead_zone") {
      const double d = dead_band(k);
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
  if (name == "dead_zone") {
    // While the input stays on one side of the band, u - dz(u) is the constant d or -d: the law is
    // a constant offset at the input on those data (random plants 5 006 110, 942, 996: named so).
    // The offset starts at -d, 0 or +d (level 0, 1/2, 1).
    E.special_case = {"constant_offset"};
    E.apply_special_case = [=](double k, double level, auto& eqs, auto& ps) {
      const double d = dead_band(k);
      const std::string off = new_free_param(*names, ps, {"off", "bias"}, (2 * level - 1) * d);
      for (auto& e : eqs) e.body = replace_word(e.body, a, "(" + a + " + " + off + ")");
    };
  }
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

}  // namespace

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

}  // namespace sets::random_plant_detail
