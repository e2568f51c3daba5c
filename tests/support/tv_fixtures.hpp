#pragma once
// Test fixtures shared by the time-varying bound tests (tv_bound_test, tv_relinearisation_test).

#include <Eigen/Core>

#include "sets/models/time_varying_model.hpp"

namespace sets::testing {

/// A damped oscillator (the crane's pendulum, scaled down, h = 0.1) with one parameter in A
/// (pi1: stiffness, through P), one in B (pi2: gain, through Q) and one additive (pi3, through D).
/// With `damping_parameter`, pi3 also scales the damping term (through P): every term of (1) used.
inline TimeVaryingModel small_oscillator(bool damping_parameter = false) {
  const double h = 0.1;
  TimeVaryingModel m;
  m.A.resize(2, 2);
  m.A << 1, h, -h * 2.0, 1 - h * 0.5;
  m.B = Eigen::Vector2d(0, h);
  m.C = Eigen::RowVector2d(1, 0);
  m.P = Eigen::MatrixXd::Zero(2, 6);
  m.P(1, 0) = -h;                       // pi1 * (-h x1)
  if (damping_parameter) m.P(1, 5) = -h;  // pi3 * (-h x2)
  m.Q = Eigen::MatrixXd::Zero(2, 3);
  m.Q(1, 1) = h;  // pi2 * h u
  m.D = Eigen::MatrixXd::Zero(2, 3);
  m.D(0, 2) = h;  // pi3 additive
  return m;
}

/// A square wave of amplitude 1 switching every `half_period` samples (N x 1).
inline Eigen::MatrixXd square_input(int N, int half_period) {
  Eigen::MatrixXd u(N, 1);
  for (int k = 0; k < N; ++k) u(k, 0) = (k / half_period) % 2 == 0 ? 1.0 : -1.0;
  return u;
}

}  // namespace sets::testing
