// sets-ss-uncertainty: propagator subspace least squares and ellipsoidal uncertainty domains
// (Farah, Mercère, Poinot, van Wingerden), beside the feasible parameter set of the same regression.
//
// Without --data it runs the Monte Carlo study of Section V and prints Table I and the failure
// rates (sets::farah::study, printed by study.cpp); with --data it identifies a model from a CSV
// file and prints both domains.

#include <chrono>
#include <iomanip>
#include <iostream>
#include <thread>

#include "common/cli.hpp"
#include "common/json_output.hpp"
#include "sets/core/error.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/data/recording.hpp"
#include "study.hpp"

namespace {

int real_data(const Settings& st) {
  const sets::Recording table = sets::read_csv(st.data);
  const Eigen::MatrixXd u = table.matrix(sets::app::split_list(st.inputs), "--inputs");
  const Eigen::MatrixXd y = table.matrix(sets::app::split_list(st.outputs), "--outputs");
  if (st.order < 1) throw sets::InputError("--order: give the model order n >= 1 with --data");
  sets::SsUncertaintyOptions o;
  o.identification.order = st.order;
  o.identification.past = st.study.past;
  o.identification.estimate_d = st.study.estimate_d;
  o.identification.selection = parse_selection(st.selection);
  if (!st.rows.empty()) o.identification.rows = parse_rows(st.rows, static_cast<int>(y.cols()));
  o.level = st.study.level;
  const auto t0 = std::chrono::steady_clock::now();
  const auto result = sets::ss_uncertainty(u, y, o);
  const auto& id = result.identification;
  const auto& dom = result.estimate_level_set;
  const auto& p = *result.estimate_fps_pui;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto names = id.structure.parameter_names();
  const auto box = sets::outer_box(dom.ellipsoid);

  std::cout << "sets-ss-uncertainty: " << st.data << ", " << u.rows() << " samples, " << u.cols() << " inputs, "
            << y.cols() << " outputs, order " << st.order << ", p = " << st.study.past << "\n  rows of Gamma_1:";
  for (const auto& r : id.rows) std::cout << ' ' << sets::to_string(r);
  std::cout << "\n  l = " << dom.ell << " (residuals " << sets::to_string(st.study.level.residuals) << ", "
            << sets::to_string(st.study.level.norm) << "), J_min = " << dom.j_min << ", J_D = " << dom.j_d << "\n\n";
  if (p.empty()) {
    std::cout << "The feasible parameter set with |eps| <= l is empty: " << p.consistency.message() << '\n';
    return int(sets::exit_falsified);
  }
  if (p.consistency.falsified == sets::Falsified::unknown) std::cout << "Note: " << p.consistency.message() << "\n";
  std::cout << "  param        estimate     ellipsoid box (not guaranteed)       FPS PUI (holds only if |eps| <= l at the truth)\n";
  sets::app::Json jp = sets::app::Json::array();
  for (int i = 0; i < id.theta.size(); ++i) {
    std::cout << "  " << std::left << std::setw(8) << names[i] << std::right << std::scientific << std::setprecision(5)
              << std::setw(14) << id.theta[i] << "  [" << std::setw(13) << box[i].lower() << ", " << std::setw(13)
              << box[i].upper() << "]  [" << std::setw(13) << p.box[i].lower() << ", " << std::setw(13)
              << p.box[i].upper() << "]\n";
    jp.push_back({{"name", names[i]},
                  {"estimate", id.theta[i]},
                  {"ellipsoid_box", {box[i].lower(), box[i].upper()}},
                  {"pui", {p.box[i].lower(), p.box[i].upper()}}});
  }
  std::cout << std::fixed << std::setprecision(3) << "\nTiming: " << seconds << " s\n";
  if (!st.json_path.empty()) {
    sets::app::Json j;
    j["data"] = st.data;
    j["parameters"] = jp;
    j["ell"] = dom.ell;
    j["j_min"] = dom.j_min;
    j["pui_guaranteed"] = p.guaranteed;
    j["seconds"] = seconds;
    sets::app::write_json(st.json_path, j);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  sets::app::Cli cli("sets-ss-uncertainty", "sets-ss-uncertainty: propagator subspace LS with ellipsoidal uncertainty domains (Farah et al.)");
  CLI::App& app = cli.app();
  Settings st;
  st.study.threads = std::max(1u, std::thread::hardware_concurrency());
  std::string residuals = "all", norm = "entrywise";
  app.add_option("--runs", st.study.runs, "Monte Carlo runs")->check(CLI::Range(1, 10000000));
  app.add_option("--seed", st.study.seed, "random seed");
  app.add_option("--snr-db", st.study.snr_db, "signal-to-noise ratio per output channel, dB");
  app.add_option("--past,-p", st.study.past, "past horizon p (>= order)")->check(CLI::Range(1, 100000));
  app.add_option("--samples,-N", st.study.samples, "samples per run")->check(CLI::Range(2, 100000000));
  app.add_option("--threads", st.study.threads, "worker threads (one LP per thread)")->check(CLI::Range(1, 1024));
  app.add_flag("--estimate-d", st.study.estimate_d, "estimate D (default: D = 0 is known)");
  app.add_option("--rows", st.rows, "rows of Gamma_1 as OUTPUT:LAG list, e.g. 1:0,1:1,1:2 (default: automatic)");
  app.add_option("--selection", st.selection, "automatic row choice")
      ->check(CLI::IsMember({"output-major", "lag-major"}));
  app.add_option("--residuals", residuals, "residuals that give l: all, outputs or states")
      ->check(CLI::IsMember({"all", "outputs", "states"}));
  app.add_option("--norm", norm,
                 "|eps(t)|: entrywise, sample (Euclidean norm per sample) or equation (own l per equation)")
      ->check(CLI::IsMember({"entrywise", "sample", "equation"}));
  app.add_option("--level-factor", st.study.level.level_factor,
                 "domain dtheta' R dtheta <= F l^2 (2: the paper's J = eps'eps/2; 1: without the 1/2)")
      ->check(CLI::PositiveNumber);
  app.add_option("--fps-pui-runs", st.study.fps_pui_runs, "compute FPS PUIs by LP in the first K runs (-1: all)")
      ->check(CLI::Range(-1, 100000000));
  app.add_option("--noise", st.noise, "output noise of the simulation: gaussian (the paper) or uniform (bounded)")
      ->check(CLI::IsMember({"gaussian", "uniform"}));
  app.add_option("--noise-bound-sigmas", st.study.noise_bound_sigmas,
                 "Gaussian noise: the noise bound the guaranteed set assumes, in standard deviations")
      ->check(CLI::PositiveNumber);
  app.add_option("--guaranteed-pui-runs", st.study.guaranteed_pui_runs,
                 "PUIs of the guaranteed set by LP in the first K runs (-1: all; default 0: membership only, its LPs "
                 "with interval regressors cost 20 ms to seconds per run)")
      ->check(CLI::Range(-1, 100000000));
  app.add_flag("!--no-guaranteed", st.study.guaranteed, "skip the guaranteed set");
  cli.add_output_file("--json", st.json_path, "write results as JSON");
  app.add_option("--data", st.data, "CSV file with measured inputs and outputs (instead of the simulation)");
  app.add_option("--inputs", st.inputs, "input columns of --data (1-based numbers or header names)");
  app.add_option("--outputs", st.outputs, "output columns of --data");
  app.add_option("--order", st.order, "model order n with --data");
  if (const auto code = cli.parse(argc, argv)) return *code;
  st.study.level.residuals = residuals == "outputs" ? sets::ResidualSelection::outputs
                       : residuals == "states" ? sets::ResidualSelection::states
                                               : sets::ResidualSelection::all;
  st.study.level.norm = norm == "sample"     ? sets::ResidualNorm::sample_euclidean
                  : norm == "equation" ? sets::ResidualNorm::per_equation
                                       : sets::ResidualNorm::entrywise;
  return cli.run([&] {
    if (st.data.empty()) return monte_carlo(st);
    if (st.inputs.empty() || st.outputs.empty()) throw sets::InputError("--data needs --inputs, --outputs and --order");
    return real_data(st);
  });
}
