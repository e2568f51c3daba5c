// The plant families of the randomised suite: each draws its magnitudes over decades, its symbol
// and column names, and says where effects can enter (velocities, springs, levels, actuators).

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "random_plant_builder.hpp"

namespace sets::random_plant_detail {

namespace {

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

}  // namespace

void draw_family(Rng& r, Build& b) {
  if (b.family == "one_mass") one_mass(r, b);
  else if (b.family == "two_mass") two_mass(r, b);
  else if (b.family == "motor") motor(r, b);
  else if (b.family == "thermal") thermal(r, b);
  else if (b.family == "tanks") tanks(r, b);
  else if (b.family == "position_loop") position_loop(r, b);
  else throw InputError("random plant: unknown family \"" + b.family + "\"");
}

}  // namespace sets::random_plant_detail
