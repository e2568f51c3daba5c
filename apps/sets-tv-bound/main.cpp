// sets-tv-bound: time-varying parameter bounds for the overhead crane of Salehpour & Johansson
// (Section VII). Simulates the crane (15) with piecewise-constant or sinusoidal perturbations of
// b, lambda, kappa and white output noise of a given window norm, then estimates the perturbation
// trajectories and their bounds with the l-inf LP (8) and the sparse-derivative MILP (14).
// Prints Tables I-III of the paper (true and estimated bounds), RMS tracking errors and times.

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "sets/examples/crane.hpp"
#include "common/cli.hpp"
#include "common/json_output.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/methods/tv_bound/tv_bound.hpp"
#include "sets/methods/tv_bound/tv_relinearisation.hpp"

namespace {

using sets::crane::kStep;

struct Case {
  std::string table;  // "I", "II", "III" (the sinusoid of Fig. 7 is listed under table I, shape "sine")
  std::string label;
  double lambda0 = 3.3, kappa0 = 0.25, b0 = 2.0;
  Eigen::Vector3d amplitude{0.2, 1.0, 0.5};  // true bound of (pi1, pi2, pi3) on (b, lambda, kappa)
  double noise = 0.1;                        // window norm of the white output noise
  bool sine = false;
};

// Inputs, all within the same amplitude bound |u| <= 1 (the paper's u_c is only in its Fig. 1).
//   square:    +-1, period 4 s (the default; the reproduction tables use it).
//   prbs:      +-1 pseudo-random binary sequence: every kPrbsHold seconds the sign flips with
//              probability 1/2 (std::mt19937_64 seeded with --input-seed), so no level lasts
//              less than the hold time.
//   multisine: sum of equal-amplitude sines at kMultisineFreq (rad/s, spanning the pendulum's
//              resonance sqrt(lambda0) = 1.82 rad/s at the nominal 3.3) with Schroeder phases
//              (low crest factor), scaled so that max_k |u(k)| = 1 on the horizon.
inline constexpr double kPrbsHold = 0.25;  // [s], 5 samples
inline constexpr double kMultisineFreq[] = {0.5, 1.0, 1.5, 1.8, 2.2, 3.0, 4.0};  // [rad/s]

Eigen::MatrixXd input(const std::string& kind, int N, unsigned input_seed) {
  Eigen::MatrixXd u(N, 1);
  if (kind == "square") {
    for (int k = 0; k < N; ++k) u(k, 0) = (static_cast<int>(k * kStep / 2.0) % 2 == 0) ? 1.0 : -1.0;
  } else if (kind == "prbs") {
    const int hold = static_cast<int>(std::lround(kPrbsHold / kStep));
    std::mt19937_64 rng(input_seed);
    std::bernoulli_distribution flip(0.5);
    double level = 1.0;
    for (int k = 0; k < N; ++k) {
      if (k > 0 && k % hold == 0 && flip(rng)) level = -level;
      u(k, 0) = level;
    }
  } else {  // multisine
    const int m = static_cast<int>(std::size(kMultisineFreq));
    const double pi = 3.141592653589793;
    for (int k = 0; k < N; ++k) {
      double v = 0;
      for (int i = 0; i < m; ++i)  // Schroeder phase phi_i = -pi i (i + 1) / m
        v += std::sin(kMultisineFreq[i] * k * kStep - pi * i * (i + 1) / m);
      u(k, 0) = v;
    }
    const double peak = u.cwiseAbs().maxCoeff();
    if (peak > 0) u /= peak;
  }
  return u;
}

// Perturbations over the horizon T = N h. Piecewise constant ("quantized", Fig. 1):
//   pi1 = A1 * {0 on [0, .2T), 1 on [.2T, .6T), .5 on [.6T, T)}
//   pi2 = A2 * {0 on [0, .3T), 1 on [.3T, .7T), .4 on [.7T, T)}
//   pi3 = A3 * {.5 on [.1T, .45T), 1 on [.45T, .8T), 0 elsewhere}
// Sinusoidal (Fig. 7): pi_i = A_i sin(2 pi t / T_i) with T_i = T, T/1.5, T/2.
Eigen::MatrixXd perturbation(const Case& c, int N) {
  Eigen::MatrixXd pi(N, 3);
  const double two_pi = 6.283185307179586;
  for (int k = 0; k < N; ++k) {
    const double s = static_cast<double>(k) / N;
    if (c.sine) {
      pi(k, 0) = std::sin(two_pi * s);
      pi(k, 1) = std::sin(two_pi * 1.5 * s);
      pi(k, 2) = std::sin(two_pi * 2.0 * s);
    } else {
      pi(k, 0) = s < 0.2 ? 0.0 : (s < 0.6 ? 1.0 : 0.5);
      pi(k, 1) = s < 0.3 ? 0.0 : (s < 0.7 ? 1.0 : 0.4);
      pi(k, 2) = s < 0.1 ? 0.0 : (s < 0.45 ? 0.5 : (s < 0.8 ? 1.0 : 0.0));
    }
  }
  return pi * c.amplitude.asDiagonal();
}

std::vector<Case> cases(const std::string& which) {
  std::vector<Case> out;
  auto want = [&](const char* t) { return which == "all" || which == t; };
  if (want("I")) {
    const Eigen::Vector3d amps[] = {{0.2, 1.0, 0.5}, {0.4, 1.0, 0.5}, {0.2, 2.0, 0.5}, {0.2, 1.0, 1.0}};
    for (const auto& a : amps) {
      Case c;
      c.table = "I";
      c.amplitude = a;
      std::ostringstream s;
      s << "A = [" << a[0] << ", " << a[1] << ", " << a[2] << "]";
      c.label = s.str();
      out.push_back(c);
    }
    Case c;
    c.table = "I";
    c.sine = true;
    c.label = "sinusoid (Fig. 7), A = [0.2, 1, 0.5]";
    out.push_back(c);
  }
  if (want("II")) {
    const double nominal[][3] = {{3.0, 0.25, 2.0}, {3.7, 0.25, 2.0}, {3.3, 0.20, 2.0},
                                 {3.3, 0.15, 2.0}, {3.3, 0.25, 1.5}, {3.3, 0.25, 2.5}};
    for (const auto& n : nominal) {
      Case c;
      c.table = "II";
      c.lambda0 = n[0];
      c.kappa0 = n[1];
      c.b0 = n[2];
      std::ostringstream s;
      s << "[l0,k0,b0] = [" << n[0] << ", " << n[1] << ", " << n[2] << "]";
      c.label = s.str();
      out.push_back(c);
    }
  }
  if (want("III")) {
    for (double e : {0.05, 0.10, 0.20, 0.30}) {
      Case c;
      c.table = "III";
      c.noise = e;
      std::ostringstream s;
      s << "eps = " << e;
      c.label = s.str();
      out.push_back(c);
    }
  }
  return out;
}

nlohmann::json vec(const Eigen::VectorXd& v) {
  std::vector<double> out(v.data(), v.data() + v.size());
  return out;
}

std::string fmt(const Eigen::VectorXd& v, int prec = 2) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(prec) << "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
  s << "]";
  return s.str();
}

}  // namespace

int main(int argc, char** argv) {
  sets::app::Cli cli("sets-tv-bound", "sets-tv-bound: bounds of time-varying parameter perturbations of the overhead crane "
               "(Salehpour & Johansson), l-inf LP and sparse-derivative MILP");
  CLI::App& app = cli.app();
  std::string method = "both", table = "all", json_path;
  double time_limit = 60, seconds = 6, mu_rel = 0.001, box_rel = 4, gap = 1e-4;
  unsigned seed = 1;
  std::string formulation = "single";
  bool warm = true, verbose = false;
  int only = -1;
  double scale = 1;
  std::string milp_eps = "linf";
  std::string plant = "exact";
  std::string input_kind = "square";
  unsigned input_seed = 1;
  int relinearise = 0;
  app.add_option("--method", method, "linf, milp or both")->check(CLI::IsMember({"linf", "milp", "both"}));
  app.add_option("--table", table, "I, II, III or all")->check(CLI::IsMember({"I", "II", "III", "all"}));
  app.add_option("--time-limit", time_limit, "MILP time limit per case [s]")->check(CLI::PositiveNumber);
  long node_limit = 0;
  app.add_option("--node-limit", node_limit,
                 "MILP branch-and-bound node limit per case (0 = none); unlike --time-limit the result "
                 "does not depend on the machine's load, so runs are reproducible")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--seed", seed, "noise seed");
  cli.add_output_file("--json", json_path, "write the results as JSON to this file");
  app.add_option("--horizon", seconds, "simulated time [s] (N = horizon / 0.05)")->check(CLI::Range(1.0, 60.0));
  app.add_option("--mu", mu_rel, "MILP threshold mu as a fraction of the nominal (b0, l0, k0)")
      ->check(CLI::PositiveNumber);
  app.add_option("--box", box_rel, "a-priori |pi_i| <= box * nominal_i (sets the big-M)")->check(CLI::PositiveNumber);
  app.add_option("--gap", gap, "MILP relative gap")->check(CLI::PositiveNumber);
  app.add_option("--formulation", formulation, "MILP binaries: single (one per jump) or paper (two, eq. 12)")
      ->check(CLI::IsMember({"single", "paper"}));
  app.add_flag("!--no-warm-start", warm, "do not start the MILP from the l-inf solution");
  app.add_option("--case", only, "run only this case of the selected table(s) (0-based)")->check(CLI::NonNegativeNumber);
  app.add_option("--scale", scale,
                 "multiply every perturbation amplitude and noise level by this (1 = the paper's; smaller "
                 "values keep the biaffine approximation accurate)")
      ->check(CLI::PositiveNumber);
  app.add_option("--milp-eps", milp_eps,
                 "eps of the MILP: linf (from (8), the paper's) or oracle (the window norm of "
                 "y_m - Upsilon - Xi Pi at the true Pi; a diagnostic only)")
      ->check(CLI::IsMember({"linf", "oracle"}));
  app.add_option("--plant", plant,
                 "what generates y_m: exact (the crane (15), i.e. model (1)) or biaffine (the approximation "
                 "(2) with the true pi, so nu = eta exactly and the methods' assumption holds)")
      ->check(CLI::IsMember({"exact", "biaffine"}));
  app.add_option("--input", input_kind,
                 "crane input u, all |u| <= 1: square (period 4 s, the default), prbs (random +-1, minimum "
                 "hold 0.25 s, --input-seed) or multisine (7 sines at 0.5-4 rad/s around the resonance "
                 "sqrt(lambda0) = 1.8 rad/s, Schroeder phases)")
      ->check(CLI::IsMember({"square", "prbs", "multisine"}));
  app.add_option("--input-seed", input_seed, "seed of the prbs input (independent of the noise --seed)");
  app.add_option("--relinearise", relinearise,
                 "re-linearise (1) around the l-inf estimate this many times (sequential LP; not in the paper; "
                 "0 = the paper's single expansion around pi = 0); the MILP uses the last linearisation")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--verbose", verbose, "GLPK branch-and-cut log");
  if (const auto code = cli.parse(argc, argv)) return *code;
  const bool do_linf = method != "milp", do_milp = method != "linf";
  if (relinearise > 0 && plant == "biaffine") {
    std::cerr << "sets-tv-bound: --relinearise needs --plant exact (the biaffine plant is already affine in pi)\n";
    return int(sets::exit_bad_input);
  }
  const int N = static_cast<int>(std::lround(seconds / kStep));

  try {
    nlohmann::json out;
    out["settings"] = {{"N", N}, {"h", kStep}, {"seed", seed}, {"time_limit_s", time_limit}, {"node_limit", node_limit}, {"mu_rel", mu_rel},
                       {"box_rel", box_rel}, {"gap", gap}, {"formulation", formulation}, {"warm_start", warm},
                       {"scale", scale}, {"milp_eps", milp_eps},
                       {"plant", plant}, {"relinearise", relinearise}};
    nlohmann::json input_settings = {{"kind", input_kind}, {"amplitude_bound", 1.0}};
    if (input_kind == "square") input_settings["period_s"] = 4.0;
    if (input_kind == "prbs") {
      input_settings["min_hold_s"] = kPrbsHold;
      input_settings["seed"] = input_seed;
      input_settings["generator"] = "std::mt19937_64, sign flip with probability 1/2 per hold";
    }
    if (input_kind == "multisine") {
      input_settings["frequencies_rad_s"] = std::vector<double>(std::begin(kMultisineFreq), std::end(kMultisineFreq));
      input_settings["phases"] = "Schroeder, -pi i (i + 1) / m";
      input_settings["scaled_to_peak"] = 1.0;
    }
    out["settings"]["input"] = input_settings;
    out["cases"] = nlohmann::json::array();
    std::vector<Case> selected = cases(table);
    if (only >= 0) {
      if (only >= static_cast<int>(selected.size()))
        throw sets::InputError("--case " + std::to_string(only) + ": the selection has " +
                               std::to_string(selected.size()) + " cases");
      selected = {selected[static_cast<std::size_t>(only)]};
    }
    std::cout << "sets-tv-bound: overhead crane, N = " << N << " samples (h = 0.05 s), window 1/35 on 36 samples, "
              << "seed " << seed << ", plant " << plant << (plant == "biaffine" ? " (approximation (2) + noise)" : " (crane (15))")
              << ", re-linearisations " << relinearise << ", input " << input_kind << "\n"
              << "bounds rho = max_k |pi(k)| for (pi1, pi2, pi3) on (b, lambda, kappa); estimates, not guarantees\n\n";
    std::string current;
    for (Case& c : selected) {
      c.amplitude *= scale;
      c.noise *= scale;
    }
    for (const Case& c : selected) {
      if (c.table != current) {
        current = c.table;
        std::cout << "Table " << c.table << "\n";
      }
      const sets::TimeVaryingModel model = sets::crane::model(c.lambda0, c.kappa0, c.b0);
      const Eigen::MatrixXd u = input(input_kind, N, input_seed), pi = perturbation(c, N);
      const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(3);
      const sets::BiaffineRegression nominal_regression = sets::biaffine_regression(model, x0, u);
      const Eigen::MatrixXd y_plant =
          plant == "exact" ? sets::simulate(model, x0, u, pi).y
                           : sets::unstack_samples(nominal_regression.upsilon +
                                                       nominal_regression.xi * sets::stack_samples(pi),
                                                   model.outputs());
      // White Gaussian noise scaled to the requested window norm.
      const sets::WindowNorm window = sets::WindowNorm::pulse(36, 1.0 / 35);
      std::mt19937_64 rng(seed);
      std::normal_distribution<double> normal(0, 1);
      Eigen::VectorXd eta(N + 1);
      for (int k = 0; k <= N; ++k) eta[k] = normal(rng);
      eta *= c.noise / window(eta);

      sets::TvBoundData data{nominal_regression, y_plant + eta, {window}};
      const Eigen::Vector3d nominal(c.b0, c.lambda0, c.kappa0);
      const Eigen::VectorXd F = nominal.cwiseInverse();
      const Eigen::VectorXd true_bound = pi.cwiseAbs().colwise().maxCoeff().transpose();
      nlohmann::json j = {{"table", c.table}, {"label", c.label}, {"lambda0", c.lambda0}, {"kappa0", c.kappa0},
                          {"b0", c.b0}, {"noise_window_norm", c.noise}, {"shape", c.sine ? "sine" : "steps"},
                          {"true_bound", vec(true_bound)}};
      // Window norm of nu = y_m - Upsilon - Xi Pi at the true Pi: noise plus linearization error.
      const double true_nu = window(sets::stack_samples(data.y) - data.regression.upsilon -
                                    data.regression.xi * sets::stack_samples(pi));
      const double deviation = window(sets::stack_samples(data.y) - data.regression.upsilon);
      j["true_residual_window_norm"] = true_nu;
      // How strongly each parameter shows in the output under (2): window norm of Xi Pi for a
      // constant pi_i = true amplitude (others 0). Compare with the noise's window norm: a parameter
      // whose effect is of the order of the noise cannot be told apart from it.
      Eigen::Vector3d sensitivity;
      for (int i = 0; i < 3; ++i) {
        Eigen::MatrixXd p1 = Eigen::MatrixXd::Zero(N, 3);
        p1.col(i).setConstant(c.amplitude[i]);
        sensitivity[i] = window(nominal_regression.xi * sets::stack_samples(p1));
      }
      j["sensitivity_window_norm"] = vec(sensitivity);
      j["output_deviation_window_norm"] = deviation;
      std::cout << "  " << std::left << std::setw(40) << c.label << std::right << " true " << fmt(true_bound)
                << "  ||y-Cz||_w " << std::setprecision(3) << deviation << "  ||nu(true pi)||_w " << true_nu
                << "  ||Xi pi_i||_w " << fmt(sensitivity, 3) << "\n";
      sets::TvBoundResult linf;
      if (do_linf || do_milp) {  // the MILP needs eps from (8)
        sets::LinfBoundOptions lo;
        lo.F = F;
        lo.G = F;
        lo.mu = mu_rel * nominal;
        if (relinearise == 0) {
          linf = sets::linf_bound(data, lo);
        } else {
          const auto t0 = std::chrono::steady_clock::now();
          const auto rl = sets::relinearised_linf_bound(model, x0, u, data.y, data.windows, relinearise, lo);
          linf = rl.linf;
          linf.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          data = rl.data;  // the MILP runs on the last linearisation, with the last LP's eps
          // nu(true pi) on the linearisation around the last-but-one estimate (the one (8) and (14) use).
          const double relin_nu = window(sets::stack_samples(data.y) - data.regression.upsilon -
                                         data.regression.xi * sets::stack_samples(pi));
          nlohmann::json steps = nlohmann::json::array();
          for (const auto& st : rl.steps)
            steps.push_back({{"objective", st.objective}, {"epsilon", vec(st.epsilon)}, {"bound", vec(st.bound)},
                             {"max_change", st.max_change}, {"exact_residual_window_norm", vec(st.exact_residual)}});
          j["relinearisation"] = {{"true_residual_window_norm", relin_nu}, {"steps", steps}};
          std::cout << "      relinearised " << relinearise << "x: ||nu(true pi)||_w " << std::setprecision(3) << relin_nu
                    << " on the last linearisation; per LP: bound, eps, max |pi - pi_bar|, ||y - y(pi-hat)||_w exact\n";
          for (std::size_t m = 0; m < rl.steps.size(); ++m)
            std::cout << "        " << m << "  " << fmt(rl.steps[m].bound) << "  " << fmt(rl.steps[m].epsilon, 3) << "  "
                      << std::setprecision(3) << rl.steps[m].max_change << "  " << fmt(rl.steps[m].exact_residual, 3)
                      << "\n";
        }
        if (do_linf) {
          const Eigen::VectorXd rms = sets::rms_tracking_error(linf.pi, pi);
          j["linf"] = {{"bound", vec(linf.bound)}, {"rms_tracking", vec(rms)}, {"seconds", linf.seconds},
                       {"epsilon", vec(linf.epsilon)}, {"changes", linf.changes.size()}};
          std::cout << "      linf  bound " << fmt(linf.bound) << "  rms " << fmt(rms, 3) << "  eps "
                    << fmt(linf.epsilon, 3) << "  " << std::fixed << std::setprecision(2) << linf.seconds << " s\n";
        }
      }
      if (do_milp) {
        sets::SparseBoundOptions so;
        so.F = F;
        so.mu = mu_rel * nominal;
        so.max_abs = box_rel * nominal;
        so.epsilon = milp_eps == "oracle" ? Eigen::VectorXd::Constant(1, true_nu) : linf.epsilon;
        if (milp_eps == "oracle" && relinearise > 0)
          so.epsilon[0] = window(sets::stack_samples(data.y) - data.regression.upsilon -
                                 data.regression.xi * sets::stack_samples(pi));
        so.formulation =
            formulation == "paper" ? sets::SparseFormulation::paper : sets::SparseFormulation::single_binary;
        so.milp = {time_limit, gap, verbose, node_limit};
        if (warm) so.start = linf.pi;
        const auto m = sets::sparse_bound(data, so);
        const Eigen::VectorXd rms = sets::rms_tracking_error(m.pi, pi);
        j["milp"] = {{"bound", vec(m.bound)}, {"rms_tracking", vec(rms)}, {"seconds", m.seconds}, {"gap", m.gap},
                     {"status", sets::to_string(m.status)}, {"objective", m.objective},
                     {"best_bound", m.best_bound}, {"changes", m.changes.size()}, {"nodes", m.nodes}};
        std::cout << "      milp  bound " << fmt(m.bound) << "  rms " << fmt(rms, 3) << "  jumps "
                  << m.changes.size() << "  obj " << m.objective << "  gap " << std::setprecision(3) << m.gap << "  " << std::fixed
                  << std::setprecision(2) << m.seconds << " s, " << m.nodes << " nodes (" << sets::to_string(m.status) << ")\n";
      }
      out["cases"].push_back(j);
      std::cout.flush();
    }
    if (!json_path.empty()) sets::write_file_atomically(json_path, out.dump(2) + "\n");
  } catch (const std::exception& e) {
    return sets::report_failure("sets-tv-bound", e);
  }
  return 0;
}
