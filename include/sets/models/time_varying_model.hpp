#pragma once
// State-space models with affine time-varying parameter perturbations (Salehpour & Johansson,
// equation 1) and their biaffine input/output approximation (equations 2-4).
//
//   x(k+1) = A x(k) + B u(k) + P (pi(k) (x) x(k)) + D pi(k) + Q (pi(k) (x) u(k))
//   y(k)   = C x(k) + eta(k)
//
// pi(k) in R^q is the deviation of the parameters from their nominal values; (x) is the
// Kronecker product, so pi (x) x = (I_q (x) x) pi stacks pi_1 x, ..., pi_q x.
//
// Signals are matrices with one row per sample: u is N x p (u(0..N-1)), pi is N x q
// (pi(0..N-1)), y is (N+1) x l (y(0..N)).

#include <Eigen/Core>

#include <vector>

namespace sets {

/// The matrices of equation (1). P is n x nq, D is n x q, Q is n x qp.
struct TimeVaryingModel {
  Eigen::MatrixXd A, B, C, P, D, Q;

  int states() const { return static_cast<int>(A.rows()); }
  int inputs() const { return static_cast<int>(B.cols()); }
  int outputs() const { return static_cast<int>(C.rows()); }
  int parameters() const { return static_cast<int>(D.cols()); }

  /// Throws InputError naming the matrix whose size disagrees with A (n), B (p), C (l) and D (q),
  /// or that holds a non-finite entry.
  void validate() const;
};

/// The trajectory of (1) without noise: x is (N+1) x n, y is (N+1) x l.
struct TimeVaryingSimulation {
  Eigen::MatrixXd x;
  Eigen::MatrixXd y;
};

/// Simulates (1) exactly (bilinear in pi and x) from x(0) = x0 with the input u (N x p) and the
/// perturbation pi (N x q). Throws InputError on mismatched dimensions.
TimeVaryingSimulation simulate(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                               const Eigen::Ref<const Eigen::MatrixXd>& u, const Eigen::Ref<const Eigen::MatrixXd>& pi);

/// The stacked biaffine regression Y = Upsilon + Xi Pi + V of equation (4), where
/// Xi = Omega + Psi + Phi (the D-, P- and Q-terms of equation 3) and Pi = [pi(0); ...; pi(N-1)].
/// Stacking: row k*l + j is output j at sample k; column k*q + i is parameter i at sample k.
///
/// linearised_regression generalises it to an expansion around a perturbation trajectory pi_bar
/// (not in the paper): Y = Upsilon + Xi Pi + V still holds with Pi the absolute perturbation, but
/// zeta is then the state of (1) under pi_bar and Upsilon = C zeta - Xi Pi_bar (the constant term).
struct BiaffineRegression {
  Eigen::MatrixXd zeta;     // state trajectory at the linearisation point, (N+1) x n (nominal for (2))
  Eigen::VectorXd upsilon;  // constant term, (N+1) l: C zeta(k) stacked for (2), C zeta - Xi Pi_bar otherwise
  Eigen::MatrixXd xi;       // (N+1) l x N q, block lower triangular (first block row is zero)
  Eigen::MatrixXd pi_bar;   // linearisation point, N x q (zero for (2))
  /// The recursion behind Xi, for solvers that prefer its sparse rows to the dense Xi (filled by
  /// biaffine_regression and linearised_regression; empty when Xi was built some other way):
  ///   s(0) = 0,  s(k+1) = transition[k] s(k) + input_map[k] pi(k),  (Xi Pi)(k) = output_map s(k).
  std::vector<Eigen::MatrixXd> transition;  // A(k), n x n, k = 0..N-1
  std::vector<Eigen::MatrixXd> input_map;   // M_k, n x q, k = 0..N-1
  Eigen::MatrixXd output_map;               // C, l x n

  int samples() const { return static_cast<int>(zeta.rows()) - 1; }  // N
};

/// Builds Upsilon and Xi of (3)-(4) for the nominal model, x(0) = x0 and the input u (N x p).
/// Throws InputError on mismatched dimensions or an empty input.
BiaffineRegression biaffine_regression(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                                       const Eigen::Ref<const Eigen::MatrixXd>& u);

/// The first-order expansion of (1) in pi around the trajectory pi_bar (N x q), an extension of (2)
/// for re-linearisation (not in the paper). With x_bar = simulate(pi_bar).x:
///   A(k) = A + P (pi_bar(k) (x) I_n),   M_k = P (I_q (x) x_bar(k)) + D + Q (I_q (x) u(k)),
///   block (k, j) of Xi = C A(k-1) ... A(j+1) M_j  (k > j),   Upsilon = C x_bar - Xi Pi_bar,
/// so y(pi) = Upsilon + Xi Pi + O(|pi - pi_bar|^2). pi_bar = 0 gives biaffine_regression exactly.
/// Throws InputError on mismatched dimensions or an empty input.
BiaffineRegression linearised_regression(const TimeVaryingModel& model, const Eigen::Ref<const Eigen::VectorXd>& x0,
                                         const Eigen::Ref<const Eigen::MatrixXd>& u,
                                         const Eigen::Ref<const Eigen::MatrixXd>& pi_bar);

/// Stacks the rows of a signal matrix (one row per sample) into one column: [s(0); s(1); ...].
Eigen::VectorXd stack_samples(const Eigen::Ref<const Eigen::MatrixXd>& signal);
/// The inverse of stack_samples: width entries per sample.
Eigen::MatrixXd unstack_samples(const Eigen::Ref<const Eigen::VectorXd>& stacked, int width);

}  // namespace sets
