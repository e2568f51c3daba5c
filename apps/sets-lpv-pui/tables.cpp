#include "tables.hpp"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

#include "common/json_output.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/examples/cerone_regruto.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace {

using sets::LpvModelStructure;

struct RunResult {
  double snr_w = 0, snr_lambda = 0;
  Eigen::VectorXd theta_c, delta_theta;
  bool covered = false, empty = false, guaranteed = false;
  int orthants = 0, feasible_orthants = 0, lps = 0;
  double seconds = 0;
};

struct Setting {
  int table;      // index into paper_tables()
  int level;      // 1..4, or 0 for a custom --delta-e
  double delta_e;
};

RunResult simulate_and_bound(const Setting& s, int run, const TableRuns& tr) {
  const auto& spec = sets::cerone_regruto::paper_tables()[static_cast<std::size_t>(s.table)];
  const LpvModelStructure model =
      tr.lagged_coefficients ? sets::cerone_regruto::lagged_structure() : sets::cerone_regruto::structure();
  std::seed_seq seq{tr.seed, static_cast<std::uint64_t>(s.table), static_cast<std::uint64_t>(s.level),
                    static_cast<std::uint64_t>(run)};
  std::mt19937_64 rng(seq);
  const auto e = sets::cerone_regruto::simulate(spec.N, spec.uniform, s.delta_e, rng, tr.lagged_coefficients);
  RunResult r;
  // SNRs (eqs. 43-44) over the N regression samples.
  const auto T = e.w.size(), n0 = static_cast<Eigen::Index>(model.first_regression());
  r.snr_w = 10 * std::log10(e.w.tail(T - n0).squaredNorm() / e.eta.tail(T - n0).squaredNorm());
  r.snr_lambda = 10 * std::log10(e.lambda.col(0).tail(T - n0).squaredNorm() / e.eps.col(0).tail(T - n0).squaredNorm());
  const auto t0 = std::chrono::steady_clock::now();
  const sets::LpvPuiResult res = sets::unreliable_lpv_pui(model, e.data, tr.regressor_errors, tr.options);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.empty = res.pui.empty();
  r.guaranteed = res.pui.guaranteed;
  r.lps = res.pui.lp_solves;
  r.orthants = static_cast<int>(res.pui.orthants.size());
  for (const auto& o : res.pui.orthants) r.feasible_orthants += o.status == sets::OrthantStatus::feasible;
  if (!r.empty) {
    r.theta_c = res.pui.central;
    r.delta_theta.resize(6);
    for (int l = 0; l < 6; ++l) r.delta_theta[l] = (res.pui.box[l].upper() - res.pui.box[l].lower()) / 2;
    r.covered = sets::contains(res.pui.box, sets::cerone_regruto::true_theta());
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

// What one setting's runs add up to: the means and spreads printed beside the paper's.
struct SettingSummary {
  Stats snr_w, snr_lambda;
  std::vector<Stats> theta_c, delta_theta;  // per parameter, over the runs with a non-empty FPS
  int covered = 0, empty = 0, guaranteed = 0, orthants = 0, feasible_orthants = 0;
  double seconds = 0;  // bounding time summed over the runs
};

SettingSummary summarize(const RunResult* runs, int count) {
  std::vector<double> snr_w, snr_l;
  std::vector<std::vector<double>> tc(6), dt(6);
  SettingSummary s;
  for (int run = 0; run < count; ++run) {
    const RunResult& r = runs[run];
    snr_w.push_back(r.snr_w);
    snr_l.push_back(r.snr_lambda);
    s.seconds += r.seconds;
    s.covered += r.covered;
    s.empty += r.empty;
    s.guaranteed += r.guaranteed;
    s.orthants += r.orthants;
    s.feasible_orthants += r.feasible_orthants;
    if (r.empty) continue;
    for (int l = 0; l < 6; ++l) {
      tc[l].push_back(r.theta_c[l]);
      dt[l].push_back(r.delta_theta[l]);
    }
  }
  s.snr_w = stats(snr_w);
  s.snr_lambda = stats(snr_l);
  for (int l = 0; l < 6; ++l) {
    s.theta_c.push_back(stats(tc[l]));
    s.delta_theta.push_back(stats(dt[l]));
  }
  return s;
}

void print_table_header(const sets::cerone_regruto::PaperTable& spec, const TableRuns& tr) {
  std::cout << "\nTable " << spec.name << ": lambda " << (spec.uniform ? "uniform in [-1, 1]" : "= sin(0.1 t)")
            << ", N = " << spec.N << ", " << tr.runs << " runs, "
            << (tr.options.orthants == sets::OrthantSelection::all ? "all orthants" : "Remark-2 orthants")
            << (tr.regressor_errors == sets::RegressorErrors::both ? ""
                                                                   : ", DIAGNOSTIC regressor boxes (not guaranteed)")
            << '\n';
}

void print_setting(const Setting& s, const SettingSummary& m, const sets::cerone_regruto::PaperLevel* paper, int runs) {
  const std::vector<std::string> names = sets::cerone_regruto::structure().parameter_names();
  const Eigen::VectorXd theta = sets::cerone_regruto::true_theta();
  std::cout << "  level " << (s.level > 0 ? std::to_string(s.level) : std::string("custom")) << ": Delta E = "
            << sci(s.delta_e, 2) << "   SNR_w " << fix(m.snr_w.mean, 1) << " dB (paper "
            << (paper ? fix(paper->snr_w, 1) : "-") << ")   SNR_lambda " << fix(m.snr_lambda.mean, 1) << " dB (paper "
            << (paper ? fix(paper->snr_lambda, 1) : "-") << ")   true theta in all PUIs: " << m.covered << "/" << runs
            << (m.empty ? "   EMPTY FPS in " + std::to_string(m.empty) + " runs" : "") << '\n';
  std::cout << "    " << std::left << std::setw(18) << "parameter" << std::right << std::setw(6) << "true"
            << std::setw(22) << "theta_c ours" << std::setw(9) << "paper" << std::setw(24) << "Delta theta ours"
            << std::setw(10) << "paper" << '\n';
  for (int l = 0; l < 6; ++l) {
    const Stats &a = m.theta_c[l], &b = m.delta_theta[l];
    std::cout << "    " << std::left << std::setw(18) << names[l] << std::right << std::setw(6) << fix(theta[l], 1)
              << std::setw(22) << (fix(a.mean, 4) + " +- " + fix(a.std, 4)) << std::setw(9)
              << (paper ? fix(paper->theta_c[l]) : "-") << std::setw(24) << (sci(b.mean) + " +- " + sci(b.std))
              << std::setw(10) << (paper ? sci(paper->delta_theta[l]) : "-") << '\n';
  }
  std::cout << "    orthants examined per run " << fix(static_cast<double>(m.orthants) / runs, 2) << " (feasible "
            << fix(static_cast<double>(m.feasible_orthants) / runs, 2) << "), every end certified in " << m.guaranteed
            << "/" << runs << " runs, bounding time " << fix(1e3 * m.seconds / runs, 1) << " ms per run\n";
}

sets::app::Json setting_json(const Setting& s, const SettingSummary& m, const TableRuns& tr) {
  const auto& spec = sets::cerone_regruto::paper_tables()[static_cast<std::size_t>(s.table)];
  const sets::cerone_regruto::PaperLevel* paper = s.level > 0 ? &spec.paper[s.level - 1] : nullptr;
  const int runs = tr.runs;
  sets::app::Json js;
  js["table"] = spec.name;
  js["level"] = s.level;
  js["N"] = spec.N;
  js["lambda"] = spec.uniform ? "uniform" : "sin";
  js["delta_e"] = s.delta_e;
  js["runs"] = runs;
  js["coefficient_time"] = tr.lagged_coefficients ? "lagged" : "current";
  js["regressor_noise"] = sets::to_string(tr.regressor_errors);
  js["snr_w"] = m.snr_w.mean;
  js["snr_lambda"] = m.snr_lambda.mean;
  js["theta_true"] = sets::app::to_json(sets::cerone_regruto::true_theta());
  std::vector<double> tcm, tcs, dtm, dts;
  for (int l = 0; l < 6; ++l) {
    tcm.push_back(m.theta_c[l].mean);
    tcs.push_back(m.theta_c[l].std);
    dtm.push_back(m.delta_theta[l].mean);
    dts.push_back(m.delta_theta[l].std);
  }
  js["theta_c_mean"] = tcm;
  js["theta_c_std"] = tcs;
  js["delta_theta_mean"] = dtm;
  js["delta_theta_std"] = dts;
  js["coverage"] = static_cast<double>(m.covered) / runs;
  js["guaranteed_share"] = static_cast<double>(m.guaranteed) / runs;
  js["empty_runs"] = m.empty;
  js["orthants_mean"] = static_cast<double>(m.orthants) / runs;
  js["feasible_orthants_mean"] = static_cast<double>(m.feasible_orthants) / runs;
  js["seconds"] = m.seconds;
  if (paper) {
    js["paper"] = {{"snr_w", paper->snr_w},
                   {"snr_lambda", paper->snr_lambda},
                   {"theta_c", std::vector<double>(paper->theta_c, paper->theta_c + 6)},
                   {"delta_theta", std::vector<double>(paper->delta_theta, paper->delta_theta + 6)}};
  }
  return js;
}

std::vector<Setting> settings_of(const TableRuns& tr) {
  const auto& tables = sets::cerone_regruto::paper_tables();
  std::vector<Setting> settings;
  for (int t : tr.tables) {
    if (tr.delta_e > 0)
      settings.push_back({t, 0, tr.delta_e});
    else
      for (int lv = 1; lv <= 4; ++lv) settings.push_back({t, lv, tables[t].delta_e[lv - 1]});
  }
  return settings;
}

}  // namespace

int run_tables(const TableRuns& tr) {
  const auto& kTables = sets::cerone_regruto::paper_tables();
  const int runs = tr.runs;
  const std::vector<Setting> settings = settings_of(tr);
  // One job per (setting, run); each job builds its own FPS and LPs on its own thread.
  const std::size_t jobs = settings.size() * static_cast<std::size_t>(runs);
  std::vector<RunResult> results(jobs);
  const auto wall0 = std::chrono::steady_clock::now();
  // Each run depends only on its index (its own generator), so the tables do not depend on --threads.
  const auto failure = sets::try_jobs(static_cast<int>(tr.threads), jobs, [&](std::size_t k) {
    results[k] = simulate_and_bound(settings[k / runs], static_cast<int>(k % runs), tr);
  });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (failure) {
    try {
      std::rethrow_exception(failure->error);
    } catch (const std::exception& e) {
      std::cerr << "sets-lpv-pui: run " << failure->index % runs << " of table "
                << kTables[settings[failure->index / runs].table].name << " failed: " << e.what() << '\n';
      return sets::exit_code_for(e);
    }
  }
  sets::app::Json out;
  out["settings"] = sets::app::Json::array();
  bool all_covered = true;
  int last_table = -1;
  for (std::size_t si = 0; si < settings.size(); ++si) {
    const Setting& s = settings[si];
    const SettingSummary m = summarize(&results[si * static_cast<std::size_t>(runs)], runs);
    all_covered = all_covered && m.covered == runs;
    if (s.table != last_table) print_table_header(kTables[s.table], tr);
    last_table = s.table;
    print_setting(s, m, s.level > 0 ? &kTables[s.table].paper[s.level - 1] : nullptr, runs);
    out["settings"].push_back(setting_json(s, m, tr));
  }
  std::cout << "\n" << (all_covered ? "coverage: the true theta was inside every PUI in every run (100%)"
                                    : "WARNING: the true theta was outside a PUI in some run")
            << "; wall time " << fix(wall, 1) << " s on " << std::max(1u, tr.threads) << " thread(s)\n";
  sets::app::write_json(tr.json_path, out);
  return 0;
}
