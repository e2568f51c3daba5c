#include "sets/examples/farah_study.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <exception>
#include <mutex>
#include <time.h>
#include <utility>

#include "sets/core/error.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets::farah {

std::mt19937_64 run_generator(unsigned long long seed, int run) {
  return std::mt19937_64(seed * 1000003ULL + static_cast<unsigned long long>(run));
}

namespace {

enum Verdict : unsigned char { inside = 0, outside = 1, undecided = 2 };
Verdict verdict(BoolInterval b) {
  return b == BoolInterval::yes ? inside : b == BoolInterval::no ? outside : undecided;
}

// A PUI computed in a run: does its box hold the truth, and its half-widths (zero when empty).
struct PuiOutcome {
  bool done = false;
  Verdict verdict = inside;
  Eigen::VectorXd halfwidth;
};

PuiOutcome outcome_of(const PuiResult& p, const Eigen::VectorXd& truth) {
  const bool empty = p.empty();
  return {true, empty ? outside : (contains(p.box, truth) ? inside : outside),
          empty ? Eigen::VectorXd::Zero(truth.size()) : radius(p.box)};
}

// Adds a run's PUI to its failure count and half-width sum (runs where it was computed only).
void tally(const PuiOutcome& o, FailureCount& count, Eigen::VectorXd& halfwidth_sum) {
  if (!o.done) return;
  ++count.runs;
  count.outside += o.verdict == outside;
  halfwidth_sum += o.halfwidth;
}

struct RunResult {
  Eigen::VectorXd theta;
  double ell = 0;
  Verdict full = inside, fps_full = inside;
  PuiOutcome fps_pui;
  Eigen::VectorXd box_halfwidth;
  std::vector<Verdict> projection, slice;  // per pair
  // The guaranteed set: membership of the truth, its PUI box, whether the run met the assumption
  // (Gaussian noise can exceed the bound) and whether the data contradicted the assumptions.
  Verdict g_full = inside;
  PuiOutcome g_pui;
  bool assumption_held = true, contradicted = false;
  Eigen::VectorXd g_state_radius;
};

// What every run shares.
struct Setup {
  StateSpaceModel sys;
  std::vector<ObservabilityRow> rows;
  Eigen::VectorXd truth, tail;
  std::vector<std::pair<int, int>> pairs;  // (i, j), i < j, in the order of the result
  std::vector<std::string> names;
};

// The noise bound the guaranteed set assumes, in sigmas: sqrt(3) for uniform noise, k for Gaussian.
double assumed_sigmas(const StudyOptions& o) {
  return o.noise == Noise::uniform ? std::sqrt(3.0) : o.noise_bound_sigmas;
}

// Every pair i < j, the paper's two pairs first.
std::vector<std::pair<int, int>> pairs_in_paper_order(const std::vector<std::string>& names) {
  const int m = static_cast<int>(names.size());
  std::vector<std::pair<int, int>> all, out;
  for (int i = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j) all.push_back({i, j});
  auto paper = [&](const std::pair<int, int>& p) {
    return (names[p.first] == "-a0" && names[p.second] == "-a1") ||
           (names[p.first] == "-a2" && names[p.second] == "b0^1");
  };
  for (const auto& p : all)
    if (paper(p)) out.push_back(p);
  for (const auto& p : all)
    if (!paper(p)) out.push_back(p);
  return out;
}

Setup make_setup(const StudyOptions& o) {
  if (o.runs < 1) throw InputError("StudyOptions::runs = " + std::to_string(o.runs) + ": at least one run");
  Setup s;
  s.sys = system();
  s.rows = o.rows.empty() ? select_rows(s.sys.A, s.sys.C, o.selection) : o.rows;
  const CanonicalStructure structure(s.rows, 2, 2, o.estimate_d);
  s.truth = structure.to_parameters(canonical_form(s.sys, s.rows));
  s.names = structure.parameter_names();
  if (o.past < 3) throw InputError("StudyOptions::past = " + std::to_string(o.past) + " is smaller than the order 3");
  s.tail = fir_tail_bound(s.sys, o.past, 1.0);
  s.pairs = pairs_in_paper_order(s.names);
  return s;
}

RunResult one_run(const StudyOptions& st, const Setup& s, int run) {
  std::mt19937_64 rng = run_generator(st.seed, run);
  const auto data = simulate(s.sys, st.samples, st.snr_db, rng, st.noise);
  SsUncertaintyOptions o;
  o.identification.order = 3;
  o.identification.past = st.past;
  o.identification.estimate_d = st.estimate_d;
  o.identification.rows = s.rows;
  o.level = st.level;
  o.estimate_fps_pui = st.fps_pui_runs < 0 || run < st.fps_pui_runs;
  // 1e-9 relative covers the rounding of y + v and of the simulation.
  const Eigen::VectorXd vbar = data.sigma * assumed_sigmas(st) * (1 + 1e-9);
  if (st.guaranteed) {
    GuaranteedSetAssumptions a;
    a.noise_bound = vbar;
    a.tail_bound = s.tail;  // x(0) = 0 and |u| = 1: the FIR tail of the true system beyond p
    o.guaranteed = a;
    o.guaranteed_pui = st.guaranteed_pui_runs < 0 || run < st.guaranteed_pui_runs;
  }
  const auto result = ss_uncertainty(data.u, data.y, o);
  const auto& dom = result.estimate_level_set;
  const Eigen::VectorXd& truth = s.truth;
  RunResult r;
  r.theta = dom.theta;
  r.ell = dom.ell;
  r.full = verdict(contains(dom.ellipsoid, truth));
  for (const auto& [i, j] : s.pairs) {
    const auto v = pair_view(dom.ellipsoid, i, j);
    const Eigen::Vector2d tp(truth[i], truth[j]);
    r.projection.push_back(verdict(contains(v.projection, tp)));
    r.slice.push_back(v.slice ? verdict(contains(*v.slice, tp)) : outside);
  }
  r.fps_full = verdict(result.estimate_fps.contains(truth));
  r.box_halfwidth = radius(outer_box(dom.ellipsoid));
  if (result.estimate_fps_pui) r.fps_pui = outcome_of(*result.estimate_fps_pui, truth);  // LPs of this thread
  r.assumption_held = (data.largest_noise.array() <= vbar.array()).all();
  if (result.guaranteed_fps) {
    r.contradicted = !result.state_enclosure->contradictions.empty();
    r.g_full = verdict(result.guaranteed_fps->contains(truth));
    const Eigen::MatrixXd radii = radius(result.state_enclosure->states);  // one mode switch
    r.g_state_radius = Eigen::VectorXd::Zero(radii.rows());
    for (Eigen::Index k = 0; k < radii.rows(); ++k)
      for (Eigen::Index c = 0; c < radii.cols(); ++c) r.g_state_radius[k] += radii(k, c) / radii.cols();
  }
  if (result.guaranteed_pui) r.g_pui = outcome_of(*result.guaranteed_pui, truth);
  return r;
}

// CPU time of the calling thread, seconds.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Runs 0 .. count-1 on the worker threads, taken from a shared counter. After a failure the
// pending runs are skipped and the failure of the lowest run index is rethrown.
std::vector<RunResult> run_all(const StudyOptions& o, const Setup& s, double& busiest_thread_cpu) {
  const int count = o.runs;
  std::vector<RunResult> results(static_cast<std::size_t>(count));
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(count));
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::mutex mu;
  busiest_thread_cpu = 0;
  run_worker_threads(o.threads, [&] {
    const double c0 = thread_cpu_seconds();
    for (int k; !failed && (k = next++) < count;) {
      try {
        results[static_cast<std::size_t>(k)] = one_run(o, s, k);
      } catch (...) {
        errors[static_cast<std::size_t>(k)] = std::current_exception();
        failed = true;
      }
    }
    const double used = thread_cpu_seconds() - c0;
    const std::lock_guard<std::mutex> lock(mu);
    busiest_thread_cpu = std::max(busiest_thread_cpu, used);
  });
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  return results;
}

template <class Get>
FailureCount count(const std::vector<RunResult>& results, Get get) {
  FailureCount c;
  c.runs = static_cast<int>(results.size());
  for (const auto& r : results) {
    const Verdict v = get(r);
    c.outside += v == outside;
    c.undecided += v == undecided;
  }
  return c;
}

// Table I, the ellipsoid's and the estimate FPS' failure counts, the mean half-widths.
void summarise_estimates(const std::vector<RunResult>& results, const Setup& s, StudyResult& out) {
  const int runs = static_cast<int>(results.size()), m = static_cast<int>(s.truth.size());
  Eigen::MatrixXd TH(m, runs);
  for (int k = 0; k < runs; ++k) TH.col(k) = results[static_cast<std::size_t>(k)].theta;
  out.mean = TH.rowwise().mean();
  out.std_dev.resize(m);
  for (int i = 0; i < m; ++i)
    out.std_dev[i] = runs > 1 ? std::sqrt((TH.row(i).array() - out.mean[i]).square().sum() / (runs - 1)) : 0.0;
  for (std::size_t k = 0; k < s.pairs.size(); ++k)
    out.pairs.push_back({s.pairs[k].first, s.pairs[k].second,
                         count(results, [k](const RunResult& r) { return r.projection[k]; }),
                         count(results, [k](const RunResult& r) { return r.slice[k]; })});
  out.ellipsoid = count(results, [](const RunResult& r) { return r.full; });
  out.estimate_fps = count(results, [](const RunResult& r) { return r.fps_full; });
  out.estimate_fps_pui = FailureCount{};
  out.ellipsoid_box_halfwidth = Eigen::VectorXd::Zero(m);
  out.estimate_pui_halfwidth = Eigen::VectorXd::Zero(m);
  for (const auto& r : results) {
    out.ellipsoid_box_halfwidth += r.box_halfwidth / runs;
    tally(r.fps_pui, out.estimate_fps_pui, out.estimate_pui_halfwidth);
  }
  if (out.estimate_fps_pui.runs) out.estimate_pui_halfwidth /= out.estimate_fps_pui.runs;
  out.mean_ell = 0;
  for (const auto& r : results) out.mean_ell += r.ell / runs;
}

void summarise_guaranteed(const std::vector<RunResult>& results, const Setup& s, StudyResult& out) {
  const int runs = static_cast<int>(results.size());
  out.guaranteed.runs = runs;
  out.guaranteed_pui_halfwidth = Eigen::VectorXd::Zero(s.truth.size());
  out.mean_state_radius = Eigen::VectorXd::Zero(3);
  for (const auto& r : results) {
    out.runs_meeting_assumption += r.assumption_held;
    out.contradicted_runs += r.contradicted;
    out.guaranteed.outside += r.g_full == outside;
    out.guaranteed.undecided += r.g_full == undecided;
    out.guaranteed_outside_meeting_assumption += r.g_full == outside && r.assumption_held;
    out.mean_state_radius += r.g_state_radius / runs;
    tally(r.g_pui, out.guaranteed_pui, out.guaranteed_pui_halfwidth);
  }
  if (out.guaranteed_pui.runs) out.guaranteed_pui_halfwidth /= out.guaranteed_pui.runs;
}

}  // namespace

StudyResult study(const StudyOptions& options) {
  const Setup s = make_setup(options);
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();  // process CPU time (all threads)
  StudyResult out;
  const auto results = run_all(options, s, out.busiest_thread_cpu_seconds);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.cpu_seconds = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  out.rows = s.rows;
  out.names = s.names;
  out.truth = s.truth;
  out.tail_bound = s.tail;
  summarise_estimates(results, s, out);
  if (options.guaranteed) {
    out.assumed_noise_sigmas = assumed_sigmas(options);
    summarise_guaranteed(results, s, out);
  }
  return out;
}

}  // namespace sets::farah
