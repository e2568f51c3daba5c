#pragma once
// The overhead crane of Salehpour & Johansson, Section VII (shared by the app and its test).

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

}  // namespace sets::crane
