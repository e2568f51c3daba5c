#include "sets/models/state_space_model.hpp"

#include "sets/core/error.hpp"

namespace sets {

Eigen::MatrixXd simulate(const StateSpaceModel& m, const Eigen::Ref<const Eigen::MatrixXd>& u,
                         const Eigen::Ref<const Eigen::VectorXd>& x0) {
  const auto n = m.A.rows();
  if (m.A.cols() != n || m.B.rows() != n || m.B.cols() != u.cols() || m.C.cols() != n || m.D.rows() != m.C.rows() ||
      m.D.cols() != u.cols() || (x0.size() != 0 && x0.size() != n))
    throw InputError("simulate: dimensions of A, B, C, D, u and x0 do not match");
  Eigen::VectorXd x = x0.size() ? x0 : Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd y(u.rows(), m.C.rows());
  for (int t = 0; t < u.rows(); ++t) {
    const Eigen::VectorXd ut = u.row(t).transpose();
    y.row(t) = (m.C * x + m.D * ut).transpose();
    x = m.A * x + m.B * ut;
  }
  return y;
}

}  // namespace sets
