#pragma once
// The stages of sets::diagnose (private to src/diagnosis/): one file each.
//   calibrate_nominal.cpp  1. simulate the file's values, calibrate the nominal
//   noise_floor.cpp           the noise level of every output (sets/data/noise_level.hpp)
//   data_hypothesis.cpp       a finding about the data: the inputs' intersample behaviour
//   locate.cpp             2. windows, operating regions, frequency band (varying_parameters.cpp:
//                             which parameter would have to vary, and when)
//   hypotheses.cpp         3. competing catalogue hypotheses, added greedily (its parts:
//                             refine_trials, special_cases, refine_again, judge_round.cpp)
//   augment.cpp            4. the augmented model, its fits and the new parameters' intervals
//   report.cpp             5. JSON and text
//   diagnosis.cpp          the pipeline and the verdict
// See docs/methods/diagnosis.md for what each stage computes and why.

#include <Eigen/Core>

#include <functional>
#include <limits>
#include <iomanip>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sets/diagnosis/calibration.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/diagnosis/physics_catalogue.hpp"
#include "sets/data/simulation.hpp"

namespace sets::diagnosis_stage {

/// What every stage reads: the inputs, the options (screening substeps resolved) and the
/// simulators of the nominal model on both records.
struct Context {
  const ModelFile& model;
  const Recording& estimation;
  const Recording* validation;     // null without a validation record
  const DiagnosisOptions& options; // screening_substeps > 0
  const Simulator& exact;          // estimation record, final substeps
  const Simulator& fast;           // estimation record, screening substeps
  const Simulator* exact_validation;
  std::function<void(const std::string&)> say;  // a progress line (with elapsed time)
};

// ---- small helpers shared by the stages
/// Sum over outputs of (1 - fit/100)^2: the squared misfit the rules compare.
double cost_of(const std::vector<double>& fit);
/// cost_of's terms, one per output.
std::vector<double> output_costs(const std::vector<double>& fit);
Eigen::VectorXd values_of(const ModelFile& m);
void store_values(ModelFile& m, const Eigen::VectorXd& p);
/// Typical size of each free parameter: |value|, or a known scale by name, or 1.
std::vector<double> scales_for(const ModelFile& m, const std::vector<int>& free,
                               const std::vector<std::pair<std::string, double>>& known);
/// Jacobian of the outputs (output units, outputs stacked) with respect to the free parameters,
/// forward differences of 1e-4 of each scale (backward when the forward step blows up).
Eigen::MatrixXd output_jacobian(const Simulator& sim, const Eigen::VectorXd& p, const std::vector<int>& free,
                                const std::vector<double>& scale, const Eigen::MatrixXd& y0);
/// The same, one column per worker job on `threads` threads, each worker with a simulator of
/// `model` on `data` of its own (bit for bit the serial one).
Eigen::MatrixXd output_jacobian(const ModelFile& model, const Recording& data, int substeps, int threads, const Eigen::VectorXd& p,
                                const std::vector<int>& free, const std::vector<double>& scale, const Eigen::MatrixXd& y0);
/// The optimum found with the screening substeps, calibrated again with the final ones (`exact`)
/// when they differ: a model that fits to near the noise absorbs the coarse step's RK4 error in
/// its parameters, so its fits at the final substeps would understate it (Silverbox, input
/// band-limited, 1 substep: 99.4 % with those values, 95.8 % at 10). Never worse than `coarse`;
/// ok = false when `coarse` blows up with the final substeps.
CalibrationResult refine_with_final_substeps(const Context& c, const Simulator& exact, const Eigen::VectorXd& coarse,
                                             const std::vector<int>& free, const CalibrationOptions& options);
/// Bounded-error intervals of the free parameters from the output error linearised at the
/// estimate: strips |r_t - J_t dtheta| <= delta_j on every stride-th sample (about 1500 per
/// output), delta_j = 1.5 x the largest |residual| of output j there (the smallest bound under
/// which the estimate itself is consistent, with a margin for the truth, which sees the noise).
/// J: output_jacobian's; R: measured - simulated outputs. Stage 4 reports them; stage 3's nested
/// rule asks whether they exclude a special case.
struct OutputErrorIntervals {
  bool built = false;          // false: the strips were inconsistent, or the LPs failed (note)
  std::vector<double> lo, hi;  // per free parameter, parameter units, outward rounded
  std::vector<double> delta;   // the bound per output
  bool guaranteed = false;     // every finite end certified by a safe bound
  int stride = 1;
  std::string note;
};
/// `given_delta` (one per output): use these bounds instead (another point of the same
/// bounded-error set, stage 4's other optima).
OutputErrorIntervals output_error_intervals(const Eigen::MatrixXd& J, const Eigen::MatrixXd& R,
                                            const Eigen::VectorXd& estimate, const std::vector<int>& free,
                                            const std::vector<double>& scale,
                                            const std::vector<double>* given_delta = nullptr);
/// Are the same strips, with these bounds (one per output), certified inconsistent? (No point of
/// the linearised model fits within them; an LP that cannot decide is "not falsified".) Stage 3's
/// nested rule asks it of a special case, linearised at its own optimum, under the richer law's
/// bounds.
bool linearised_strips_falsified(const Eigen::MatrixXd& J, const Eigen::MatrixXd& R, const std::vector<double>& scale,
                                 std::vector<double> delta);
std::string fmt(double x, int prec = 3);
std::string fixed1(double x);
/// "constant_offset in T2 (removes 96.6 % of the squared misfit, 97.1 % on validation)", as the named
/// effect's evidence says it; a pair as "a in x + b in y".
std::string equally_good_text(const EquallyGood& e);

// ---- 1. calibrate
/// The fewest RK4 substeps (at least `at_least`, every count below final_substeps tried) whose
/// fits at the parameters `p` agree with the final substeps within 0.2 points; else final_substeps.
int screening_substeps(const ModelFile& model, const Recording& estimation, const Simulator& exact, const Eigen::VectorXd& p,
                       int final_substeps, int at_least = 1);
/// Whether the screening step `fast` (chosen at the file's values) blows up at the calibrated
/// values `p`: their simulation is not finite, or fits worse than the file's values at the same
/// step, although the calibration at the final step fits better than the file's values.
bool blows_up_at(const Simulator& fast, const Eigen::VectorXd& p, const ModelFile& file);

struct NominalFit {
  std::vector<int> free;               // the nominal's free parameters
  CalibrationResult calibration;       // fits and cost at the final substeps (calibrate_from)
  SimulationResult simulation;         // calibrated, final substeps, estimation record
  Eigen::MatrixXd validation_outputs;  // calibrated, final substeps, validation record (empty without)
  double cost = 0;                     // cost_of the calibrated fits (final substeps)
  CalibrationResult file_values;       // the file's values, final substeps: ok (false: they blow up) and cost
                                       // only; their fits are in Diagnosis::fit_start_*
  bool random_starts_drawn = false;    // the random starts have been calibrated (at most once)
};
/// Fits of the file's values (NaN and d.fit_start_note when they blow up: the other starts are
/// calibrated), then the calibrated nominal; fills d.fit_start_*, d.free_nominal, d.nominal and
/// d.fit_nominal_*. NumericalError when the file's values blow up and no start can be simulated.
NominalFit calibrate_nominal(const Context& c, Diagnosis& d);
/// A nominal calibrated near the data but not within the noise may have stalled there: the random
/// starts (unless drawn already) are calibrated, and their best replaces n's calibration when it
/// removes as much of the misfit as an effect must (options.min_cost_reduction on the estimation
/// record, min_validation_reduction on the validation record). True when it did: n, d.nominal,
/// d.fit_nominal_* are the new calibration's; d.nominal_note says what was tried either way.
bool recalibrate_stalled_nominal(const Context& c, NominalFit& n, Diagnosis& d);

// ---- noise_floor.cpp
struct NoiseFloor {
  std::vector<double> sigma;  // per output (estimates: sets/data/noise_level.hpp)
  std::vector<double> pole;   // the noise's AR(1) pole per output when its colour was verified, else 0
  double cost = 0;            // the misfit (cost_of units) the noise alone gives
  std::vector<double> costs;  // the same per output (0 where the output is constant)
  double cost_validation = std::numeric_limits<double>::quiet_NaN();  // the same on the validation record (NaN: none)
  std::string note;           // how sigma was estimated
};
/// The level and the verified AR(1) pole of each output's reading (the costs left empty): what
/// the residual tests take.
NoiseFloor levels_of(const std::vector<OutputNoise>& readings);
/// The noise level of every output from the calibrated nominal's residual (and the inputs'
/// repeats), on every record, the most reliable method's value used for all; fills d.noise.
NoiseFloor noise_floor(const Context& c, const NominalFit& nominal, Diagnosis& d);
/// The floor no higher than a calibrated model leaves. The residual of the right model is the
/// noise, and a model of a few parameters fitted to N samples takes only about p/N of it away; so
/// an output on which some calibrated hypothesis leaves a misfit (`least_costs`, per output,
/// estimation record; negative: none) below the floor's own proves the floor too high there, and
/// it is lowered to that misfit. Other outputs keep theirs; `note` says what was lowered.
NoiseFloor floor_within_fits(const Context& c, const NoiseFloor& floor, const std::vector<double>& least_costs,
                             const std::vector<std::string>& outputs);
/// The noise level read again from the final model's residual (after augment): a concealed effect
/// left in the nominal's residual inflates the floor; once named and fitted, it no longer does.
/// Fills d.noise_final (a copy of d.noise when no effect was named).
void final_noise(const Context& c, Diagnosis& d);

// ---- data_hypothesis.cpp
/// Is the mismatch a property of the data rather than of the physics? The nominal structure
/// calibrated again with the inputs between samples as the other hypothesis (band-limited when
/// declared held or linear, held when declared band-limited); fills d.data_hypothesis.
void test_data_hypothesis(const Context& c, const NominalFit& nominal, const NoiseFloor& noise, Diagnosis& d);

// ---- 2. locate
/// Windows, operating regions, signature, frequency band, error bounds and the time-varying
/// estimates on the calibrated nominal.
void locate_mismatch(const Context& c, const NominalFit& nominal, const NoiseFloor& noise, Diagnosis& d);
/// ||y_j - mean y_j|| per output (1 where the output is constant).
std::vector<double> output_norms(const Eigen::MatrixXd& measured);

std::vector<VaryingParameter> varying_parameters(const ModelFile& model, const Recording& est, int substeps,
                                                 const Eigen::VectorXd& p, const std::vector<int>& free,
                                                 const std::vector<double>& scale, const Eigen::MatrixXd& R,
                                                 const std::vector<double>& time, int segments, int threads);

// ---- 3. hypotheses
struct HypothesisSearch {
  ModelFile current;                                         // calibrated, with every chosen effect
  std::vector<Candidate> chosen;                             // in the order added
  std::vector<std::pair<std::string, double>> known_scales;  // scales of the effects' parameters
};
/// Competing catalogue hypotheses added greedily; fills d.effects and d.nothing_missing.
HypothesisSearch search_hypotheses(const Context& c, const NominalFit& nominal, const NoiseFloor& noise, Diagnosis& d);

// ---- 4. augment
/// The augmented model refined with the final substeps, its fits, and the new parameters'
/// intervals; fills d.augmented, d.fit_augmented_*, d.augmented_* and the effects' parameters.
void augment(const Context& c, const NominalFit& nominal, const HypothesisSearch& search, Diagnosis& d);
/// The reported bounded-error interval [ep.lo, ep.hi]: the declared [min, max] met only with the
/// sets that hold under the stated error bound (the certified equation-error PUI); the linearised
/// output-error PUI and the statistical interval are estimates and never cut it.
void set_bounded_error_interval(EffectParameter& ep, double min, double max);
/// A parameter's declared [min, max], "no bound" (+-1e300 in the model file) as +-inf: an interval
/// end there is unbounded (printed as inf, null in the JSON), not the number 1e+300.
std::pair<double, double> declared_range(const ModelParameter& p);

}  // namespace sets::diagnosis_stage
