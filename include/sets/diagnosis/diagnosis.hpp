#pragma once
// Discrepancy diagnosis: calibrate a nominal model (several starts), locate where it fails (time
// windows, operating regions, frequency band, parameters that would have to vary), screen the
// catalogue's hypotheses by least squares, refine the best few by output error, name the missing
// physics that passes every documented rule (or say that nothing is missing, or that the mismatch
// is real but unexplained), add it, and give the new parameters with bounded-error intervals.
// See docs/methods/diagnosis.md.

#include <Eigen/Core>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sets/diagnosis/acceptance.hpp"
#include "sets/diagnosis/residual_tests.hpp"
#include "sets/models/model_file.hpp"
#include "sets/data/intersample.hpp"
#include "sets/data/noise_level.hpp"
#include "sets/data/recording.hpp"

namespace sets {

struct DiagnosisOptions {
  int screening_substeps = 0;   // RK4 substeps while hypotheses are calibrated; 0: the fewest (1, 2,
                                // 3, ...) whose fits agree with final_substeps within 0.2 points
  int final_substeps = 10;      // RK4 substeps for the reported fits
  int max_effects = 3;
  double min_cost_reduction = 0.10;  // a hypothesis must remove >= 10 % of the squared misfit, and its
                                     // own term must be worth >= 10 % (acceptance.hpp)
  double min_validation_reduction = 0.05;  // ... and >= 5 % on the validation record
  double sparsity_tolerance = 1.25;  // the misfit each new parameter must buy (factor per parameter)
  double noise_floor_factor = 1.5;   // > 0: stop as soon as the residual tests say the model is within
                                     // the noise; 0: never (hypotheses must fail the rules on their own)
  int refine = 4;                    // hypotheses refined by output error per round (best screened)
  bool shortlist_slots = true;       // also refine the best single effect of every place with none
                                     // in the shortlist, and the best by linearised gain
  int global_step_starts = 2;        // stage 4: starts of the global step over the effects' parameters
                                     // that are calibrated (0: none; the estimate is the search's optimum)
  int threads = 2;
  int varying_segments = 0;          // segments of the time-varying estimates; 0: N/500 within [10, 30]
  std::function<void(const std::string&)> progress;  // one line per stage (optional)
  std::optional<Intersample> intersample;  // every input's behaviour between samples, overriding
                                           // the model file (sets/data/intersample.hpp)
};

struct MismatchWindow {
  std::string output;
  double start = 0, end = 0;   // s
  double rms = 0;              // residual RMS inside, output units
  bool falsified = false;      // no value of the free parameters keeps |residual| <= bound inside
};

struct MismatchRegion {
  std::string variable;
  std::string description;     // e.g. "near zero v"
  double residual_share = 0;   // share of the squared residual inside the region
  double sample_share = 0;     // share of the samples inside the region
};

/// One segment of an estimated parameter trajectory.
struct SegmentValue {
  double start = 0, end = 0;   // s
  double value = 0;            // parameter value held over the segment
};

/// Which parameter would have to vary over time, and when (Salehpour–Johansson estimates on the
/// calibrated model, the parameter perturbed piecewise constant over segments; see
/// docs/methods/diagnosis.md). These are estimates, not guaranteed bounds.
struct VaryingParameter {
  std::string name;
  double value = 0;            // calibrated constant value
  double lo = 0, hi = 0;       // range of the estimated trajectory
  double explained = 0;        // share of the residual's window-norm bound (h^T eps of the l-inf
                               // method) the trajectory removes
  double explained_squared = 0;  // share of the squared residual it removes
  std::vector<std::pair<double, double>> when;  // time windows holding the largest jumps
  double bound = 0;            // rho-hat: largest |trajectory - value| (l-inf estimate), parameter units
  std::vector<SegmentValue> trajectory;  // the estimate reported (sparse when it was solved)
  std::vector<std::pair<double, double>> jumps;  // (time of the segment start, size), parameter units
  std::string method;          // "sparse_bound" or "linf_bound"
};

struct FrequencyBand {
  std::string output;
  double lo_hz = 0, hi_hz = 0, peak_hz = 0;  // 80 % of the residual energy lies in [lo, hi]
};

struct EffectParameter {
  std::string name;
  std::string role;                 // the catalogue's role (e.g. "Fc"), whatever the symbol is called
  double estimate = 0;
  double lo = 0, hi = 0;            // bounded-error interval: holds under the stated error bound (an
                                    // assumption, not a theorem). Only sets that hold under it are met:
                                    // the equation-error PUI (has_ee) and the declared [min, max]; with
                                    // no equation-error PUI it is [min, max] alone (+-inf if unbounded).
                                    // The estimates below never cut it.
  double estimate_oe_lo = 0, estimate_oe_hi = 0;  // estimate: PUI of the output error *linearised* at the
  std::vector<double> oe_delta;     // estimate under |e_j| <= oe_delta[j] per output (1.5 x largest
                                    // residual); the nonlinear model's set need not lie inside it
  bool has_ee = false;              // an equation-error PUI was built (sets/equation_error.hpp) ...
  bool ee_certified = false;        // ... every finite end of it certified by a safe bound ...
  double ee_lo = 0, ee_hi = 0;
  double ee_delta = 0;              // ... under |integrated equation error| <= ee_delta
  double estimate_stat_lo = 0, estimate_stat_hi = 0;  // estimate: 95 % statistical interval (white noise)

  /// [lo, hi] rests on a bounded-error set (the certified equation-error PUI), not only on the
  /// declared [min, max].
  bool has_bounded_error_interval() const { return has_ee && ee_certified; }
};

/// Another hypothesis of the same round that the data cannot tell from the named one: it passes
/// every rule on its own, and neither it nor the named hypothesis is beyond the other by the nested
/// rule's comparison (docs/methods/diagnosis.md, "Equally good on these data"). Not a tie-break:
/// which of them is named is unchanged.
struct EquallyGood {
  std::vector<std::string> effects, equations;  // one effect, or the two of a pair, with their places
  double misfit = 0;             // its squared misfit, share of the current model's (estimation)
  double misfit_validation = 0;  // the same on validation (NaN without a validation record)
};

struct DiagnosedEffect {
  std::string name, equation, term, evidence;
  std::vector<EquallyGood> equally_good;  // the first effect of the named hypothesis carries them
  std::string placement;                 // structural place (physics_catalogue.hpp)
  std::vector<EffectParameter> parameters;
  int delay_samples = 0;                 // time_delay: the delay in samples
  double cost_reduction_estimation = 0;  // share of the misfit removed when it was added
  double cost_reduction_validation = 0;  // (the rules' values; NaN-free: 0 without validation)
  double screening_gain = 0;             // the linearised least-squares gain that shortlisted it
  std::vector<RuleCheck> rules;          // every documented rule, its value and threshold
};

/// The estimated noise level of one output channel (sets/data/noise_level.hpp): estimated on
/// every record, the most reliable method's value used for all of them.
struct OutputNoise {
  std::string output;            // recording column
  NoiseLevelEstimate estimate;   // the value used (an estimate, not a bound)
  std::string record;            // "estimation" or "validation": where it came from
  std::string model;             // "nominal" or "augmented": whose residual it was read from
};

/// A finding about the data, reported apart from missing physics: the same nominal structure
/// calibrated under the declared and under another intersample behaviour of the inputs
/// (data_hypothesis.cpp). ratio = V_declared / V_alternative of the squared simulation errors.
struct DataHypothesis {
  bool tested = false;
  std::string note;                  // why it was not tested, or what was compared
  std::vector<std::string> inputs;   // the inputs switched
  std::string declared, alternative; // intersample modes
  double ratio = 0;
  std::vector<double> fit_declared_estimation, fit_alternative_estimation;  // calibrated nominal
  std::vector<double> fit_declared_validation, fit_alternative_validation;
  bool found = false;                // the alternative explains the data markedly better
  std::string finding;               // one sentence when found
};

struct Diagnosis {
  std::vector<std::string> outputs;      // recording columns of the outputs
  ModelFile nominal, augmented;          // calibrated nominal and augmented model files
  std::vector<std::string> free_nominal;
  std::vector<double> fit_start_estimation, fit_start_validation;  // file values, before calibration (NaN:
  std::string fit_start_note;            // not available, e.g. the file's values blow up; this says why)
  std::vector<double> fit_nominal_estimation, fit_nominal_validation;
  std::vector<double> fit_augmented_estimation, fit_augmented_validation;
  bool has_validation = false;
  std::vector<MismatchWindow> windows;
  std::vector<MismatchRegion> regions;
  std::vector<VaryingParameter> varying;
  std::vector<FrequencyBand> bands;
  std::vector<DiagnosedEffect> effects;  // ranked, most important first
  // The three answers: nothing_missing (the calibrated nominal is within the noise: both residual
  // tests agree), effects named, or unexplained (the mismatch is real, no catalogue effect passes
  // every rule; `where` says where it is).
  bool nothing_missing = false;
  bool unexplained = false;
  std::string where;                     // unexplained: where the mismatch is
  std::string verdict;                   // one sentence
  std::string nominal_note;              // how the nominal was calibrated (starts, minima, stalls)
  bool nominal_far = false;              // the nominal could not be brought near the data
  ResidualTests nominal_tests;           // the calibrated nominal's residual tests
  ResidualTests final_tests;             // the final (augmented) model's, against noise_final
  std::vector<double> noise_sigma;       // estimated noise level per output (measurement units)
  std::string noise_note;                // how it was estimated
  int hypotheses_screened = 0, hypotheses_refined = 0;
  std::vector<double> error_bound;       // per output, used for windows and PUIs
  std::string bound_note;
  std::vector<OutputNoise> noise;        // per output, from the calibrated nominal's residual: the
                                         // floor the rules use (taken before augmentation)
  std::vector<OutputNoise> noise_final;  // per output, from the final model's residual (the augmented
                                         // one when effects were named, else the nominal's): what the
                                         // final model leaves as noise; the final residual tests use it,
                                         // the rules do not
  DataHypothesis data_hypothesis;        // a finding about the data (not physics)
  // Signals for plots.
  Eigen::VectorXd time_estimation, time_validation;
  Eigen::MatrixXd measured_estimation, nominal_estimation, augmented_estimation;
  Eigen::MatrixXd measured_validation, nominal_validation, augmented_validation;
  std::string signature_variable;        // the x of the signature plot
  Eigen::VectorXd signature_x, signature_residual;
  std::string signature_output;
  double seconds = 0;
};

Diagnosis diagnose(const ModelFile& model, const Recording& estimation, const Recording* validation,
                   const DiagnosisOptions& options = {});

/// The JSON of the issue (stable keys); `augmented_path` is written as "augmented.model".
std::string diagnosis_json(const Diagnosis& d, const std::string& augmented_path);
/// A short report an engineer reads in a terminal.
std::string diagnosis_text(const Diagnosis& d);

}  // namespace sets
