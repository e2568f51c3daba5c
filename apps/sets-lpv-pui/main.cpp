// sets-lpv-pui: guaranteed parameter uncertainty intervals of SISO LPV models when both the output
// and the scheduling signal are measured with bounded errors (Cerone & Regruto).
//
// Two modes:
//   - reproduction (default): Section IV's simulated example, Tables I-IV, our figures printed
//     beside the paper's (tables.cpp);
//   - real data: --data FILE.csv --u COL --y COL --r COL [--r COL ...] --delta-eta E --delta-eps E,
//     model structure from --model FILE.json or --a/--b flags (default: the paper's structure).

#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>

#include "common/cli.hpp"
#include "common/json_output.hpp"
#include "sets/core/error.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/data/recording.hpp"
#include "sets/methods/lpv_pui/lpv_pui.hpp"
#include "structure_flags.hpp"
#include "tables.hpp"

namespace {

using sets::LpvModelStructure;

int run_data(const std::string& path, const std::string& ucol, const std::string& ycol,
             const std::vector<std::string>& rcols, double delta_eta, double delta_eps, const LpvModelStructure& model,
             const sets::PuiOptions& options, const std::string& json_path) {
  const sets::Recording csv = sets::read_csv(path);
  sets::LpvMeasurements d;
  d.u = csv.matrix({ucol}, "--u").col(0);
  d.y = csv.matrix({ycol}, "--y").col(0);
  d.r = csv.matrix(rcols, "--r");
  d.delta_eta = Eigen::VectorXd::Constant(1, delta_eta);
  d.delta_eps = Eigen::MatrixXd::Constant(1, static_cast<Eigen::Index>(rcols.size()), delta_eps);

  const auto t0 = std::chrono::steady_clock::now();
  const sets::LpvPuiResult res = sets::lpv_pui(model, d, options);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const auto names = model.parameter_names();
  std::cout << "sets-lpv-pui: " << path << ", " << d.u.size() << " samples, " << res.regression.Phi.rows()
            << " regressions, " << names.size() << " parameters, |eta| <= " << delta_eta << ", |eps| <= " << delta_eps
            << '\n';
  if (res.pui.consistency.falsified == sets::Falsified::unknown)
    std::cerr << "sets-lpv-pui: note: " << res.pui.consistency.message() << '\n';
  if (res.pui.empty()) {
    std::cerr << "sets-lpv-pui: the data falsify the model: no parameter value satisfies all samples with these "
                 "bounds.\n  Conflicting samples (0-based index, file line: violation of the best compromise, in units "
                 "of y):";
    for (std::size_t i = 0; i < res.falsifying_times.size(); ++i)
      std::cerr << "\n    sample " << res.falsifying_times[i] << " (line " << res.falsifying_times[i] + 2
                << "): " << res.pui.consistency.conflict.violation[i];
    std::cerr << "\n  Check these samples, or widen --delta-eta / --delta-eps, or change the model structure.\n";
    return int(sets::exit_falsified);
  }
  std::cout << std::setprecision(6);
  std::cout << "  " << std::left << std::setw(22) << "parameter" << std::right << std::setw(14) << "PUI lower"
            << std::setw(14) << "PUI upper" << std::setw(14) << "central" << std::setw(14) << "half-width" << '\n';
  sets::app::Json js;
  js["parameters"] = sets::app::Json::array();
  for (std::size_t l = 0; l < names.size(); ++l) {
    const auto& I = res.pui.box[static_cast<Eigen::Index>(l)];
    const double c = res.pui.central[static_cast<Eigen::Index>(l)];
    std::cout << "  " << std::left << std::setw(22) << names[l] << std::right << std::setw(14) << I.lower() << std::setw(14)
              << I.upper() << std::setw(14) << c << std::setw(14) << (I.upper() - I.lower()) / 2 << '\n';
    js["parameters"].push_back({{"name", names[l]}, {"lower", I.lower()}, {"upper", I.upper()}, {"central", c}});
  }
  std::cout << "  orthants examined:";
  js["orthants"] = sets::app::Json::array();
  for (const auto& o : res.pui.orthants) {
    std::string signs;
    for (int s : o.signs) signs += s > 0 ? '+' : s < 0 ? '-' : '*';  // '*': free (exact regressors)
    std::cout << ' ' << (signs.empty() ? "(all)" : signs) << '=' << sets::to_string(o.status);
    js["orthants"].push_back({{"signs", signs}, {"status", sets::to_string(o.status)}});
  }
  std::cout << "\n  every PUI end certified by a safe bound: " << (res.pui.guaranteed ? "yes" : "NO") << ", LPs "
            << res.pui.lp_solves << ", time " << std::setprecision(3) << ms << " ms\n";
  js["guaranteed"] = res.pui.guaranteed;
  js["seconds"] = ms / 1e3;
  sets::app::write_json(json_path, js);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  sets::app::Cli cli("sets-lpv-pui", "sets-lpv-pui: guaranteed PUIs of LPV models with bounded output and scheduling noise "
               "(Cerone & Regruto). Without --data: reproduces the paper's Tables I-IV.");
  CLI::App& app = cli.app();
  std::string table = "all", orthants = "remark2", json_path, data_path, ucol, ycol, model_file;
  int runs = 20;
  std::uint64_t seed = 1;
  double delta_e = 0, delta_eta = -1, delta_eps = -1;
  unsigned threads = 1;
  std::vector<std::string> rcols, a_flags, b_flags;
  app.add_option("--table", table, "I, II, III, IV or all")->check(CLI::IsMember({"I", "II", "III", "IV", "all"}));
  app.add_option("--runs", runs, "Monte Carlo runs per setting")->check(CLI::Range(1, 100000));
  app.add_option("--seed", seed, "random seed");
  app.add_option("--delta-e", delta_e, "one noise bound for y and lambda instead of the four levels")
      ->check(CLI::PositiveNumber);
  app.add_option("--orthants", orthants, "remark2 (least-squares orthant, extended at zero bounds) or all")
      ->check(CLI::IsMember({"remark2", "all"}));
  cli.add_output_file("--json", json_path, "write the results as JSON");
  std::string regressor_noise = "both";
  app.add_option("--regressor-noise", regressor_noise,
                 "errors that widen the regressor boxes: both (the paper's method, guaranteed); scheduling, "
                 "output or none are NOT guaranteed diagnostics (docs/reproduction/cerone.md)")
      ->check(CLI::IsMember({"both", "scheduling", "output", "none"}));
  std::string coefficient_time = "current";
  app.add_option("--coefficient-time", coefficient_time,
                 "current: a_i, b_j at lambda_t (eq. 13, default); lagged: at lambda_{t-i}, lambda_{t-j} "
                 "(diagnostic reading, simulation and identification)")
      ->check(CLI::IsMember({"current", "lagged"}));
  app.add_option("--threads", threads, "worker threads (one FPS and LP per thread)")->check(CLI::Range(1u, 256u));
  app.add_option("--data", data_path, "CSV file with a header line: real-data mode");
  app.add_option("--u", ucol, "input column (name or 1-based number)");
  app.add_option("--y", ycol, "output column");
  app.add_option("--r", rcols, "scheduling column(s); repeat for alpha > 1");
  app.add_option("--delta-eta", delta_eta, "bound on the output error |eta|");
  app.add_option("--delta-eps", delta_eps, "bound on the scheduling error |eps|");
  app.add_option("--model", model_file, "model structure JSON {\"alpha\":1,\"a\":[[..]],\"b\":[[..]]}");
  app.add_option("--a", a_flags, "basis of a_i, comma-separated (repeat for i = 1..na), e.g. --a lambda --a 1,lambda^2");
  app.add_option("--b", b_flags, "basis of b_j (repeat for j = 0..nb; \"\" for none)");
  if (const auto code = cli.parse(argc, argv)) return *code;

  TableRuns tr{{}, runs, seed, delta_e, {}, threads, json_path};
  tr.options.orthants = orthants == "all" ? sets::OrthantSelection::all : sets::OrthantSelection::remark2;
  tr.regressor_errors = regressor_noise == "scheduling" ? sets::RegressorErrors::scheduling
                        : regressor_noise == "output"   ? sets::RegressorErrors::output
                        : regressor_noise == "none"     ? sets::RegressorErrors::none
                                                        : sets::RegressorErrors::both;
  tr.lagged_coefficients = coefficient_time == "lagged";
  return cli.run([&] {
    if (!data_path.empty()) {
      if (ucol.empty() || ycol.empty() || rcols.empty())
        throw sets::InputError("--data needs --u, --y and at least one --r column");
      if (delta_eta < 0 || delta_eps < 0 || !std::isfinite(delta_eta) || !std::isfinite(delta_eps))
        throw sets::InputError("--data needs --delta-eta and --delta-eps, finite and >= 0 (got " +
                               std::to_string(delta_eta) + ", " + std::to_string(delta_eps) + ")");
      const LpvModelStructure model = structure_from_flags(model_file, a_flags, b_flags, static_cast<int>(rcols.size()));
      return run_data(data_path, ucol, ycol, rcols, delta_eta, delta_eps, model, tr.options, json_path);
    }
    const std::map<std::string, int> index = {{"I", 0}, {"II", 1}, {"III", 2}, {"IV", 3}};
    tr.tables = table == "all" ? std::vector<int>{0, 1, 2, 3} : std::vector<int>{index.at(table)};
    return run_tables(tr);
  });
}
