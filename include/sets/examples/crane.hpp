#pragma once
// The overhead crane of Salehpour & Johansson, Section VII: the model, its inputs, the
// perturbations of Tables I-III and the noise (used by sets-tv-bound, its benchmark and its tests).

#include <Eigen/Core>

#include <string>
#include <vector>

#include "sets/methods/tv_bound/window_norm.hpp"
#include "sets/models/time_varying_model.hpp"

namespace sets::crane {

inline constexpr double kStep = 0.05;  // sampling interval h [s]

// Crane (15) as model (1): pi1 enters through Q (third row, times u), pi2 and pi3 through P
// (second row, times x); D = 0. pi (x) x = [pi1 x; pi2 x; pi3 x], pi (x) u = [pi1 u; pi2 u; pi3 u].
inline TimeVaryingModel model(double lambda0, double kappa0, double b0) {
  const double h = kStep;
  TimeVaryingModel m;
  m.A.resize(3, 3);
  m.A << 1, h, 0, -h * lambda0, 1 - h * kappa0, h * lambda0, 0, 0, 1;
  m.B = Eigen::Vector3d(0, 0, h * b0);
  m.C = Eigen::RowVector3d(1, 0, 0);
  m.D = Eigen::MatrixXd::Zero(3, 3);
  m.P = Eigen::MatrixXd::Zero(3, 9);
  m.P(1, 3) = -h;  // pi2 * (-h x_p)
  m.P(1, 5) = h;   // pi2 * ( h x_s)
  m.P(1, 7) = -h;  // pi3 * (-h x_p')
  m.Q = Eigen::MatrixXd::Zero(3, 3);
  m.Q(2, 0) = h;   // pi1 * h u
  return m;
}

// Inputs, all within the same amplitude bound |u| <= 1 (the paper's u_c is only in its Fig. 1).
//   square:    +-1, period 4 s (the default; the reproduction tables use it).
//   prbs:      +-1 pseudo-random binary sequence: every kPrbsHold seconds the sign flips with
//              probability 1/2 (std::mt19937_64 seeded with `seed`), so no level lasts less than
//              the hold time.
//   multisine: sum of equal-amplitude sines at kMultisineFreq (rad/s, spanning the pendulum's
//              resonance sqrt(lambda0) = 1.82 rad/s at the nominal 3.3) with Schroeder phases
//              (low crest factor), scaled so that max_k |u(k)| = 1 on the horizon.
inline constexpr double kPrbsHold = 0.25;  // [s], 5 samples
inline constexpr double kMultisineFreq[] = {0.5, 1.0, 1.5, 1.8, 2.2, 3.0, 4.0};  // [rad/s]

/// N samples of the input `kind` ("square", "prbs" or "multisine"); InputError for another kind.
Eigen::MatrixXd input(const std::string& kind, int N, unsigned seed);

/// One case of Tables I-III: nominal (lambda0, kappa0, b0), perturbation amplitudes (true bounds
/// of pi1, pi2, pi3 on b, lambda, kappa), window norm of the output noise, and the shape.
struct Case {
  std::string table;  // "I", "II", "III" (the sinusoid of Fig. 7 is listed under table I, shape "sine")
  std::string label;
  double lambda0 = 3.3, kappa0 = 0.25, b0 = 2.0;
  Eigen::Vector3d amplitude{0.2, 1.0, 0.5};
  double noise = 0.1;
  bool sine = false;
};

/// The cases of table "I", "II", "III" or "all", in the paper's order.
std::vector<Case> cases(const std::string& table);

/// Perturbations over the horizon T = N h. Piecewise constant ("quantized", Fig. 1):
///   pi1 = A1 * {0 on [0, .2T), 1 on [.2T, .6T), .5 on [.6T, T)}
///   pi2 = A2 * {0 on [0, .3T), 1 on [.3T, .7T), .4 on [.7T, T)}
///   pi3 = A3 * {.5 on [.1T, .45T), 1 on [.45T, .8T), 0 elsewhere}
/// Sinusoidal (Fig. 7): pi_i = A_i sin(2 pi t / T_i) with T_i = T, T/1.5, T/2. N x 3.
Eigen::MatrixXd perturbation(const Case& c, int N);

/// The window norm of the paper: 36 samples, 1/35.
WindowNorm window();

/// White Gaussian output noise (N + 1 samples, std::mt19937_64 seeded with `seed`) scaled to the
/// window norm `level`.
Eigen::VectorXd noise(int N, double level, const WindowNorm& window, unsigned seed);

}  // namespace sets::crane
