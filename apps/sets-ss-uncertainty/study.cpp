#include "study.hpp"

#include <cmath>
#include <iomanip>
#include <iostream>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <sstream>

#include "common/json_output.hpp"
#include "sets/core/error.hpp"

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

sets::farah::StudyOptions study_options(const Settings& st) {
  sets::farah::StudyOptions o = st.study;
  o.selection = parse_selection(st.selection);
  if (!st.rows.empty()) o.rows = parse_rows(st.rows, 2);
  o.noise = st.noise == "uniform" ? sets::farah::Noise::uniform : sets::farah::Noise::gaussian;
  if (o.past < 3) throw sets::InputError("--past " + std::to_string(o.past) + " is smaller than the order 3");
  return o;
}

void print_header(const Settings& st, const sets::farah::StudyOptions& o, const sets::farah::StudyResult& r) {
  std::cout << "sets-ss-uncertainty: Farah et al., Section V (3 states, 2 inputs, 2 outputs, D "
            << (o.estimate_d ? "estimated" : "= 0 known") << ")\n"
            << "  " << o.runs << " runs, N = " << o.samples << ", random binary input, white " << (st.noise == "uniform" ? "uniform (bounded)" : "Gaussian")
            << " output noise at "
            << o.snr_db << " dB SNR per channel, p = " << o.past << ", seed " << o.seed << "\n  rows of Gamma_1:";
  for (const auto& row : r.rows) std::cout << ' ' << sets::to_string(row);
  std::cout << "\n  residuals for l: " << sets::to_string(o.level.residuals) << ", "
            << sets::to_string(o.level.norm) << ", level dtheta' R dtheta <= " << o.level.level_factor
            << " l^2; mean l = " << std::setprecision(4) << r.mean_ell << "\n\n";
}

void print_table_i(const sets::farah::StudyResult& r) {
  std::cout << "Table I  (true value from the printed A, B, C; mean and std over the runs)\n"
            << "  param         true          mean           std   |bias|/std\n";
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const double ratio = r.std_dev[i] > 0 ? std::abs(r.mean[i] - r.truth[i]) / r.std_dev[i] : 0.0;
    std::cout << "  " << std::left << std::setw(8) << r.names[i] << std::right << std::fixed << std::setprecision(4)
              << std::setw(11) << r.truth[i] << std::setw(14) << r.mean[i] << std::scientific << std::setprecision(3)
              << std::setw(14) << r.std_dev[i] << std::fixed << std::setprecision(3) << std::setw(12) << ratio << '\n';
  }
}

// Returns the pairs' memberships that rounding could not decide.
int print_failure_rates(const sets::farah::StudyResult& r) {
  std::cout << "\nFailure rates (share of runs whose true parameters lie outside the domain)\n"
            << "  pair                  projection     slice\n";
  int undecided_pairs = 0;
  for (const auto& p : r.pairs) {  // the paper's pairs first
    undecided_pairs += p.projection.undecided + p.slice.undecided;
    const std::string label = "(" + r.names[p.i] + ", " + r.names[p.j] + ")";
    std::cout << "  " << std::left << std::setw(20) << label << std::right << std::fixed << std::setprecision(1)
              << std::setw(10) << 100 * p.projection.rate() << " %" << std::setw(8) << 100 * p.slice.rate() << " %\n";
  }
  std::cout << "  full vector (ellipsoid):   " << std::setprecision(1) << 100 * r.ellipsoid.rate() << " %\n"
            << "  full vector (estimate FPS |eps| <= l, l read from the residuals): " << 100 * r.estimate_fps.rate()
            << " %\n";
  if (const int pui_runs = r.estimate_fps_pui.runs)
    std::cout << "  estimate FPS PUI box (LP, " << pui_runs << " runs): " << 100.0 * r.estimate_fps_pui.outside / pui_runs << " %\n";
  return undecided_pairs;
}

void print_guaranteed(const sets::farah::StudyOptions& o, const sets::farah::StudyResult& r) {
  const int g_out = r.guaranteed.outside;
  std::cout << "\nGuaranteed set (true states enclosed from the data and the propagator, carried as interval regressors)\n"
            << "  assumes |v_j(t)| <= " << std::setprecision(3) << r.assumed_noise_sigmas
            << " sigma_j, x(0) = 0 and |u| <= 1 (FIR tail of the true system beyond p <= " << std::scientific
            << std::setprecision(2) << r.tail_bound.transpose() << ")" << std::fixed << std::setprecision(1) << "\n"
            << "  runs that met the assumption: " << r.runs_meeting_assumption << " of " << o.runs << "\n"
            << "  full vector outside: " << 100.0 * g_out / o.runs << " % (" << g_out << " runs, "
            << r.guaranteed_outside_meeting_assumption << " of them met the assumption)\n"
            << "  runs whose data contradicted the assumptions: " << r.contradicted_runs << "\n";
  if (const int g_pui_runs = r.guaranteed_pui.runs)
    std::cout << "  PUI box outside (LP, " << g_pui_runs << " runs): " << 100.0 * r.guaranteed_pui.outside / g_pui_runs << " %\n";
  std::cout << "  mean state-enclosure radius:" << std::scientific << std::setprecision(3);
  for (Eigen::Index k = 0; k < r.mean_state_radius.size(); ++k) std::cout << ' ' << r.mean_state_radius[k];
  std::cout << std::fixed << "\n";
}

void print_half_widths_and_timing(const sets::farah::StudyOptions& o, const sets::farah::StudyResult& r) {
  const int pui_runs = r.estimate_fps_pui.runs, g_pui_runs = r.guaranteed_pui.runs;
  std::cout << "\nMean half-widths: ellipsoid outer box" << (pui_runs ? ", estimate FPS PUIs" : "")
            << (g_pui_runs ? ", guaranteed PUIs" : "") << "\n";
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    std::cout << "  " << std::left << std::setw(8) << r.names[i] << std::right << std::scientific << std::setprecision(3)
              << std::setw(12) << r.ellipsoid_box_halfwidth[i];
    if (pui_runs) std::cout << std::setw(12) << r.estimate_pui_halfwidth[i];
    if (g_pui_runs) std::cout << std::setw(12) << r.guaranteed_pui_halfwidth[i];
    std::cout << '\n';
  }
  std::cout << std::fixed << std::setprecision(2) << "\nTiming: " << r.seconds << " s for " << o.runs << " runs on "
            << o.threads << " threads" << (pui_runs ? " (with " + std::to_string(pui_runs) + " PUI computations)" : "")
            << ", " << r.cpu_seconds << " s CPU (busiest thread " << r.busiest_thread_cpu_seconds << " s)\n";
}

Json study_json(const Settings& st, const sets::farah::StudyOptions& o, const sets::farah::StudyResult& r) {
  const int pui_runs = r.estimate_fps_pui.runs, g_pui_runs = r.guaranteed_pui.runs;
  Json jp = Json::array();
  for (std::size_t i = 0; i < r.names.size(); ++i)
    jp.push_back({{"name", r.names[i]}, {"true", r.truth[i]}, {"mean", r.mean[i]}, {"std", r.std_dev[i]}});
  Json jpairs = Json::array();
  for (const auto& p : r.pairs)
    jpairs.push_back({{"pair", {r.names[p.i], r.names[p.j]}}, {"projection", p.projection.rate()}, {"slice", p.slice.rate()}});
  Json j;
  j["runs"] = o.runs;
  j["parameters"] = jp;
  j["failure_rates"] = {{"pairs", jpairs}, {"full", r.ellipsoid.rate()}, {"estimate_fps_full", r.estimate_fps.rate()}};
  if (pui_runs) j["failure_rates"]["estimate_fps_pui_box"] = r.estimate_fps_pui.rate();
  if (o.guaranteed) {
    j["failure_rates"]["guaranteed_fps_full"] = r.guaranteed.rate();
    if (g_pui_runs) j["failure_rates"]["guaranteed_pui_box"] = r.guaranteed_pui.rate();
    const auto& hw = r.guaranteed_pui_halfwidth;
    j["guaranteed"] = {{"runs_meeting_assumption", r.runs_meeting_assumption},
                       {"outside_while_assumption_held", r.guaranteed_outside_meeting_assumption},
                       {"contradicted_runs", r.contradicted_runs},
                       {"tail_bound", std::vector<double>(r.tail_bound.data(), r.tail_bound.data() + r.tail_bound.size())},
                       {"mean_pui_halfwidth", std::vector<double>(hw.data(), hw.data() + hw.size())}};
  }
  j["seconds"] = r.seconds;
  j["cpu_seconds"] = r.cpu_seconds;
  j["settings"] = {{"seed", o.seed},          {"snr_db", o.snr_db},
                   {"past", o.past},          {"samples", o.samples},
                   {"threads", o.threads},    {"estimate_d", o.estimate_d},
                   {"residuals", sets::to_string(o.level.residuals)},
                   {"norm", sets::to_string(o.level.norm)},
                   {"level_factor", o.level.level_factor},
                   {"mean_ell", r.mean_ell},  {"pui_runs", pui_runs},
                   {"noise", st.noise},       {"noise_bound_sigmas", o.noise_bound_sigmas}};
  return j;
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
  const sets::farah::StudyOptions o = study_options(st);
  const sets::farah::StudyResult r = sets::farah::study(o);
  print_header(st, o, r);
  print_table_i(r);
  const int undecided_pairs = print_failure_rates(r);
  if (o.guaranteed) print_guaranteed(o, r);
  const int undecided = r.ellipsoid.undecided + r.estimate_fps.undecided + undecided_pairs;
  if (undecided) std::cout << "  (undecided by rounding, counted as inside: " << undecided << ")\n";
  print_half_widths_and_timing(o, r);
  if (!st.json_path.empty()) sets::app::write_json(st.json_path, study_json(st, o, r));
  return 0;
}
