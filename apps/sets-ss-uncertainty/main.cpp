// sets-ss-uncertainty: propagator subspace least squares and ellipsoidal uncertainty domains
// (Farah, Mercère, Poinot, van Wingerden), beside the guaranteed feasible parameter set.
//
// Without --data it runs the Monte Carlo study of Section V and prints Table I and the failure
// rates; with --data it identifies a model from a CSV file and prints both uncertainty domains.

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <random>
#include <thread>

#include "common/cli.hpp"
#include "common/json_output.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/data/recording.hpp"
#include "sets/methods/ss_uncertainty/ss_uncertainty.hpp"

namespace {

using nlohmann::json;

struct Settings {
  int runs = 1000;
  unsigned long long seed = 1;
  double snr_db = 20;
  int past = 20;
  int samples = 1000;
  int threads = 2;
  bool estimate_d = false;
  std::string rows;                  // "1:0,1:1,1:2" = output:lag (1-based output)
  std::string selection = "output-major";
  sets::LevelSetOptions level;
  int fps_pui_runs = -1;             // PUIs by LP in the first K runs (-1: all)
  std::string json_path;
  // real data
  std::string data, inputs, outputs;
  int order = 0;
};

std::vector<sets::ObservabilityRow> parse_rows(const std::string& spec, int ny) {
  std::vector<sets::ObservabilityRow> rows;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto colon = item.find(':');
    try {
      if (colon == std::string::npos) throw std::invalid_argument("no colon");
      std::size_t used1 = 0, used2 = 0;
      const int out = std::stoi(item.substr(0, colon), &used1);
      const int lag = std::stoi(item.substr(colon + 1), &used2);
      if (used1 != colon || used2 != item.size() - colon - 1) throw std::invalid_argument("trailing text");
      if (out < 1 || out > ny || lag < 0) throw std::invalid_argument("range");
      rows.push_back({lag, out - 1});
    } catch (const std::exception&) {
      throw sets::InputError("--rows: '" + item + "' is not OUTPUT:LAG with OUTPUT in 1.." + std::to_string(ny) +
                             " and LAG >= 0");
    }
  }
  return rows;
}

sets::RowSelection parse_selection(const std::string& s) {
  return s == "lag-major" ? sets::RowSelection::lag_major : sets::RowSelection::output_major;
}

// Writes the JSON completely or not at all.
void write_json(const std::string& path, const json& j) { sets::write_file_atomically(path, j.dump(2) + "\n"); }

// ------------------------------------------------------------------ Monte Carlo (Section V)

enum Verdict : unsigned char { inside = 0, outside = 1, undecided = 2 };
Verdict verdict(sets::BoolInterval b) {
  return b == sets::BoolInterval::yes ? inside : b == sets::BoolInterval::no ? outside : undecided;
}

struct RunResult {
  Eigen::VectorXd theta;
  double ell = 0;
  Verdict full = inside, fps_full = inside, fps_pui = inside;
  bool pui_done = false;
  Eigen::VectorXd pui_halfwidth, box_halfwidth;
  std::vector<Verdict> projection, slice;  // per pair
};

RunResult one_run(const Settings& st, const sets::StateSpaceModel& sys, const std::vector<sets::ObservabilityRow>& rows,
                  const Eigen::VectorXd& truth, const std::vector<std::pair<int, int>>& pairs, int run) {
  // One generator per run: the result does not depend on the number of threads.
  std::mt19937_64 rng(st.seed * 1000003ULL + static_cast<unsigned long long>(run));
  std::bernoulli_distribution coin(0.5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const int N = st.samples, nu = 2, ny = 2;
  Eigen::MatrixXd u(N, nu);
  for (int t = 0; t < N; ++t)
    for (int m = 0; m < nu; ++m) u(t, m) = coin(rng) ? 1.0 : -1.0;
  Eigen::MatrixXd y = sets::simulate(sys, u);
  for (int j = 0; j < ny; ++j) {
    // SNR per channel: variance of the noise-free output over the noise variance.
    const double var = (y.col(j).array() - y.col(j).mean()).square().mean();
    const double sigma = std::sqrt(var / std::pow(10.0, st.snr_db / 10.0));
    for (int t = 0; t < N; ++t) y(t, j) += sigma * gauss(rng);
  }
  sets::SsUncertaintyOptions o;
  o.identification.order = 3;
  o.identification.past = st.past;
  o.identification.estimate_d = st.estimate_d;
  o.identification.rows = rows;
  o.level = st.level;
  o.estimate_fps_pui = st.fps_pui_runs < 0 || run < st.fps_pui_runs;
  const auto result = sets::ss_uncertainty(u, y, o);
  const auto& dom = result.estimate_level_set;
  RunResult r;
  r.theta = dom.theta;
  r.ell = dom.ell;
  r.full = verdict(sets::contains(dom.ellipsoid, truth));
  for (const auto& [i, j] : pairs) {
    const auto v = sets::pair_view(dom.ellipsoid, i, j);
    const Eigen::Vector2d tp(truth[i], truth[j]);
    r.projection.push_back(verdict(sets::contains(v.projection, tp)));
    r.slice.push_back(v.slice ? verdict(sets::contains(*v.slice, tp)) : outside);
  }
  r.fps_full = verdict(result.estimate_fps.contains(truth));
  const auto box = sets::outer_box(dom.ellipsoid);
  r.box_halfwidth = sets::radius(box);
  if (result.estimate_fps_pui) {  // one LP, created and destroyed on this thread
    const auto& p = *result.estimate_fps_pui;
    r.pui_done = true;
    r.fps_pui = p.empty ? outside : (sets::contains(p.box, truth) ? inside : outside);
    r.pui_halfwidth = p.empty ? Eigen::VectorXd::Zero(truth.size()) : sets::radius(p.box);
  }
  return r;
}

int monte_carlo(const Settings& st) {
  const auto sys = sets::farah_example_system();
  const auto rows = st.rows.empty() ? sets::select_rows(sys.A, sys.C, parse_selection(st.selection))
                                    : parse_rows(st.rows, 2);
  const sets::CanonicalStructure structure(rows, 2, 2, st.estimate_d);
  const auto truth = structure.to_parameters(sets::canonical_form(sys, rows));
  const auto names = structure.parameter_names();
  const int m = static_cast<int>(truth.size());
  if (st.past < 3) throw sets::InputError("--past " + std::to_string(st.past) + " is smaller than the order 3");
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j) pairs.push_back({i, j});

  std::vector<RunResult> results(st.runs);
  std::atomic<int> next{0};
  std::mutex err_mutex;
  std::exception_ptr error;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();  // process CPU time (all threads)
  auto worker = [&] {
    for (int k = next++; k < st.runs; k = next++) {
      try {
        results[k] = one_run(st, sys, rows, truth, pairs, k);
      } catch (...) {
        std::lock_guard<std::mutex> lock(err_mutex);
        if (!error) error = std::current_exception();
        next = st.runs;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int k = 0; k < st.threads; ++k) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;

  // Table I: mean and standard deviation over the runs.
  Eigen::MatrixXd TH(m, st.runs);
  for (int k = 0; k < st.runs; ++k) TH.col(k) = results[k].theta;
  const Eigen::VectorXd mean = TH.rowwise().mean();
  Eigen::VectorXd sd(m);
  for (int i = 0; i < m; ++i)
    sd[i] = st.runs > 1 ? std::sqrt((TH.row(i).array() - mean[i]).square().sum() / (st.runs - 1)) : 0.0;

  auto rate = [&](auto get) {
    int out = 0, und = 0;
    for (const auto& r : results) {
      const Verdict v = get(r);
      out += v == outside;
      und += v == undecided;
    }
    return std::pair<double, int>(static_cast<double>(out) / st.runs, und);
  };
  const auto full = rate([](const RunResult& r) { return r.full; });
  const auto fps_full = rate([](const RunResult& r) { return r.fps_full; });
  int pui_runs = 0, pui_out = 0;
  Eigen::VectorXd pui_hw = Eigen::VectorXd::Zero(m), box_hw = Eigen::VectorXd::Zero(m);
  for (const auto& r : results) {
    box_hw += r.box_halfwidth / st.runs;
    if (r.pui_done) {
      ++pui_runs;
      pui_out += r.fps_pui == outside;
      pui_hw += r.pui_halfwidth;
    }
  }
  if (pui_runs) pui_hw /= pui_runs;
  double ell_mean = 0;
  for (const auto& r : results) ell_mean += r.ell / st.runs;

  std::cout << "sets-ss-uncertainty: Farah et al., Section V (3 states, 2 inputs, 2 outputs, D "
            << (st.estimate_d ? "estimated" : "= 0 known") << ")\n"
            << "  " << st.runs << " runs, N = " << st.samples << ", random binary input, white Gaussian output noise at "
            << st.snr_db << " dB SNR per channel, p = " << st.past << ", seed " << st.seed << "\n  rows of Gamma_1:";
  for (const auto& r : rows) std::cout << ' ' << sets::to_string(r);
  std::cout << "\n  residuals for l: " << sets::to_string(st.level.residuals) << ", "
            << sets::to_string(st.level.norm) << ", level dtheta' R dtheta <= " << st.level.level_factor
            << " l^2; mean l = " << std::setprecision(4) << ell_mean << "\n\n";
  std::cout << "Table I  (true value from the printed A, B, C; mean and std over the runs)\n"
            << "  param         true          mean           std   |bias|/std\n";
  json jp = json::array();
  for (int i = 0; i < m; ++i) {
    const double ratio = sd[i] > 0 ? std::abs(mean[i] - truth[i]) / sd[i] : 0.0;
    std::cout << "  " << std::left << std::setw(8) << names[i] << std::right << std::fixed << std::setprecision(4)
              << std::setw(11) << truth[i] << std::setw(14) << mean[i] << std::scientific << std::setprecision(3)
              << std::setw(14) << sd[i] << std::fixed << std::setprecision(3) << std::setw(12) << ratio << '\n';
    jp.push_back({{"name", names[i]}, {"true", truth[i]}, {"mean", mean[i]}, {"std", sd[i]}});
  }
  std::cout << "\nFailure rates (share of runs whose true parameters lie outside the domain)\n"
            << "  pair                  projection     slice\n";
  json jpairs = json::array();
  // The paper's pairs first, then every other pair.
  std::vector<int> order;
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if ((names[pairs[k].first] == "-a0" && names[pairs[k].second] == "-a1") ||
        (names[pairs[k].first] == "-a2" && names[pairs[k].second] == "b0^1"))
      order.push_back(static_cast<int>(k));
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (std::find(order.begin(), order.end(), static_cast<int>(k)) == order.end()) order.push_back(static_cast<int>(k));
  int undecided_pairs = 0;
  for (int k : order) {
    const auto pr = rate([k](const RunResult& r) { return r.projection[k]; });
    const auto sl = rate([k](const RunResult& r) { return r.slice[k]; });
    undecided_pairs += pr.second + sl.second;
    const std::string label = "(" + names[pairs[k].first] + ", " + names[pairs[k].second] + ")";
    std::cout << "  " << std::left << std::setw(20) << label << std::right << std::fixed << std::setprecision(1)
              << std::setw(10) << 100 * pr.first << " %" << std::setw(8) << 100 * sl.first << " %\n";
    jpairs.push_back({{"pair", {names[pairs[k].first], names[pairs[k].second]}},
                      {"projection", pr.first},
                      {"slice", sl.first}});
  }
  std::cout << "  full vector (ellipsoid):   " << std::setprecision(1) << 100 * full.first << " %\n"
            << "  full vector (FPS |eps| <= l, guaranteed alternative): " << 100 * fps_full.first << " %\n";
  if (pui_runs)
    std::cout << "  FPS PUI box (LP, " << pui_runs << " runs): " << 100.0 * pui_out / pui_runs << " %\n";
  if (full.second + fps_full.second + undecided_pairs)
    std::cout << "  (undecided by rounding, counted as inside: " << full.second + fps_full.second + undecided_pairs
              << ")\n";
  std::cout << "\nMean half-widths: ellipsoid outer box vs FPS PUIs\n";
  for (int i = 0; i < m; ++i) {
    std::cout << "  " << std::left << std::setw(8) << names[i] << std::right << std::scientific << std::setprecision(3)
              << std::setw(12) << box_hw[i];
    if (pui_runs) std::cout << std::setw(12) << pui_hw[i];
    std::cout << '\n';
  }
  std::cout << std::fixed << std::setprecision(2) << "\nTiming: " << seconds << " s for " << st.runs << " runs on "
            << st.threads << " threads" << (pui_runs ? " (with " + std::to_string(pui_runs) + " PUI computations)" : "")
            << ", " << cpu_seconds << " s CPU\n";

  if (!st.json_path.empty()) {
    json j;
    j["runs"] = st.runs;
    j["parameters"] = jp;
    j["failure_rates"] = {{"pairs", jpairs}, {"full", full.first}, {"fps_full", fps_full.first}};
    if (pui_runs) j["failure_rates"]["fps_pui_box"] = static_cast<double>(pui_out) / pui_runs;
    j["seconds"] = seconds;
    j["cpu_seconds"] = cpu_seconds;
    j["settings"] = {{"seed", st.seed},          {"snr_db", st.snr_db},
                     {"past", st.past},          {"samples", st.samples},
                     {"threads", st.threads},    {"estimate_d", st.estimate_d},
                     {"residuals", sets::to_string(st.level.residuals)},
                     {"norm", sets::to_string(st.level.norm)},
                     {"level_factor", st.level.level_factor},
                     {"mean_ell", ell_mean},     {"pui_runs", pui_runs}};
    write_json(st.json_path, j);
  }
  return 0;
}

// ------------------------------------------------------------------ real data

int real_data(const Settings& st) {
  const sets::Recording table = sets::read_csv(st.data);
  const Eigen::MatrixXd u = table.matrix(sets::app::split_list(st.inputs), "--inputs");
  const Eigen::MatrixXd y = table.matrix(sets::app::split_list(st.outputs), "--outputs");
  if (st.order < 1) throw sets::InputError("--order: give the model order n >= 1 with --data");
  sets::SsUncertaintyOptions o;
  o.identification.order = st.order;
  o.identification.past = st.past;
  o.identification.estimate_d = st.estimate_d;
  o.identification.selection = parse_selection(st.selection);
  if (!st.rows.empty()) o.identification.rows = parse_rows(st.rows, static_cast<int>(y.cols()));
  o.level = st.level;
  const auto t0 = std::chrono::steady_clock::now();
  const auto result = sets::ss_uncertainty(u, y, o);
  const auto& id = result.identification;
  const auto& dom = result.estimate_level_set;
  const auto& p = *result.estimate_fps_pui;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto names = id.structure.parameter_names();
  const auto box = sets::outer_box(dom.ellipsoid);

  std::cout << "sets-ss-uncertainty: " << st.data << ", " << u.rows() << " samples, " << u.cols() << " inputs, "
            << y.cols() << " outputs, order " << st.order << ", p = " << st.past << "\n  rows of Gamma_1:";
  for (const auto& r : id.rows) std::cout << ' ' << sets::to_string(r);
  std::cout << "\n  l = " << dom.ell << " (residuals " << sets::to_string(st.level.residuals) << ", "
            << sets::to_string(st.level.norm) << "), J_min = " << dom.j_min << ", J_D = " << dom.j_d << "\n\n";
  if (p.empty) {
    std::cout << "The feasible parameter set with |eps| <= l is empty: " << p.falsification.message() << '\n';
    return int(sets::exit_falsified);
  }
  std::cout << "  param        estimate     ellipsoid box (not guaranteed)       FPS PUI (holds only if |eps| <= l at the truth)\n";
  json jp = json::array();
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
    json j;
    j["data"] = st.data;
    j["parameters"] = jp;
    j["ell"] = dom.ell;
    j["j_min"] = dom.j_min;
    j["pui_guaranteed"] = p.guaranteed;
    j["seconds"] = seconds;
    write_json(st.json_path, j);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  sets::app::Cli cli("sets-ss-uncertainty", "sets-ss-uncertainty: propagator subspace LS with ellipsoidal uncertainty domains (Farah et al.)");
  CLI::App& app = cli.app();
  Settings st;
  st.threads = std::max(1u, std::thread::hardware_concurrency());
  std::string residuals = "all", norm = "entrywise";
  app.add_option("--runs", st.runs, "Monte Carlo runs")->check(CLI::Range(1, 10000000));
  app.add_option("--seed", st.seed, "random seed");
  app.add_option("--snr-db", st.snr_db, "signal-to-noise ratio per output channel, dB");
  app.add_option("--past,-p", st.past, "past horizon p (>= order)")->check(CLI::Range(1, 100000));
  app.add_option("--samples,-N", st.samples, "samples per run")->check(CLI::Range(2, 100000000));
  app.add_option("--threads", st.threads, "worker threads (one LP per thread)")->check(CLI::Range(1, 1024));
  app.add_flag("--estimate-d", st.estimate_d, "estimate D (default: D = 0 is known)");
  app.add_option("--rows", st.rows, "rows of Gamma_1 as OUTPUT:LAG list, e.g. 1:0,1:1,1:2 (default: automatic)");
  app.add_option("--selection", st.selection, "automatic row choice")
      ->check(CLI::IsMember({"output-major", "lag-major"}));
  app.add_option("--residuals", residuals, "residuals that give l: all, outputs or states")
      ->check(CLI::IsMember({"all", "outputs", "states"}));
  app.add_option("--norm", norm,
                 "|eps(t)|: entrywise, sample (Euclidean norm per sample) or equation (own l per equation)")
      ->check(CLI::IsMember({"entrywise", "sample", "equation"}));
  app.add_option("--level-factor", st.level.level_factor,
                 "domain dtheta' R dtheta <= F l^2 (2: the paper's J = eps'eps/2; 1: without the 1/2)")
      ->check(CLI::PositiveNumber);
  app.add_option("--fps-pui-runs", st.fps_pui_runs, "compute FPS PUIs by LP in the first K runs (-1: all)")
      ->check(CLI::Range(-1, 100000000));
  cli.add_output_file("--json", st.json_path, "write results as JSON");
  app.add_option("--data", st.data, "CSV file with measured inputs and outputs (instead of the simulation)");
  app.add_option("--inputs", st.inputs, "input columns of --data (1-based numbers or header names)");
  app.add_option("--outputs", st.outputs, "output columns of --data");
  app.add_option("--order", st.order, "model order n with --data");
  if (const auto code = cli.parse(argc, argv)) return *code;
  st.level.residuals = residuals == "outputs" ? sets::ResidualSelection::outputs
                       : residuals == "states" ? sets::ResidualSelection::states
                                               : sets::ResidualSelection::all;
  st.level.norm = norm == "sample"     ? sets::ResidualNorm::sample_euclidean
                  : norm == "equation" ? sets::ResidualNorm::per_equation
                                       : sets::ResidualNorm::entrywise;
  try {
    if (!st.data.empty()) {
      if (st.inputs.empty() || st.outputs.empty())
        throw sets::InputError("--data needs --inputs, --outputs and --order");
      return real_data(st);
    }
    return monte_carlo(st);
  } catch (const std::exception& e) {
    return sets::report_failure("sets-ss-uncertainty", e);
  }
}
