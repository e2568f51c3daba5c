#pragma once
// sets-hinf-bound: the runs (Monte Carlo over the built-in example's simulated data, or one data
// set), the printed report, the JSON and the plot. The method is sets::hinf_bound.

#include <string>
#include <vector>

#include "common/json_output.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"

struct Settings {
  sets::HinfStructure structure;
  sets::HinfBoundOptions options;
  std::string basis_name = "kautz", noise_name = "stochastic";
  bool builtin = true, bounded = false, quiet = false;
  int runs = 200, N = 2000;  // built-in: data sets and samples per data set
  double noise_std = 0.02;   // built-in: white noise before the 1/(1 - 0.7 q^-1) filter
  unsigned seed = 1;
};

/// A Monte Carlo run in which the method stopped with a numerical failure (recorded, not fatal).
struct FailedRun {
  int run = 0;  // 1-based
  std::string reason;
};

struct Runs {
  sets::HinfBoundResult first;  // the first run that did not fail (or the first falsified one)
  int fail_b = 0, fail_grid = 0, fail_data = 0, fail_prior = 0, fail_regions = 0, falsified = 0;
  std::vector<FailedRun> failed;  // built-in Monte Carlo only; one data set rethrows (exit code 3)
  double seconds = 0;           // wall time in sets::hinf_bound, all runs
  std::vector<double> bs, bgrids, bdatas, bpriors, ubs, ubgrids, ubdatas, ubpriors, radii;
};

/// Built-in: `settings.runs` data sets of G0 from one generator; otherwise `data` once. Counts
/// where G0 falls outside the bounds (built-in only). A built-in run that fails numerically is
/// recorded with its reason and the campaign goes on; throws NumericalError if every run failed.
Runs run_all(const Settings& settings, const sets::HinfData& data, const sets::TransferFunction& G0);

/// The per-frequency table (unless quiet), the bounds, means, timing and Monte Carlo rates.
void print_results(const Settings& settings, const Runs& runs, double cpu_per_run);

sets::app::Json results_json(const Settings& settings, const Runs& runs, int samples, double cpu_per_run);

/// Regions, central estimate, nominal model, delta and the weight against frequency (G0 if given).
void plot(const std::string& png, const sets::HinfBoundResult& R, const sets::TransferFunction* G0);
