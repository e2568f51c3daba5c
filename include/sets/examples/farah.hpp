#pragma once
// The example of Farah, Mercère, Poinot, van Wingerden, Section V: a 3-state, 2-input, 2-output
// system and its Monte Carlo data (used by sets-ss-uncertainty, its benchmark and its tests).

#include <random>

#include "sets/models/state_space_model.hpp"

namespace sets::farah {

/// The printed A, B, C (3 states, 2 inputs, 2 outputs) with D = 0.
StateSpaceModel system();

/// Output noise of the simulation: the paper's white Gaussian noise, or white noise uniform on
/// [-sqrt(3) sigma, sqrt(3) sigma] (the same variance, and bounded: the guaranteed set's assumption).
enum class Noise { gaussian, uniform };

/// Inputs and outputs, time along rows: u is N x nu, y is N x ny; sigma: the noise standard
/// deviation per output; largest_noise: max_t |v_j(t)| as realised (y_j - noise-free y_j).
struct Data {
  Eigen::MatrixXd u, y;
  Eigen::VectorXd sigma, largest_noise;
};

/// Section V's data: a random binary input (+-1, independent per sample and channel) of `samples`
/// samples, the system's response from x(0) = 0, and white noise added to each output at
/// `snr_db` (variance of the noise-free output over the noise variance, per channel). Draws the
/// input sample by sample, then the noise channel by channel, from `rng`.
Data simulate(const StateSpaceModel& sys, int samples, double snr_db, std::mt19937_64& rng,
              Noise noise = Noise::gaussian);

}  // namespace sets::farah
