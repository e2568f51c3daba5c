#pragma once
// Discrete window norms (Salehpour & Johansson, Definition 1 and equation 5) and the
// window-norm ball of equation (7) as a polytope with auxiliary variables T >= |V|.
//
//   ||v||_w = max_k sum_{i=0..k} w(k-i) |v(i)|
//
// A window here is a finite sequence w(0), ..., w(L-1) (zero afterwards), non-negative, not all
// zero and monotone non-increasing: the derivation of (7) from the norm needs the monotonicity.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

#include "sets/domains/hpolytope.hpp"

namespace sets {

class LinearProgram;

class WindowNorm {
 public:
  /// Throws InputError if the window is empty, has a negative or non-finite entry, is all zero
  /// or increases anywhere (naming the first offending sample).
  explicit WindowNorm(Eigen::VectorXd weights);
  /// The pulse w(k) = height for 0 <= k < length (the crane example: length 36, height 1/35).
  static WindowNorm pulse(int length, double height);

  const Eigen::VectorXd& weights() const { return w_; }
  int length() const { return static_cast<int>(w_.size()); }

  /// ||v||_w of a finite signal v(0..K) (equation 5).
  double operator()(const Eigen::Ref<const Eigen::VectorXd>& v) const;
  /// The (K+1) x (K+1) lower-triangular Toeplitz matrix W with W(k, i) = w(k - i).
  Eigen::SparseMatrix<double, Eigen::RowMajor> toeplitz(int samples) const;

 private:
  Eigen::VectorXd w_;
};

/// The window-norm ball { V : ||nu_j||_w_j <= eps_j, j = 1..l } over samples 0..N, V stacked as in
/// time_varying_model.hpp (row k*l + j). Written as the polytope (7) lifted by T >= |V|:
///   -T <= V <= T,  W T <= 1 (x) eps,
/// whose projection on V is exactly the ball (W is non-negative).
class WindowNormBall {
 public:
  /// One window per output (l = windows.size()); throws InputError if there are none or
  /// samples <= 0.
  WindowNormBall(std::vector<WindowNorm> windows, int samples);

  int outputs() const { return static_cast<int>(windows_.size()); }
  int samples() const { return samples_; }  // N + 1
  const std::vector<WindowNorm>& windows() const { return windows_; }

  /// The window norm of each output of the stacked signal V.
  Eigen::VectorXd norms(const Eigen::Ref<const Eigen::VectorXd>& V) const;
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& V, const Eigen::Ref<const Eigen::VectorXd>& eps,
                double tolerance = 0) const;
  /// The lifted polytope in (V, T) coordinates (dense; for small problems and tests).
  HPolytope lifted_polytope(const Eigen::Ref<const Eigen::VectorXd>& eps) const;

  /// Where add_to put its variables and rows.
  struct LpBlock {
    int first_t = -1;        // T occupies columns first_t .. first_t + samples*outputs - 1
    int first_eps = -1;      // eps columns (-1 when eps was fixed)
    int first_row = -1;
    int num_rows = 0;
  };
  /// Adds the constraint "offset - map * x[first_col ..] lies in the ball" to lp, with T as new
  /// variables. eps is either fixed (eps_fixed, size l) or, when eps_fixed is empty, l new
  /// non-negative variables. Throws InputError on mismatched sizes.
  LpBlock add_to(LinearProgram& lp, const Eigen::Ref<const Eigen::VectorXd>& offset,
                 const Eigen::Ref<const Eigen::MatrixXd>& map, int first_col,
                 const Eigen::Ref<const Eigen::VectorXd>& eps_fixed = Eigen::VectorXd()) const;

 private:
  void check_size(Eigen::Index n, const char* what) const;
  std::vector<WindowNorm> windows_;
  int samples_;
};

}  // namespace sets
