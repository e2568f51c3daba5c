#include "sets/models/time_varying_model.hpp"

#include <string>
#include <vector>

#include "sets/core/error.hpp"

namespace sets {

namespace {

std::string dims(const Eigen::Ref<const Eigen::MatrixXd>& M) {
  return std::to_string(M.rows()) + " x " + std::to_string(M.cols());
}

void expect(const Eigen::MatrixXd& M, Eigen::Index rows, Eigen::Index cols, const char* what) {
  if (M.rows() != rows || M.cols() != cols)
    throw InputError(std::string("TimeVaryingModel: ") + what + " is " + dims(M) + ", expected " +
                     std::to_string(rows) + " x " + std::to_string(cols));
  if (!M.allFinite()) throw InputError(std::string("TimeVaryingModel: ") + what + " has a non-finite entry");
}

}  // namespace

void TimeVaryingModel::validate() const {
  const Eigen::Index n = A.rows(), p = B.cols(), l = C.rows(), q = D.cols();
  if (n == 0) throw InputError("TimeVaryingModel: A is empty");
  if (q == 0) throw InputError("TimeVaryingModel: D has no columns (no parameters); use a zero n x q D");
  expect(A, n, n, "A (n x n)");
  expect(B, n, p, "B (n x p)");
  expect(C, l, n, "C (l x n)");
  expect(D, n, q, "D (n x q)");
  expect(P, n, n * q, "P (n x nq)");
  expect(Q, n, q * p, "Q (n x qp)");
}

namespace {

// I_q (x) v: the (q * v.size()) x q matrix with v in each diagonal block.
Eigen::MatrixXd kron_identity(int q, const Eigen::VectorXd& v) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(q * v.size(), q);
  for (int i = 0; i < q; ++i) K.block(i * v.size(), i, v.size(), 1) = v;
  return K;
}

void check_signals(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                   const Eigen::Ref<const Eigen::MatrixXd>& u, const char* where) {
  model.validate();
  if (x0.size() != model.states())
    throw InputError(std::string(where) + ": x0 has " + std::to_string(x0.size()) + " entries, the model " +
                     std::to_string(model.states()) + " states");
  if (u.rows() == 0) throw InputError(std::string(where) + ": the input has no samples");
  if (u.cols() != model.inputs())
    throw InputError(std::string(where) + ": the input has " + std::to_string(u.cols()) +
                     " columns, the model " + std::to_string(model.inputs()) + " inputs");
  if (!u.allFinite() || !x0.allFinite())
    throw InputError(std::string(where) + ": the input or x0 holds a non-finite value");
}

}  // namespace

TimeVaryingSimulation simulate(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                               const Eigen::Ref<const Eigen::MatrixXd>& u,
                               const Eigen::Ref<const Eigen::MatrixXd>& pi) {
  check_signals(model, x0, u, "simulate");
  const int N = static_cast<int>(u.rows()), q = model.parameters();
  if (pi.rows() != N || pi.cols() != q)
    throw InputError("simulate: the perturbation is " + dims(pi) + ", expected " + std::to_string(N) + " x " +
                     std::to_string(q) + " (one row per input sample)");
  TimeVaryingSimulation s;
  s.x.resize(N + 1, model.states());
  Eigen::VectorXd x = x0;
  for (int k = 0; k <= N; ++k) {
    s.x.row(k) = x.transpose();
    if (k == N) break;
    const Eigen::VectorXd uk = u.row(k).transpose(), pk = pi.row(k).transpose();
    x = model.A * x + model.B * uk + model.P * (kron_identity(q, x) * pk) + model.D * pk +
        model.Q * (kron_identity(q, uk) * pk);
  }
  s.y = s.x * model.C.transpose();
  return s;
}

BiaffineRegression biaffine_regression(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                                       const Eigen::Ref<const Eigen::MatrixXd>& u) {
  check_signals(model, x0, u, "biaffine_regression");
  return linearised_regression(model, x0, u, Eigen::MatrixXd::Zero(u.rows(), model.parameters()));
}

BiaffineRegression linearised_regression(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                                         const Eigen::Ref<const Eigen::MatrixXd>& u,
                                         const Eigen::Ref<const Eigen::MatrixXd>& pi_bar) {
  check_signals(model, x0, u, "linearised_regression");
  const int N = static_cast<int>(u.rows()), n = model.states(), l = model.outputs(), q = model.parameters();
  if (pi_bar.rows() != N || pi_bar.cols() != q)
    throw InputError("linearised_regression: the linearisation point is " + dims(pi_bar) + ", expected " +
                     std::to_string(N) + " x " + std::to_string(q) + " (one row per input sample)");
  if (!pi_bar.allFinite()) throw InputError("linearised_regression: the linearisation point holds a non-finite value");
  BiaffineRegression r;
  r.pi_bar = pi_bar;
  r.zeta = simulate(model, x0, u, pi_bar).x;
  // A(k) = A + P (pi_bar(k) (x) I_n) = A + sum_i pi_bar_i(k) P_i (P_i: column block i of P).
  std::vector<Eigen::MatrixXd> Ak(static_cast<std::size_t>(N), model.A);
  for (int k = 0; k < N; ++k)
    for (int i = 0; i < q; ++i)
      if (pi_bar(k, i) != 0) Ak[static_cast<std::size_t>(k)] += pi_bar(k, i) * model.P.middleCols(i * n, n);
  // Column block j: pi(j) enters x(j+1) through M_j = P (I (x) zeta(j)) + D + Q (I (x) u(j)),
  // then propagates with A(j+1), A(j+2), ..., so block (k, j) = C A(k-1) ... A(j+1) M_j for k > j.
  r.xi = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(N + 1) * l, static_cast<Eigen::Index>(N) * q);
  r.transition = Ak;
  r.output_map = model.C;
  for (int j = 0; j < N; ++j) {
    Eigen::MatrixXd G = model.P * kron_identity(q, r.zeta.row(j).transpose()) + model.D +
                        model.Q * kron_identity(q, u.row(j).transpose());
    r.input_map.push_back(G);
    for (int k = j + 1; k <= N; ++k) {
      r.xi.block(static_cast<Eigen::Index>(k) * l, static_cast<Eigen::Index>(j) * q, l, q) = model.C * G;
      if (k < N) G = Ak[static_cast<std::size_t>(k)] * G;
    }
  }
  r.upsilon = stack_samples(r.zeta * model.C.transpose());
  if (!pi_bar.isZero(0)) r.upsilon -= r.xi * stack_samples(pi_bar);
  return r;
}

Eigen::VectorXd stack_samples(const Eigen::Ref<const Eigen::MatrixXd>& signal) {
  Eigen::VectorXd s(signal.size());
  for (Eigen::Index k = 0; k < signal.rows(); ++k) s.segment(k * signal.cols(), signal.cols()) = signal.row(k).transpose();
  return s;
}

Eigen::MatrixXd unstack_samples(const Eigen::Ref<const Eigen::VectorXd>& stacked, int width) {
  if (width <= 0 || stacked.size() % width != 0)
    throw InputError("unstack_samples: " + std::to_string(stacked.size()) + " entries do not split into rows of " +
                     std::to_string(width));
  Eigen::MatrixXd m(stacked.size() / width, width);
  for (Eigen::Index k = 0; k < m.rows(); ++k) m.row(k) = stacked.segment(k * width, width).transpose();
  return m;
}

}  // namespace sets
