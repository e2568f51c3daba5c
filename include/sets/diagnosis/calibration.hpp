#pragma once
// Calibration of a model's free parameters by output error: Levenberg–Marquardt (Eigen's MINPACK
// port, forward-difference Jacobian) on simulated outputs, each output's residual divided by
// ||y - mean y|| so that outputs in different units weigh alike. Bounds (min/max) are respected by
// clamping inside the residual function.

#include <Eigen/Core>

#include <functional>
#include <vector>

#include "sets/data/simulation.hpp"

namespace sets {

struct CalibrationOptions {
  int max_evaluations = 300;                    // simulations
  double tolerance = 1e-7;                      // relative change of cost and parameters
  std::vector<double> scale;                    // typical size of each free parameter (default |start|)
  std::function<void(int evaluations)> progress;  // called after each simulation (optional)
};

struct CalibrationResult {
  Eigen::VectorXd parameters;  // all parameters, model order
  std::vector<int> free;       // the calibrated ones
  Eigen::MatrixXd outputs;     // simulated outputs at the optimum
  std::vector<double> fit;     // per output, percent
  double cost = 0;             // sum over outputs of (1 - fit/100)^2
  int evaluations = 0;
  bool ok = false;             // false when even the start blows up
  bool converged = false;      // LM stopped on its tolerances, not on max_evaluations (calibrate only)
};

/// Per-output fits of simulated outputs against measured ones.
std::vector<double> fits(const Eigen::Ref<const Eigen::MatrixXd>& measured, const Eigen::Ref<const Eigen::MatrixXd>& simulated);

/// Calibrates `free` (indices into the model's parameters) starting from `start` (all parameters).
CalibrationResult calibrate(const Simulator& sim, const Eigen::Ref<const Eigen::VectorXd>& start, const std::vector<int>& free,
                            const CalibrationOptions& options = {});

/// Simulates once and reports fits (no calibration); ok=false on blow-up.
CalibrationResult evaluate(const Simulator& sim, const Eigen::Ref<const Eigen::VectorXd>& parameters);

}  // namespace sets
