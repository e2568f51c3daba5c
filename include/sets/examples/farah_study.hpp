#pragma once
// The Monte Carlo study of Farah, Mercère, Poinot, van Wingerden, Section V, on the example system
// of farah.hpp: per run, data from the run's own generator, one ss_uncertainty() call and whether
// the true parameters lie in each domain; over the runs, Table I (mean and standard deviation of
// θ̃), the failure rates of the paper's ellipsoid, of the estimate FPS and of the guaranteed set.
// The runs share worker threads; each run depends only on its index and the reductions follow the
// run order, so the result does not depend on the number of threads. `sets-ss-uncertainty`
// without --data prints it.

#include <Eigen/Core>

#include <string>
#include <vector>

#include "sets/examples/farah.hpp"
#include "sets/methods/ss_uncertainty/ss_uncertainty.hpp"

namespace sets::farah {

struct StudyOptions {
  int runs = 1000;
  unsigned long long seed = 1;
  double snr_db = 20;
  int past = 20;
  int samples = 1000;
  int threads = 1;                     // runs at once, each on its own worker thread
  bool estimate_d = false;
  std::vector<ObservabilityRow> rows;  // rows of Γ_1; empty: select_rows(A, C, selection)
  RowSelection selection = RowSelection::output_major;
  LevelSetOptions level;
  int fps_pui_runs = -1;               // PUIs of the estimate FPS by LP in the first K runs (-1: all)
  Noise noise = Noise::gaussian;
  double noise_bound_sigmas = 4;       // Gaussian noise: the bound the guaranteed set assumes, in sigmas
  bool guaranteed = true;              // the guaranteed set (its membership test) in every run
  int guaranteed_pui_runs = 0;         // its PUIs by LP in the first K runs (-1: all); costly
};

/// The generator of run `run` of a study with seed `seed` (the data of farah::simulate).
std::mt19937_64 run_generator(unsigned long long seed, int run);

/// Runs whose true parameters lie outside a domain, of `runs`; `undecided`: runs in which
/// rounding could not decide membership (not counted in `outside`).
struct FailureCount {
  int outside = 0, undecided = 0, runs = 0;
  double rate() const { return runs > 0 ? static_cast<double>(outside) / runs : 0.0; }
};

struct PairFailureCounts {
  int i = 0, j = 0;                 // parameter indices, i < j
  FailureCount projection, slice;   // the ellipsoid's projection on (θ_i, θ_j) and its slice there
};

struct StudyResult {
  std::vector<ObservabilityRow> rows;   // the rows of Γ_1 used
  std::vector<std::string> names;       // parameter names
  Eigen::VectorXd truth, mean, std_dev; // Table I
  double mean_ell = 0;                  // mean level l
  /// Every pair of parameters: the paper's (-a0, -a1) and (-a2, b0^1) first, then the others.
  std::vector<PairFailureCounts> pairs;
  FailureCount ellipsoid, estimate_fps, estimate_fps_pui;  // estimate_fps_pui.runs: runs with PUIs
  Eigen::VectorXd ellipsoid_box_halfwidth;  // mean over the runs
  Eigen::VectorXd estimate_pui_halfwidth;   // mean over the runs with PUIs (zero without)
  // The guaranteed set (options.guaranteed; zero otherwise).
  double assumed_noise_sigmas = 0;       // |v_j(t)| <= this * sigma_j is assumed
  Eigen::VectorXd tail_bound;            // FIR tail of the true system beyond p, |u| <= 1
  int runs_meeting_assumption = 0;       // realised noise within the assumed bound
  int contradicted_runs = 0;             // the data contradicted the assumptions
  FailureCount guaranteed;               // full vector outside the guaranteed FPS
  int guaranteed_outside_meeting_assumption = 0;
  FailureCount guaranteed_pui;           // .runs: runs with its PUIs
  Eigen::VectorXd guaranteed_pui_halfwidth;  // mean over the runs with PUIs
  Eigen::VectorXd mean_state_radius;     // mean radius of the state enclosures, per state
  double seconds = 0, cpu_seconds = 0;   // of the runs (wall; CPU of the process, all threads)
  /// The most CPU time one worker thread used: the wall time of the runs when every worker has a
  /// core of its own (a load-independent reading of how the work is shared out).
  double busiest_thread_cpu_seconds = 0;
};

/// The study on farah::system(). Throws InputError for options it cannot use (naming the field),
/// and the first failure (lowest run index) of a run.
StudyResult study(const StudyOptions& options);

}  // namespace sets::farah
