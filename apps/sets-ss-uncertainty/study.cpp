#include "study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <iostream>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <random>
#include <sstream>

#include "common/json_output.hpp"
#include "common/monte_carlo.hpp"
#include "sets/core/error.hpp"
#include "sets/examples/farah.hpp"

using sets::app::Json;

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

namespace {


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
  // The guaranteed set: membership of the truth, its PUI box, whether the run met the assumption
  // (Gaussian noise can exceed the bound) and whether the data contradicted the assumptions.
  Verdict g_full = inside, g_pui = inside;
  bool g_pui_done = false, assumption_held = true, contradicted = false;
  Eigen::VectorXd g_halfwidth, g_state_radius;
};

// The noise bound the guaranteed set assumes: sqrt(3) sigma for uniform noise, k sigma for
// Gaussian; 1e-9 relative covers the rounding of y + v and of the simulation.
Eigen::VectorXd assumed_noise_bound(const Settings& st, const Eigen::VectorXd& sigma) {
  const double k = st.noise == "uniform" ? std::sqrt(3.0) : st.noise_bound_sigmas;
  return sigma * k * (1 + 1e-9);
}

RunResult one_run(const Settings& st, const sets::StateSpaceModel& sys, const std::vector<sets::ObservabilityRow>& rows,
                  const Eigen::VectorXd& truth, const std::vector<std::pair<int, int>>& pairs,
                  const Eigen::VectorXd& tail, int run) {
  // One generator per run: the result does not depend on the number of threads.
  std::mt19937_64 rng(st.seed * 1000003ULL + static_cast<unsigned long long>(run));
  const auto noise = st.noise == "uniform" ? sets::farah::Noise::uniform : sets::farah::Noise::gaussian;
  const auto data = sets::farah::simulate(sys, st.samples, st.snr_db, rng, noise);
  const Eigen::MatrixXd& u = data.u;
  const Eigen::MatrixXd& y = data.y;
  sets::SsUncertaintyOptions o;
  o.identification.order = 3;
  o.identification.past = st.past;
  o.identification.estimate_d = st.estimate_d;
  o.identification.rows = rows;
  o.level = st.level;
  o.estimate_fps_pui = st.fps_pui_runs < 0 || run < st.fps_pui_runs;
  const Eigen::VectorXd vbar = assumed_noise_bound(st, data.sigma);
  if (st.guaranteed) {
    sets::GuaranteedSetAssumptions a;
    a.noise_bound = vbar;
    a.tail_bound = tail;  // x(0) = 0 and |u| = 1: the FIR tail of the true system beyond p
    o.guaranteed = a;
    o.guaranteed_pui = st.guaranteed_pui_runs < 0 || run < st.guaranteed_pui_runs;
  }
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
    r.fps_pui = p.empty() ? outside : (sets::contains(p.box, truth) ? inside : outside);
    r.pui_halfwidth = p.empty() ? Eigen::VectorXd::Zero(truth.size()) : sets::radius(p.box);
  }
  r.assumption_held = (data.largest_noise.array() <= vbar.array()).all();
  if (result.guaranteed_fps) {
    r.contradicted = !result.state_enclosure->contradictions.empty();
    r.g_full = verdict(result.guaranteed_fps->contains(truth));
    const Eigen::MatrixXd radii = sets::radius(result.state_enclosure->states);  // one mode switch
    r.g_state_radius = Eigen::VectorXd::Zero(radii.rows());
    for (Eigen::Index k = 0; k < radii.rows(); ++k)
      for (Eigen::Index c = 0; c < radii.cols(); ++c) r.g_state_radius[k] += radii(k, c) / radii.cols();
  }
  if (result.guaranteed_pui) {
    const auto& p = *result.guaranteed_pui;
    r.g_pui_done = true;
    r.g_pui = p.empty() ? outside : (sets::contains(p.box, truth) ? inside : outside);
    r.g_halfwidth = p.empty() ? Eigen::VectorXd::Zero(truth.size()) : sets::radius(p.box);
  }
  return r;
}

}  // namespace

int monte_carlo(const Settings& st) {
#ifdef __GLIBC__
  // Every run allocates and frees the same matrices of 0.1-1 MB. By default glibc hands such
  // blocks back to the kernel (mmap above 128 kB, heap trimming) and the next run faults them in
  // again, zeroed: about a tenth of a run (perf, docs/performance.md). Keep them in the process.
  mallopt(M_MMAP_THRESHOLD, 16 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
  const auto sys = sets::farah::system();
  const auto rows = st.rows.empty() ? sets::select_rows(sys.A, sys.C, parse_selection(st.selection))
                                    : parse_rows(st.rows, 2);
  const sets::CanonicalStructure structure(rows, 2, 2, st.estimate_d);
  const auto truth = structure.to_parameters(sets::canonical_form(sys, rows));
  const auto names = structure.parameter_names();
  const int m = static_cast<int>(truth.size());
  if (st.past < 3) throw sets::InputError("--past " + std::to_string(st.past) + " is smaller than the order 3");
  const Eigen::VectorXd tail = sets::fir_tail_bound(sys, st.past, 1.0);
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j) pairs.push_back({i, j});

  std::vector<RunResult> results(st.runs);
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();  // process CPU time (all threads)
  const auto failure = sets::app::run_parallel(static_cast<std::size_t>(st.runs), static_cast<unsigned>(st.threads),
                                               [&](std::size_t k) { results[k] = one_run(st, sys, rows, truth, pairs, tail, static_cast<int>(k)); });
  if (failure) std::rethrow_exception(failure->error);
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
  // The guaranteed set.
  int g_out = 0, g_out_held = 0, g_pui_runs = 0, g_pui_out = 0, held_runs = 0, contradicted_runs = 0;
  Eigen::VectorXd g_hw = Eigen::VectorXd::Zero(m), g_rad = Eigen::VectorXd::Zero(3);
  for (const auto& r : results) {
    if (!st.guaranteed) break;
    held_runs += r.assumption_held;
    contradicted_runs += r.contradicted;
    g_out += r.g_full == outside;
    g_out_held += r.g_full == outside && r.assumption_held;
    g_rad += r.g_state_radius / st.runs;
    if (r.g_pui_done) {
      ++g_pui_runs;
      g_pui_out += r.g_pui == outside;
      g_hw += r.g_halfwidth;
    }
  }
  if (g_pui_runs) g_hw /= g_pui_runs;
  double ell_mean = 0;
  for (const auto& r : results) ell_mean += r.ell / st.runs;

  std::cout << "sets-ss-uncertainty: Farah et al., Section V (3 states, 2 inputs, 2 outputs, D "
            << (st.estimate_d ? "estimated" : "= 0 known") << ")\n"
            << "  " << st.runs << " runs, N = " << st.samples << ", random binary input, white " << (st.noise == "uniform" ? "uniform (bounded)" : "Gaussian")
            << " output noise at "
            << st.snr_db << " dB SNR per channel, p = " << st.past << ", seed " << st.seed << "\n  rows of Gamma_1:";
  for (const auto& r : rows) std::cout << ' ' << sets::to_string(r);
  std::cout << "\n  residuals for l: " << sets::to_string(st.level.residuals) << ", "
            << sets::to_string(st.level.norm) << ", level dtheta' R dtheta <= " << st.level.level_factor
            << " l^2; mean l = " << std::setprecision(4) << ell_mean << "\n\n";
  std::cout << "Table I  (true value from the printed A, B, C; mean and std over the runs)\n"
            << "  param         true          mean           std   |bias|/std\n";
  Json jp = Json::array();
  for (int i = 0; i < m; ++i) {
    const double ratio = sd[i] > 0 ? std::abs(mean[i] - truth[i]) / sd[i] : 0.0;
    std::cout << "  " << std::left << std::setw(8) << names[i] << std::right << std::fixed << std::setprecision(4)
              << std::setw(11) << truth[i] << std::setw(14) << mean[i] << std::scientific << std::setprecision(3)
              << std::setw(14) << sd[i] << std::fixed << std::setprecision(3) << std::setw(12) << ratio << '\n';
    jp.push_back({{"name", names[i]}, {"true", truth[i]}, {"mean", mean[i]}, {"std", sd[i]}});
  }
  std::cout << "\nFailure rates (share of runs whose true parameters lie outside the domain)\n"
            << "  pair                  projection     slice\n";
  Json jpairs = Json::array();
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
            << "  full vector (estimate FPS |eps| <= l, l read from the residuals): " << 100 * fps_full.first
            << " %\n";
  if (pui_runs)
    std::cout << "  estimate FPS PUI box (LP, " << pui_runs << " runs): " << 100.0 * pui_out / pui_runs << " %\n";
  if (st.guaranteed) {
    std::cout << "\nGuaranteed set (true states enclosed from the data and the propagator, carried as interval regressors)\n"
              << "  assumes |v_j(t)| <= " << std::setprecision(3)
              << (st.noise == "uniform" ? std::sqrt(3.0) : st.noise_bound_sigmas)
              << " sigma_j, x(0) = 0 and |u| <= 1 (FIR tail of the true system beyond p <= " << std::scientific
              << std::setprecision(2) << tail.transpose() << ")" << std::fixed << std::setprecision(1) << "\n"
              << "  runs that met the assumption: " << held_runs << " of " << st.runs << "\n"
              << "  full vector outside: " << 100.0 * g_out / st.runs << " % (" << g_out << " runs, " << g_out_held
              << " of them met the assumption)\n"
              << "  runs whose data contradicted the assumptions: " << contradicted_runs << "\n";
    if (g_pui_runs)
      std::cout << "  PUI box outside (LP, " << g_pui_runs << " runs): " << 100.0 * g_pui_out / g_pui_runs << " %\n";
    std::cout << "  mean state-enclosure radius:" << std::scientific << std::setprecision(3);
    for (Eigen::Index k = 0; k < g_rad.size(); ++k) std::cout << ' ' << g_rad[k];
    std::cout << std::fixed << "\n";
  }
  if (full.second + fps_full.second + undecided_pairs)
    std::cout << "  (undecided by rounding, counted as inside: " << full.second + fps_full.second + undecided_pairs
              << ")\n";
  std::cout << "\nMean half-widths: ellipsoid outer box" << (pui_runs ? ", estimate FPS PUIs" : "")
            << (g_pui_runs ? ", guaranteed PUIs" : "") << "\n";
  for (int i = 0; i < m; ++i) {
    std::cout << "  " << std::left << std::setw(8) << names[i] << std::right << std::scientific << std::setprecision(3)
              << std::setw(12) << box_hw[i];
    if (pui_runs) std::cout << std::setw(12) << pui_hw[i];
    if (g_pui_runs) std::cout << std::setw(12) << g_hw[i];
    std::cout << '\n';
  }
  std::cout << std::fixed << std::setprecision(2) << "\nTiming: " << seconds << " s for " << st.runs << " runs on "
            << st.threads << " threads" << (pui_runs ? " (with " + std::to_string(pui_runs) + " PUI computations)" : "")
            << ", " << cpu_seconds << " s CPU\n";

  if (!st.json_path.empty()) {
    Json j;
    j["runs"] = st.runs;
    j["parameters"] = jp;
    j["failure_rates"] = {{"pairs", jpairs}, {"full", full.first}, {"estimate_fps_full", fps_full.first}};
    if (pui_runs) j["failure_rates"]["estimate_fps_pui_box"] = static_cast<double>(pui_out) / pui_runs;
    if (st.guaranteed) {
      j["failure_rates"]["guaranteed_fps_full"] = static_cast<double>(g_out) / st.runs;
      if (g_pui_runs) j["failure_rates"]["guaranteed_pui_box"] = static_cast<double>(g_pui_out) / g_pui_runs;
      j["guaranteed"] = {{"runs_meeting_assumption", held_runs},
                         {"outside_while_assumption_held", g_out_held},
                         {"contradicted_runs", contradicted_runs},
                         {"tail_bound", std::vector<double>(tail.data(), tail.data() + tail.size())},
                         {"mean_pui_halfwidth", std::vector<double>(g_hw.data(), g_hw.data() + g_hw.size())}};
    }
    j["seconds"] = seconds;
    j["cpu_seconds"] = cpu_seconds;
    j["settings"] = {{"seed", st.seed},          {"snr_db", st.snr_db},
                     {"past", st.past},          {"samples", st.samples},
                     {"threads", st.threads},    {"estimate_d", st.estimate_d},
                     {"residuals", sets::to_string(st.level.residuals)},
                     {"norm", sets::to_string(st.level.norm)},
                     {"level_factor", st.level.level_factor},
                     {"mean_ell", ell_mean},     {"pui_runs", pui_runs},
                     {"noise", st.noise},        {"noise_bound_sigmas", st.noise_bound_sigmas}};
    sets::app::write_json(st.json_path, j);
  }
  return 0;
}

