#pragma once
// Test fixtures shared by the time-varying bound tests (tv_bound, jump_search, tv_relinearisation).

#include <Eigen/Core>

#include <random>

#include "sets/methods/tv_bound/tv_bound.hpp"
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

/// Data of a small problem: small_oscillator() simulated with the perturbation pi and output noise
/// of window norm noise_norm.
inline TvBoundData small_data(const Eigen::MatrixXd& pi, double noise_norm, unsigned seed, int window = 8,
                              int input_half_period = 7) {
  const auto m = small_oscillator();
  const int N = static_cast<int>(pi.rows());
  const Eigen::MatrixXd u = square_input(N, input_half_period);
  const Eigen::VectorXd x0 = Eigen::Vector2d::Zero();
  const auto w = sets::WindowNorm::pulse(window, 1.0 / window);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd eta(N + 1);
  for (int k = 0; k <= N; ++k) eta[k] = U(rng);
  if (noise_norm > 0) eta *= noise_norm / w(eta);
  else eta.setZero();
  return {sets::biaffine_regression(m, x0, u), sets::simulate(m, x0, u, pi).y + eta, {w}};
}

/// The sparse-bound options the MILP tests share: mu = 1e-3 on each of the three parameters,
/// |pi| <= max_abs, the window-norm bound epsilon (from linf_bound). The node limit decides where a
/// search stops, so results do not depend on load; the 600 s time limit only guards against a hang.
inline SparseBoundOptions milp_options(const Eigen::VectorXd& epsilon, long node_limit, double max_abs = 1.0) {
  SparseBoundOptions o;
  o.mu = Eigen::Vector3d::Constant(1e-3);
  o.max_abs = Eigen::Vector3d::Constant(max_abs);
  o.epsilon = epsilon;
  o.milp.time_limit_s = 600;
  o.milp.node_limit = node_limit;
  return o;
}

}  // namespace sets::testing
