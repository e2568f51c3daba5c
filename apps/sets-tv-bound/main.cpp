// sets-tv-bound: time-varying parameter bounds for the overhead crane of Salehpour & Johansson
// (Section VII). Simulates the crane (15) with piecewise-constant or sinusoidal perturbations of
// b, lambda, kappa and white output noise of a given window norm, then estimates the perturbation
// trajectories and their bounds with the l-inf LP (8) and the sparse-derivative MILP (14).
// Prints Tables I-III of the paper (true and estimated bounds), RMS tracking errors and times.

#include <cmath>
#include <iostream>
#include <iterator>
#include <vector>

#include "common/cli.hpp"
#include "common/json_output.hpp"
#include "run_case.hpp"
#include "sets/core/error.hpp"
#include "sets/core/exit_code.hpp"

namespace {

using sets::app::Json;

// The settings as recorded in the JSON.
Json settings_json(const TvSettings& s, double scale) {
  Json out = {{"N", s.N}, {"h", sets::crane::kStep}, {"seed", s.seed}, {"time_limit_s", s.time_limit},
              {"node_limit", s.node_limit}, {"mu_rel", s.mu_rel}, {"box_rel", s.box_rel}, {"gap", s.gap},
              {"formulation", s.formulation}, {"solver", s.solver}, {"grid", s.grid}, {"warm_start", s.warm}, {"scale", scale}, {"milp_eps", s.milp_eps},
              {"plant", s.plant}, {"relinearise", s.relinearise}};
  Json input = {{"kind", s.input}, {"amplitude_bound", 1.0}};
  if (s.input == "square") input["period_s"] = 4.0;
  if (s.input == "prbs") {
    input["min_hold_s"] = sets::crane::kPrbsHold;
    input["seed"] = s.input_seed;
    input["generator"] = "std::mt19937_64, sign flip with probability 1/2 per hold";
  }
  if (s.input == "multisine") {
    input["frequencies_rad_s"] =
        std::vector<double>(std::begin(sets::crane::kMultisineFreq), std::end(sets::crane::kMultisineFreq));
    input["phases"] = "Schroeder, -pi i (i + 1) / m";
    input["scaled_to_peak"] = 1.0;
  }
  out["input"] = input;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  sets::app::Cli cli("sets-tv-bound", "sets-tv-bound: bounds of time-varying parameter perturbations of the overhead "
                                      "crane (Salehpour & Johansson), l-inf LP and sparse-derivative MILP");
  CLI::App& app = cli.app();
  TvSettings s;
  std::string method = "both", table = "all", json_path;
  double seconds = 6, scale = 1;
  int only = -1;
  app.add_option("--method", method, "linf, milp or both")->check(CLI::IsMember({"linf", "milp", "both"}));
  app.add_option("--table", table, "I, II, III or all")->check(CLI::IsMember({"I", "II", "III", "all"}));
  app.add_option("--time-limit", s.time_limit, "MILP time limit per case [s]")->check(CLI::PositiveNumber);
  app.add_option("--node-limit", s.node_limit,
                 "MILP branch-and-bound node limit per case (0 = none); unlike --time-limit the result "
                 "does not depend on the machine's load, so runs are reproducible")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--seed", s.seed, "noise seed");
  cli.add_output_file("--json", json_path, "write the results as JSON to this file");
  app.add_option("--horizon", seconds, "simulated time [s] (N = horizon / 0.05)")->check(CLI::Range(1.0, 60.0));
  app.add_option("--mu", s.mu_rel, "MILP threshold mu as a fraction of the nominal (b0, l0, k0)")->check(CLI::PositiveNumber);
  app.add_option("--box", s.box_rel, "a-priori |pi_i| <= box * nominal_i (sets the big-M)")->check(CLI::PositiveNumber);
  app.add_option("--gap", s.gap, "MILP relative gap")->check(CLI::PositiveNumber);
  app.add_option("--formulation", s.formulation, "MILP binaries: single (one per jump) or paper (two, eq. 12)")
      ->check(CLI::IsMember({"single", "paper"}));
  app.add_option("--solver", s.solver,
                 "how (14) is solved: jump (branch and bound over jump patterns with certified bounds, the "
                 "default) or glpk (the big-M MILP (12)-(14) in GLPK, for comparison; --formulation applies)")
      ->check(CLI::IsMember({"jump", "glpk"}));
  app.add_option("--grid", s.grid,
                 "the paper's quantized approximation: jumps only every GRID samples (1 = every sample, (14) "
                 "as written)")
      ->check(CLI::PositiveNumber);
  app.add_flag("!--no-warm-start", s.warm, "do not start the MILP from the l-inf solution");
  app.add_option("--case", only, "run only this case of the selected table(s) (0-based)")->check(CLI::NonNegativeNumber);
  app.add_option("--scale", scale,
                 "multiply every perturbation amplitude and noise level by this (1 = the paper's; smaller "
                 "values keep the biaffine approximation accurate)")
      ->check(CLI::PositiveNumber);
  app.add_option("--milp-eps", s.milp_eps,
                 "eps of the MILP: linf (from (8), the paper's) or oracle (the window norm of "
                 "y_m - Upsilon - Xi Pi at the true Pi; a diagnostic only)")
      ->check(CLI::IsMember({"linf", "oracle"}));
  app.add_option("--plant", s.plant,
                 "what generates y_m: exact (the crane (15), i.e. model (1)) or biaffine (the approximation "
                 "(2) with the true pi, so nu = eta exactly and the methods' assumption holds)")
      ->check(CLI::IsMember({"exact", "biaffine"}));
  app.add_option("--input", s.input,
                 "crane input u, all |u| <= 1: square (period 4 s, the default), prbs (random +-1, minimum "
                 "hold 0.25 s, --input-seed) or multisine (7 sines at 0.5-4 rad/s around the resonance "
                 "sqrt(lambda0) = 1.8 rad/s, Schroeder phases)")
      ->check(CLI::IsMember({"square", "prbs", "multisine"}));
  app.add_option("--input-seed", s.input_seed, "seed of the prbs input (independent of the noise --seed)");
  app.add_option("--relinearise", s.relinearise,
                 "re-linearise (1) around the l-inf estimate this many times (sequential LP; not in the paper; "
                 "0 = the paper's single expansion around pi = 0); the MILP uses the last linearisation")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--verbose", s.verbose, "progress of (14): the jump search every 2 s, or GLPK's branch-and-cut log");
  if (const auto code = cli.parse(argc, argv)) return *code;
  return cli.run([&] {
    if (s.relinearise > 0 && s.plant == "biaffine")
      throw sets::InputError("--relinearise needs --plant exact (the biaffine plant is already affine in pi)");
    s.linf = method != "milp";
    s.milp = method != "linf";
    s.N = static_cast<int>(std::lround(seconds / sets::crane::kStep));
    Json out;
    out["settings"] = settings_json(s, scale);
    out["cases"] = Json::array();
    std::vector<sets::crane::Case> selected = sets::crane::cases(table);
    if (only >= 0) {
      if (only >= static_cast<int>(selected.size()))
        throw sets::InputError("--case " + std::to_string(only) + ": the selection has " +
                               std::to_string(selected.size()) + " cases");
      selected = {selected[static_cast<std::size_t>(only)]};
    }
    std::cout << "sets-tv-bound: overhead crane, N = " << s.N << " samples (h = 0.05 s), window 1/35 on 36 samples, "
              << "seed " << s.seed << ", plant " << s.plant
              << (s.plant == "biaffine" ? " (approximation (2) + noise)" : " (crane (15))") << ", re-linearisations "
              << s.relinearise << ", input " << s.input << "\n"
              << "bounds rho = max_k |pi(k)| for (pi1, pi2, pi3) on (b, lambda, kappa); estimates, not guarantees\n\n";
    std::string current;
    for (auto& c : selected) {
      c.amplitude *= scale;
      c.noise *= scale;
      if (c.table != current) std::cout << "Table " << (current = c.table) << "\n";
      out["cases"].push_back(run_case(c, s));
      std::cout.flush();
    }
    sets::app::write_json(json_path, out);
    return int(sets::exit_success);
  });
}
