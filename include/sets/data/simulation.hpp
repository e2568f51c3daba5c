#pragma once
// Simulation of a model file against a recording: fixed-step RK4 with substeps, each input between
// samples as the model file declares it (held by default; sets/data/intersample.hpp), `sampled`
// signals evaluated at the sample instants and held until the next one.
//
// Expressions are muparser expressions over t, Ts, parameters, inputs, states, signals and
// sampled signals, plus prev(x, n): the value of x n >= 1 samples earlier (the first sample when
// there is none; 0 for a sampled signal that refers to its own past before the first sample).

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

#include "sets/models/model_file.hpp"
#include "sets/data/recording.hpp"

namespace sets {

struct SimulationOptions {
  int substeps = 10;  // RK4 steps per sample interval
};

struct SimulationResult {
  std::vector<std::string> names;  // every recorded symbol: inputs, states, signals, sampled
  Eigen::MatrixXd values;          // samples x names, at the sample instants
  Eigen::MatrixXd outputs;         // samples x outputs (model order)
  /// Column of a recorded symbol (InputError if it is not recorded).
  Eigen::VectorXd series(const std::string& name) const;
};

class Simulator {
 public:
  /// Compiles every expression (InputError naming an unknown symbol and where it is used) and
  /// takes inputs, time and initial states from the recording (InputError for a missing column,
  /// time that does not increase).
  Simulator(const ModelFile& model, const Recording& data, SimulationOptions options = {});
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  const ModelFile& model() const;
  int samples() const;
  const std::vector<double>& time() const;
  double sample_time() const;
  /// All parameter values in model order, and the indices of the free (not fixed) ones.
  Eigen::VectorXd parameter_values() const;
  std::vector<int> free_parameters() const;
  std::vector<std::string> parameter_names() const;
  /// Measured outputs: samples x outputs, from the recording's columns.
  const Eigen::MatrixXd& measured() const;
  std::vector<std::string> output_names() const;    // model symbols
  std::vector<std::string> output_columns() const;  // recording columns

  /// Simulates with these parameter values (model order). A non-finite state throws
  /// NumericalError naming the time and the state.
  SimulationResult simulate(const Eigen::Ref<const Eigen::VectorXd>& parameters) const;
  /// Outputs only (cheaper), samples x outputs. Returns false instead of throwing on blow-up.
  bool simulate_outputs(const Eigen::Ref<const Eigen::VectorXd>& parameters, Eigen::MatrixXd& outputs) const;
  /// simulate_outputs for each column of `parameters` (parameters x runs), run side by side:
  /// outputs[j] and ok[j] are bit for bit what simulate_outputs gives for column j, in less time
  /// (the expressions' interpretation is shared; a finite-difference Jacobian's columns).
  void simulate_outputs_each(const Eigen::Ref<const Eigen::MatrixXd>& parameters, std::vector<Eigen::MatrixXd>& outputs,
                             std::vector<bool>& ok) const;
  /// Outputs with time-varying parameters: row k of `schedule` (samples x parameters) holds the
  /// values used from sample k to sample k+1 (and by the sampled signals at k). Returns false on
  /// blow-up; InputError if the schedule has the wrong size.
  bool simulate_outputs_scheduled(const Eigen::Ref<const Eigen::MatrixXd>& schedule, Eigen::MatrixXd& outputs) const;
  /// simulate_outputs_scheduled for each schedule, run side by side as simulate_outputs_each:
  /// outputs[j] and ok[j] are bit for bit what simulate_outputs_scheduled gives for schedules[j].
  void simulate_outputs_scheduled_each(const std::vector<Eigen::MatrixXd>& schedules, std::vector<Eigen::MatrixXd>& outputs,
                                       std::vector<bool>& ok) const;

  struct Impl;  // muparser state (kept out of this header)

 private:
  std::unique_ptr<Impl> impl_;
};

/// Checks a model against a recording without simulating (same errors as the constructor).
void check_model(const ModelFile& model, const Recording& data);

/// fit = 100 (1 - ||y - yhat|| / ||y - mean y||) in percent.
double fit_percent(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& yhat);

}  // namespace sets
