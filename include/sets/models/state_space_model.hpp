#pragma once
// A discrete-time linear state-space model and its simulation.
//
//   x(t+1) = A x(t) + B u(t),   y(t) = C x(t) + D u(t)
//
// Time runs along the rows of input and output matrices (u is N x nu, y is N x ny).

#include <Eigen/Core>

namespace sets {

struct StateSpaceModel {
  Eigen::MatrixXd A, B, C, D;
};

/// Simulates the model from x(0) = x0 (zero if empty); u is N x nu, the result N x ny (time along
/// rows). Throws InputError when the dimensions of A, B, C, D, u and x0 do not match.
Eigen::MatrixXd simulate(const StateSpaceModel& m, const Eigen::Ref<const Eigen::MatrixXd>& u,
                         const Eigen::Ref<const Eigen::VectorXd>& x0 = Eigen::VectorXd());

}  // namespace sets
