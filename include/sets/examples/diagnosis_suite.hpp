#pragma once
// The diagnosis run on suites of synthetic plants with known truth: the fixed suite
// (synthetic_plants.hpp) and the randomised one (random_plants.hpp), scored as in issue 14:
// first-named right on one-effect plants, both named on two-effect plants (each also leniently:
// or the truth among the named effect's equally good alternatives, with the number of alternatives
// per named effect beside it), invented effects on clean plants, the confusion matrix, per-effect
// precision and recall, the headline figures per plant family, and whether the true parameter
// values lie in the reported bounded-error intervals. `sets-diagnose --suite ...`.

#include <functional>
#include <string>
#include <vector>

#include "sets/diagnosis/diagnosis.hpp"
#include "sets/examples/synthetic_plants.hpp"

namespace sets {

struct SuiteCoverage {
  std::string effect, role;
  double truth = 0, lo = 0, hi = 0, estimate = 0;       // [lo, hi]: the reported bounded-error interval
  double estimate_oe_lo = 0, estimate_oe_hi = 0;        // estimate: the output-error PUI, linearised
  bool has_ee = false, ee_certified = false;
  double ee_lo = 0, ee_hi = 0;                          // the equation-error PUI
  double estimate_stat_lo = 0, estimate_stat_hi = 0;    // estimate: 95 % statistical interval (white noise)
  bool bounded = false;         // a bounded-error set was built (certified equation-error PUI): [lo, hi] means something
  bool inside = false;          // truth in [lo, hi] (trivially when !bounded: [lo, hi] is the declared range)
  bool inside_estimate = false; // truth in the linearised output-error estimate
  bool inside_meet = false;     // truth in the meet of the two PUIs (the reported interval before 2026-11-23)
};

struct SuitePlantResult {
  std::string name, family, description;
  std::vector<TrueEffect> truth;     // the true effects
  std::vector<std::string> named;    // the effects named, ranked
  std::vector<std::string> places;   // where each was named
  std::string answer;                // "nothing_missing", "missing" or "unexplained"
  double fit_nominal = 0, fit_augmented = 0;  // validation fit of the first output, percent
  double seconds = 0;
  std::vector<SuiteCoverage> coverage;  // true values that map cleanly, of effects named at the true place
  std::vector<double> noise_ratio;          // estimated / true noise sigma per output: the final model's estimate
  std::vector<double> noise_ratio_nominal;  // the same from the calibrated nominal's residual (the rules' floor)
  std::vector<std::vector<EquallyGood>> equally_good;  // per named effect: the hypotheses the data cannot tell from it
  std::string error;                 // the diagnosis failed with this message
  bool first_right() const;          // the first named effect is the (first) true one, or none for clean
  bool all_named() const;            // every true effect is named
  // Declared second figures, beside the strict ones: right, or the truth is among the named effects'
  // equally good alternatives (the first named effect's for first_right).
  bool first_right_or_equally_good() const;
  bool all_named_or_equally_good() const;
};

struct SuiteOptions {
  int threads = 2;      // plants diagnosed at the same time (each diagnosis on one thread)
  DiagnosisOptions diagnosis;  // threads and progress are set per plant
  std::function<void(const SuitePlantResult&, int done, int total)> on_plant;  // progress (optional)
};

/// Plants random_plant(first_seed), ..., random_plant(first_seed + count - 1).
std::vector<SuitePlantResult> run_random_suite(unsigned first_seed, int count, const SuiteOptions& options = {});
/// The fixed suite (every plant, or only `plant`).
std::vector<SuitePlantResult> run_fixed_suite(const std::string& plant = "", const SuiteOptions& options = {});
/// Diagnoses one plant and scores it.
SuitePlantResult run_suite_plant(const SyntheticPlant& plant, const DiagnosisOptions& options);

/// Markdown: the per-plant table, the summary figures, the confusion matrix (one-effect and clean
/// plants: true effect against first named), per-effect precision and recall, the headline figures
/// per plant family, interval coverage.
std::string suite_report(const std::vector<SuitePlantResult>& results, bool per_plant_table = true);

}  // namespace sets
