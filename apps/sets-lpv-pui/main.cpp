// sets-lpv-pui: guaranteed parameter uncertainty intervals of SISO LPV models when both the output
// and the scheduling signal are measured with bounded errors (Cerone & Regruto).
//
// Two modes:
//   - reproduction (default): Section IV's simulated example, Tables I–IV, our figures printed
//     beside the paper's;
//   - real data: --data FILE.csv --u COL --y COL --r COL [--r COL ...] --delta-eta E --delta-eps E,
//     model structure from --model FILE.json or --a/--b flags (default: the paper's structure).
//
// Exit codes: 0 success, 1 bad input or usage, 2 the data falsify the model, 3 numerical failure.

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <thread>

#include "common/cli.hpp"
#include "common/json_output.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/data/recording.hpp"
#include "sets/methods/lpv_pui/lpv_model.hpp"

namespace {

using sets::LpvMeasurements;
using sets::LpvModelStructure;

// ---------------------------------------------------------------- the paper's Tables I–IV

struct PaperLevel {
  double snr_w, snr_lambda;
  double theta_c[6];
  double delta_theta[6];
};

struct TableSpec {
  const char* name;
  bool uniform;  // lambda uniform in [-1, 1]; otherwise sin(0.1 t)
  int N;
  double delta_e[4];  // the issue's noise bounds per level (they give the tables' SNRs to ~1 dB)
  PaperLevel paper[4];
};

// Transcribed from the paper's Tables I–IV (Section IV). Table II's stray "0.2" in the true-value
// column of level 2 is a misprint and not part of theta_c.
const TableSpec kTables[4] = {
    {"I", true, 100, {7.5e-4, 3.75e-3, 7.9e-3, 3.8e-2},
     {{58.9, 61.3, {0.500, -0.200, 0.299, 0.100, 1.000, 0.201}, {1.6e-3, 2.7e-3, 3.8e-3, 9.4e-4, 2.5e-3, 2.8e-3}},
      {44.2, 48.1, {0.501, -0.197, 0.295, 0.102, 0.999, 0.198}, {8.9e-3, 1.5e-2, 2.0e-2, 6.4e-3, 1.1e-2, 1.3e-2}},
      {38.6, 40.8, {0.501, -0.185, 0.278, 0.100, 1.001, 0.202}, {2.2e-2, 3.5e-2, 4.8e-2, 1.1e-2, 2.8e-2, 3.3e-2}},
      {24.5, 27.5, {0.513, -0.188, 0.268, 0.106, 1.020, 0.178}, {8.1e-2, 1.5e-1, 1.8e-1, 5.0e-2, 1.1e-1, 1.1e-1}}}},
    {"II", true, 1000, {9.7e-4, 4.8e-3, 9.6e-3, 4.8e-2},
     {{56.0, 60.0, {0.500, -0.200, 0.300, 0.100, 1.000, 0.200}, {1.1e-3, 6.6e-4, 1.3e-3, 4.3e-4, 1.2e-3, 1.2e-3}},
      {41.9, 46.2, {0.502, -0.201, 0.301, 0.100, 0.999, 0.199}, {8.5e-3, 4.5e-3, 9.2e-3, 2.5e-3, 6.7e-3, 6.7e-3}},
      {36.0, 40.2, {0.498, -0.202, 0.306, 0.098, 0.999, 0.203}, {1.2e-2, 6.5e-3, 1.1e-2, 2.6e-3, 1.1e-2, 1.1e-2}},
      {22.1, 26.1, {0.521, -0.192, 0.281, 0.093, 0.996, 0.218}, {7.6e-2, 3.1e-2, 7.7e-2, 2.4e-2, 7.9e-2, 8.7e-2}}}},
    {"III", false, 100, {1.0e-3, 5.0e-3, 1.06e-2, 5.2e-2},
     {{57.8, 61.3, {0.499, -0.200, 0.299, 0.100, 1.000, 0.200}, {1.9e-3, 3.4e-3, 5.0e-3, 1.3e-3, 2.2e-3, 2.4e-3}},
      {43.1, 48.1, {0.499, -0.204, 0.304, 0.101, 1.001, 0.197}, {1.2e-2, 1.7e-2, 2.6e-2, 4.3e-3, 1.4e-2, 1.6e-2}},
      {37.5, 40.8, {0.498, -0.199, 0.292, 0.101, 1.003, 0.198}, {2.5e-2, 3.5e-2, 5.8e-2, 1.0e-2, 2.8e-2, 3.2e-2}},
      {23.3, 27.5, {0.504, -0.186, 0.244, 0.096, 1.003, 0.229}, {1.1e-1, 1.4e-1, 2.0e-1, 5.5e-2, 1.1e-1, 1.1e-1}}}},
    {"IV", false, 1000, {1.0e-3, 5.0e-3, 1.0e-2, 5.0e-2},
     {{57.4, 61.9, {0.500, -0.200, 0.301, 0.100, 1.000, 0.200}, {2.0e-4, 2.9e-4, 3.1e-4, 7.0e-5, 3.4e-4, 3.6e-4}},
      {43.5, 48.0, {0.503, -0.201, 0.300, 0.099, 1.000, 0.201}, {7.5e-4, 6.0e-4, 7.6e-4, 1.0e-4, 1.9e-3, 7.8e-4}},
      {37.7, 41.8, {0.496, -0.199, 0.296, 0.101, 0.997, 0.202}, {6.5e-3, 1.3e-2, 1.4e-2, 5.3e-3, 9.1e-3, 1.2e-2}},
      {23.5, 28.0, {0.492, -0.159, 0.247, 0.114, 1.002, 0.209}, {3.0e-2, 4.9e-2, 5.3e-2, 1.4e-2, 5.0e-2, 5.6e-2}}}},
};

const double kTheta[6] = {0.5, -0.2, 0.3, 0.1, 1.0, 0.2};

// ---------------------------------------------------------------- one simulated run

struct RunResult {
  double snr_w = 0, snr_lambda = 0;
  Eigen::VectorXd theta_c, delta_theta;
  bool covered = false, empty = false, guaranteed = false;
  int orthants = 0, feasible_orthants = 0, lps = 0;
  double seconds = 0;
};

struct Setting {
  int table;      // index into kTables
  int level;      // 1..4, or 0 for a custom --delta-e
  double delta_e;
};

// Which measurement errors widen the regressor boxes (eqs. 18–26). `both` is the paper's method
// and the only guaranteed choice; the others are diagnostics for docs/reproduction/cerone.md
// (e.g. `scheduling` is eq. 25 read literally: min/max over eps only, w_{t-i} taken as y_{t-i}).
enum class RegressorNoise { both, scheduling, output, none };
RegressorNoise g_regressor_noise = RegressorNoise::both;
// Diagnostic reading of eqs. (2)-(4): coefficient i taken at lambda_{t-i} (the shift acting on the
// coefficient too) instead of at lambda_t (eq. 13, Section IV's A(q^-1) = 1 + (0.5 lambda_t) q^-1 ...),
// in both the simulation and the identification. Done with alpha = 2: [lambda_{t-1}, lambda_{t-2}].
bool g_lagged_coefficients = false;

LpvModelStructure lagged_example() {
  using sets::BasisFunction;
  LpvModelStructure m;
  m.alpha = 2;
  m.a = {{BasisFunction::power(0, 1)}, {BasisFunction(), BasisFunction::power(1, 2)}};
  m.b = {{}, {BasisFunction()}, {BasisFunction::power(1, 1), BasisFunction::power(1, 2)}};
  return m;
}
Eigen::MatrixXd lagged(const Eigen::VectorXd& x) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(x.size(), 2);
  for (Eigen::Index t = 1; t < x.size(); ++t) m(t, 0) = x[t - 1];
  for (Eigen::Index t = 2; t < x.size(); ++t) m(t, 1) = x[t - 2];
  return m;
}

RunResult simulate_and_bound(const Setting& s, int run, std::uint64_t seed, const sets::PuiOptions& options) {
  const TableSpec& spec = kTables[s.table];
  const LpvModelStructure model =
      g_lagged_coefficients ? lagged_example() : LpvModelStructure::cerone_regruto_example();
  const Eigen::Map<const Eigen::VectorXd> theta(kTheta, 6);
  std::seed_seq seq{seed, static_cast<std::uint64_t>(s.table), static_cast<std::uint64_t>(s.level),
                    static_cast<std::uint64_t>(run)};
  std::mt19937_64 rng(seq);
  std::uniform_real_distribution<double> U(-1, 1);
  const int T = spec.N + 2;  // zero initial conditions; regressions t = 3..N+2 (1-based)
  Eigen::VectorXd u(T);
  Eigen::MatrixXd lambda(T, 1);
  for (int t = 0; t < T; ++t) u[t] = U(rng);
  for (int t = 0; t < T; ++t) lambda(t, 0) = spec.uniform ? U(rng) : std::sin(0.1 * (t + 1));
  const Eigen::VectorXd w =
      sets::simulate_lpv(model, theta, u, g_lagged_coefficients ? lagged(lambda.col(0)) : lambda);
  Eigen::VectorXd eta(T), eps(T);
  for (int t = 0; t < T; ++t) eta[t] = s.delta_e * U(rng);
  for (int t = 0; t < T; ++t) eps[t] = s.delta_e * U(rng);
  LpvMeasurements d;
  d.u = u;
  d.y = w + eta;
  d.r = lambda + eps;
  d.delta_eta = Eigen::VectorXd::Constant(1, s.delta_e);
  d.delta_eps = Eigen::MatrixXd::Constant(1, 1, s.delta_e);
  if (g_lagged_coefficients) {
    d.r = lagged(d.r.col(0));
    d.delta_eps = Eigen::MatrixXd::Constant(1, 2, s.delta_e);
  }

  RunResult r;
  // SNRs (eqs. 43–44) over the N regression samples.
  const int n0 = model.first_regression();
  r.snr_w = 10 * std::log10(w.tail(T - n0).squaredNorm() / eta.tail(T - n0).squaredNorm());
  r.snr_lambda = 10 * std::log10(lambda.col(0).tail(T - n0).squaredNorm() / eps.tail(T - n0).squaredNorm());
  const auto t0 = std::chrono::steady_clock::now();
  sets::LpvPuiResult res;
  if (g_regressor_noise == RegressorNoise::both) {
    res = sets::lpv_pui(model, d, options);
  } else {
    // Diagnostic: regressor boxes without one or both error sources; the output strip keeps Delta E.
    LpvMeasurements dr = d;
    if (g_regressor_noise != RegressorNoise::output) dr.delta_eta.setZero();
    if (g_regressor_noise != RegressorNoise::scheduling) dr.delta_eps.setZero();
    res.regression = sets::lpv_regression(model, dr);
    for (Eigen::Index row = 0; row < res.regression.Y.size(); ++row)
      res.regression.Y[row] = sets::interval_around(d.y[res.regression.time[static_cast<std::size_t>(row)]], s.delta_e);
    res.pui = sets::pui(sets::FeasibleParameterSet::from_interval_data(res.regression.Phi, res.regression.Y), options);
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.empty = res.pui.empty;
  r.guaranteed = res.pui.guaranteed;
  r.lps = res.pui.lp_solves;
  r.orthants = static_cast<int>(res.pui.orthants.size());
  for (const auto& o : res.pui.orthants) r.feasible_orthants += o.status == sets::OrthantStatus::feasible;
  if (!r.empty) {
    r.theta_c = res.pui.central;
    r.delta_theta.resize(6);
    for (int l = 0; l < 6; ++l) r.delta_theta[l] = (res.pui.box[l].upper() - res.pui.box[l].lower()) / 2;
    r.covered = sets::contains(res.pui.box, theta);
  }
  return r;
}

struct Stats {
  double mean = 0, std = 0;
};
Stats stats(const std::vector<double>& v) {
  Stats s;
  if (v.empty()) return s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  for (double x : v) s.std += (x - s.mean) * (x - s.mean);
  s.std = v.size() > 1 ? std::sqrt(s.std / static_cast<double>(v.size() - 1)) : 0.0;
  return s;
}


std::string sci(double x, int digits = 1) {
  std::ostringstream os;
  os << std::scientific << std::setprecision(digits) << x;
  return os.str();
}
std::string fix(double x, int digits = 3) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << x;
  return os.str();
}

int run_tables(const std::vector<int>& tables, int runs, std::uint64_t seed, double delta_e_override,
               const sets::PuiOptions& options, unsigned threads, const std::string& json_path) {
  std::vector<Setting> settings;
  for (int t : tables) {
    if (delta_e_override > 0)
      settings.push_back({t, 0, delta_e_override});
    else
      for (int lv = 1; lv <= 4; ++lv) settings.push_back({t, lv, kTables[t].delta_e[lv - 1]});
  }
  // One job per (setting, run); each job builds its own FPS and LPs on its own thread.
  const std::size_t jobs = settings.size() * static_cast<std::size_t>(runs);
  std::vector<RunResult> results(jobs);
  std::vector<std::string> errors(jobs);
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t k; (k = next++) < jobs;) {
      try {
        results[k] = simulate_and_bound(settings[k / runs], static_cast<int>(k % runs), seed, options);
      } catch (const std::exception& e) {
        errors[k] = e.what();
      }
    }
  };
  const auto wall0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (unsigned i = 0; i < std::max(1u, threads); ++i) pool.emplace_back(worker);
  for (auto& th : pool) th.join();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  for (std::size_t k = 0; k < jobs; ++k)
    if (!errors[k].empty()) {
      std::cerr << "sets-lpv-pui: run " << k % runs << " of table " << kTables[settings[k / runs].table].name
                << " failed: " << errors[k] << '\n';
      return int(sets::exit_numerical);
    }

  const LpvModelStructure model = LpvModelStructure::cerone_regruto_example();
  const auto names = model.parameter_names();
  nlohmann::json out;
  out["settings"] = nlohmann::json::array();
  bool all_covered = true;
  int last_table = -1;
  for (std::size_t si = 0; si < settings.size(); ++si) {
    const Setting& s = settings[si];
    const TableSpec& spec = kTables[s.table];
    const PaperLevel* paper = s.level > 0 ? &spec.paper[s.level - 1] : nullptr;
    std::vector<double> snr_w, snr_l, seconds;
    std::vector<std::vector<double>> tc(6), dt(6);
    int covered = 0, empty = 0, guaranteed = 0, orthants = 0, feasible_orthants = 0;
    for (int run = 0; run < runs; ++run) {
      const RunResult& r = results[si * static_cast<std::size_t>(runs) + static_cast<std::size_t>(run)];
      snr_w.push_back(r.snr_w);
      snr_l.push_back(r.snr_lambda);
      seconds.push_back(r.seconds);
      covered += r.covered;
      empty += r.empty;
      guaranteed += r.guaranteed;
      orthants += r.orthants;
      feasible_orthants += r.feasible_orthants;
      if (r.empty) continue;
      for (int l = 0; l < 6; ++l) {
        tc[l].push_back(r.theta_c[l]);
        dt[l].push_back(r.delta_theta[l]);
      }
    }
    all_covered = all_covered && covered == runs;
    if (s.table != last_table) {
      std::cout << "\nTable " << spec.name << ": lambda " << (spec.uniform ? "uniform in [-1, 1]" : "= sin(0.1 t)")
                << ", N = " << spec.N << ", " << runs << " runs, "
                << (options.orthants == sets::OrthantSelection::all ? "all orthants" : "Remark-2 orthants")
                << (g_regressor_noise == RegressorNoise::both ? ""
                                                             : ", DIAGNOSTIC regressor boxes (not guaranteed)")
                << '\n';
      last_table = s.table;
    }
    const Stats sw = stats(snr_w), sl = stats(snr_l);
    std::cout << "  level " << (s.level > 0 ? std::to_string(s.level) : std::string("custom")) << ": Delta E = "
              << sci(s.delta_e, 2) << "   SNR_w " << fix(sw.mean, 1) << " dB (paper "
              << (paper ? fix(paper->snr_w, 1) : "-") << ")   SNR_lambda " << fix(sl.mean, 1) << " dB (paper "
              << (paper ? fix(paper->snr_lambda, 1) : "-") << ")   true theta in all PUIs: " << covered << "/" << runs
              << (empty ? "   EMPTY FPS in " + std::to_string(empty) + " runs" : "") << '\n';
    std::cout << "    " << std::left << std::setw(18) << "parameter" << std::right << std::setw(6) << "true"
              << std::setw(22) << "theta_c ours" << std::setw(9) << "paper" << std::setw(24) << "Delta theta ours"
              << std::setw(10) << "paper" << '\n';
    nlohmann::json js;
    js["table"] = spec.name;
    js["level"] = s.level;
    js["N"] = spec.N;
    js["lambda"] = spec.uniform ? "uniform" : "sin";
    js["delta_e"] = s.delta_e;
    js["runs"] = runs;
    js["coefficient_time"] = g_lagged_coefficients ? "lagged" : "current";
    js["regressor_noise"] = g_regressor_noise == RegressorNoise::both         ? "both"
                            : g_regressor_noise == RegressorNoise::scheduling ? "scheduling"
                            : g_regressor_noise == RegressorNoise::output     ? "output"
                                                                              : "none";
    js["snr_w"] = sw.mean;
    js["snr_lambda"] = sl.mean;
    js["theta_true"] = std::vector<double>(kTheta, kTheta + 6);
    std::vector<double> tcm, tcs, dtm, dts;
    for (int l = 0; l < 6; ++l) {
      const Stats a = stats(tc[l]), b = stats(dt[l]);
      tcm.push_back(a.mean);
      tcs.push_back(a.std);
      dtm.push_back(b.mean);
      dts.push_back(b.std);
      std::cout << "    " << std::left << std::setw(18) << names[l] << std::right << std::setw(6) << fix(kTheta[l], 1)
                << std::setw(22) << (fix(a.mean, 4) + " +- " + fix(a.std, 4)) << std::setw(9)
                << (paper ? fix(paper->theta_c[l]) : "-") << std::setw(24)
                << (sci(b.mean) + " +- " + sci(b.std)) << std::setw(10)
                << (paper ? sci(paper->delta_theta[l]) : "-") << '\n';
    }
    js["theta_c_mean"] = tcm;
    js["theta_c_std"] = tcs;
    js["delta_theta_mean"] = dtm;
    js["delta_theta_std"] = dts;
    js["coverage"] = static_cast<double>(covered) / runs;
    js["guaranteed_share"] = static_cast<double>(guaranteed) / runs;
    js["empty_runs"] = empty;
    js["orthants_mean"] = static_cast<double>(orthants) / runs;
    js["feasible_orthants_mean"] = static_cast<double>(feasible_orthants) / runs;
    double total = 0;
    for (double x : seconds) total += x;
    js["seconds"] = total;
    if (paper) {
      js["paper"] = {{"snr_w", paper->snr_w},
                     {"snr_lambda", paper->snr_lambda},
                     {"theta_c", std::vector<double>(paper->theta_c, paper->theta_c + 6)},
                     {"delta_theta", std::vector<double>(paper->delta_theta, paper->delta_theta + 6)}};
    }
    std::cout << "    orthants examined per run " << fix(static_cast<double>(orthants) / runs, 2) << " (feasible "
              << fix(static_cast<double>(feasible_orthants) / runs, 2) << "), every end certified in " << guaranteed
              << "/" << runs << " runs, bounding time " << fix(1e3 * total / runs, 1) << " ms per run\n";
    out["settings"].push_back(js);
  }
  std::cout << "\n" << (all_covered ? "coverage: the true theta was inside every PUI in every run (100%)"
                                    : "WARNING: the true theta was outside a PUI in some run")
            << "; wall time " << fix(wall, 1) << " s on " << std::max(1u, threads) << " thread(s)\n";
  if (!json_path.empty()) sets::write_file_atomically(json_path, out.dump(2) + "\n");
  return 0;
}

// ---------------------------------------------------------------- real data

LpvModelStructure structure_from_flags(const std::string& model_file, const std::vector<std::string>& a_flags,
                                       const std::vector<std::string>& b_flags, int alpha) {
  if (!model_file.empty()) {
    if (!a_flags.empty() || !b_flags.empty())
      throw sets::InputError("give the model structure either by --model or by --a/--b, not both");
    std::ifstream in(model_file);
    if (!in) throw sets::InputError("cannot open model file '" + model_file + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    LpvModelStructure m = sets::parse_lpv_structure_json(ss.str(), model_file);
    if (m.alpha != alpha)
      throw sets::InputError(model_file + ": alpha = " + std::to_string(m.alpha) + " but " + std::to_string(alpha) +
                             " scheduling columns were given with --r");
    return m;
  }
  if (a_flags.empty() && b_flags.empty()) {
    if (alpha != 1) throw sets::InputError("with several --r columns give the model structure (--model or --a/--b)");
    return LpvModelStructure::cerone_regruto_example();
  }
  if (b_flags.empty()) throw sets::InputError("--b is required with --a (one --b per b_j, j = 0..nb; \"\" for none)");
  LpvModelStructure m;
  m.alpha = alpha;
  auto parse_list = [&](const std::string& text, const std::string& flag) {
    std::vector<sets::BasisFunction> basis;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
      if (item.find_first_not_of(" \t") == std::string::npos) continue;
      try {
        basis.push_back(sets::parse_basis_function(item, alpha));
      } catch (const sets::InputError& e) {
        throw sets::InputError(flag + " '" + text + "': " + e.what());
      }
    }
    return basis;
  };
  for (std::size_t i = 0; i < a_flags.size(); ++i) m.a.push_back(parse_list(a_flags[i], "--a #" + std::to_string(i + 1)));
  for (std::size_t j = 0; j < b_flags.size(); ++j) m.b.push_back(parse_list(b_flags[j], "--b #" + std::to_string(j + 1)));
  m.validate();
  return m;
}

int run_data(const std::string& path, const std::string& ucol, const std::string& ycol,
             const std::vector<std::string>& rcols, double delta_eta, double delta_eps, const LpvModelStructure& model,
             const sets::PuiOptions& options, const std::string& json_path) {
  const sets::Recording csv = sets::read_csv(path);
  LpvMeasurements d;
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
  if (res.pui.empty) {
    std::cerr << "sets-lpv-pui: the data falsify the model: no parameter value satisfies all samples with these "
                 "bounds.\n  Conflicting samples (0-based index, file line: violation of the best compromise, in units "
                 "of y):";
    for (std::size_t i = 0; i < res.falsifying_times.size(); ++i)
      std::cerr << "\n    sample " << res.falsifying_times[i] << " (line " << res.falsifying_times[i] + 2
                << "): " << res.pui.falsification.violation[i];
    std::cerr << "\n  Check these samples, or widen --delta-eta / --delta-eps, or change the model structure.\n";
    return int(sets::exit_falsified);
  }
  std::cout << std::setprecision(6);
  std::cout << "  " << std::left << std::setw(22) << "parameter" << std::right << std::setw(14) << "PUI lower"
            << std::setw(14) << "PUI upper" << std::setw(14) << "central" << std::setw(14) << "half-width" << '\n';
  nlohmann::json js;
  js["parameters"] = nlohmann::json::array();
  for (std::size_t l = 0; l < names.size(); ++l) {
    const auto& I = res.pui.box[static_cast<Eigen::Index>(l)];
    const double c = res.pui.central[static_cast<Eigen::Index>(l)];
    std::cout << "  " << std::left << std::setw(22) << names[l] << std::right << std::setw(14) << I.lower() << std::setw(14)
              << I.upper() << std::setw(14) << c << std::setw(14) << (I.upper() - I.lower()) / 2 << '\n';
    js["parameters"].push_back({{"name", names[l]}, {"lower", I.lower()}, {"upper", I.upper()}, {"central", c}});
  }
  std::cout << "  orthants examined:";
  js["orthants"] = nlohmann::json::array();
  for (const auto& o : res.pui.orthants) {
    std::string signs;
    for (int s : o.signs) signs += s > 0 ? '+' : '-';
    std::cout << ' ' << (signs.empty() ? "(all)" : signs) << '=' << sets::to_string(o.status);
    js["orthants"].push_back({{"signs", signs}, {"status", sets::to_string(o.status)}});
  }
  std::cout << "\n  every PUI end certified by a safe bound: " << (res.pui.guaranteed ? "yes" : "NO") << ", LPs "
            << res.pui.lp_solves << ", time " << std::setprecision(3) << ms << " ms\n";
  js["guaranteed"] = res.pui.guaranteed;
  js["seconds"] = ms / 1e3;
  if (!json_path.empty()) sets::write_file_atomically(json_path, js.dump(2) + "\n");
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

  g_regressor_noise = regressor_noise == "scheduling" ? RegressorNoise::scheduling
                      : regressor_noise == "output"   ? RegressorNoise::output
                      : regressor_noise == "none"     ? RegressorNoise::none
                                                      : RegressorNoise::both;
  g_lagged_coefficients = coefficient_time == "lagged";
  sets::PuiOptions options;
  options.orthants = orthants == "all" ? sets::OrthantSelection::all : sets::OrthantSelection::remark2;
  try {
    if (!data_path.empty()) {
      if (ucol.empty() || ycol.empty() || rcols.empty())
        throw sets::InputError("--data needs --u, --y and at least one --r column");
      if (delta_eta < 0 || delta_eps < 0 || !std::isfinite(delta_eta) || !std::isfinite(delta_eps))
        throw sets::InputError("--data needs --delta-eta and --delta-eps, finite and >= 0 (got " +
                               std::to_string(delta_eta) + ", " + std::to_string(delta_eps) + ")");
      const LpvModelStructure model =
          structure_from_flags(model_file, a_flags, b_flags, static_cast<int>(rcols.size()));
      return run_data(data_path, ucol, ycol, rcols, delta_eta, delta_eps, model, options, json_path);
    }
    std::vector<int> tables;
    const std::map<std::string, int> index = {{"I", 0}, {"II", 1}, {"III", 2}, {"IV", 3}};
    if (table == "all")
      tables = {0, 1, 2, 3};
    else
      tables = {index.at(table)};
    return run_tables(tables, runs, seed, delta_e, options, threads, json_path);
  } catch (const std::exception& e) {
    return sets::report_failure("sets-lpv-pui", e);
  }
}
