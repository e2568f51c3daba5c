#include "sets/methods/tv_bound/window_norm.hpp"

#include <cmath>
#include <string>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"

namespace sets {

WindowNorm::WindowNorm(Eigen::VectorXd weights) : w_(std::move(weights)) {
  if (w_.size() == 0) throw InputError("WindowNorm: the window is empty");
  for (Eigen::Index k = 0; k < w_.size(); ++k) {
    if (!std::isfinite(w_[k]) || w_[k] < 0)
      throw InputError("WindowNorm: w(" + std::to_string(k) + ") = " + std::to_string(w_[k]) +
                       " is not a finite non-negative number");
    if (k > 0 && w_[k] > w_[k - 1])
      throw InputError("WindowNorm: the window increases at sample " + std::to_string(k) + " (w(" +
                       std::to_string(k - 1) + ") = " + std::to_string(w_[k - 1]) + " < w(" + std::to_string(k) +
                       ") = " + std::to_string(w_[k]) + "); equation (7) needs a monotone non-increasing window");
  }
  if (w_[0] == 0) throw InputError("WindowNorm: the window is identically zero");
}

WindowNorm WindowNorm::pulse(int length, double height) {
  if (length <= 0) throw InputError("WindowNorm::pulse: length " + std::to_string(length) + " must be positive");
  return WindowNorm(Eigen::VectorXd::Constant(length, height));
}

double WindowNorm::operator()(const Eigen::Ref<const Eigen::VectorXd>& v) const {
  double best = 0;
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    double s = 0;
    for (Eigen::Index d = 0; d < w_.size() && d <= k; ++d) s += w_[d] * std::abs(v[k - d]);
    best = std::max(best, s);
  }
  return best;
}

Eigen::SparseMatrix<double, Eigen::RowMajor> WindowNorm::toeplitz(int samples) const {
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < samples; ++k)
    for (int d = 0; d < w_.size() && d <= k; ++d)
      if (w_[d] != 0) t.emplace_back(k, k - d, w_[d]);
  Eigen::SparseMatrix<double, Eigen::RowMajor> W(samples, samples);
  W.setFromTriplets(t.begin(), t.end());
  return W;
}

WindowNormBall::WindowNormBall(std::vector<WindowNorm> windows, int samples)
    : windows_(std::move(windows)), samples_(samples) {
  if (windows_.empty()) throw InputError("WindowNormBall: no window given (need one per output)");
  if (samples_ <= 0) throw InputError("WindowNormBall: the number of samples must be positive");
}

void WindowNormBall::check_size(Eigen::Index n, const char* what) const {
  const Eigen::Index want = static_cast<Eigen::Index>(samples_) * outputs();
  if (n != want)
    throw InputError(std::string("WindowNormBall: ") + what + " has " + std::to_string(n) + " entries, expected " +
                     std::to_string(want) + " (" + std::to_string(samples_) + " samples x " +
                     std::to_string(outputs()) + " outputs)");
}

Eigen::VectorXd WindowNormBall::norms(const Eigen::Ref<const Eigen::VectorXd>& V) const {
  check_size(V.size(), "the signal");
  const int l = outputs();
  Eigen::VectorXd out(l);
  for (int j = 0; j < l; ++j) {
    Eigen::VectorXd vj(samples_);
    for (int k = 0; k < samples_; ++k) vj[k] = V[static_cast<Eigen::Index>(k) * l + j];
    out[j] = windows_[j](vj);
  }
  return out;
}

bool WindowNormBall::contains(const Eigen::Ref<const Eigen::VectorXd>& V, const Eigen::Ref<const Eigen::VectorXd>& eps,
                              double tolerance) const {
  if (eps.size() != outputs()) throw InputError("WindowNormBall::contains: eps needs one entry per output");
  return ((norms(V) - eps).array() <= tolerance).all();
}

HPolytope WindowNormBall::lifted_polytope(const Eigen::Ref<const Eigen::VectorXd>& eps) const {
  if (eps.size() != outputs()) throw InputError("WindowNormBall::lifted_polytope: eps needs one entry per output");
  const int l = outputs(), m = samples_ * l;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * m, 2 * m);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(3 * m);
  A.topLeftCorner(m, m).setIdentity();                     //  V - T <= 0
  A.block(0, m, m, m) = -Eigen::MatrixXd::Identity(m, m);
  A.block(m, 0, m, m) = -Eigen::MatrixXd::Identity(m, m);  // -V - T <= 0
  A.block(m, m, m, m) = -Eigen::MatrixXd::Identity(m, m);
  for (int j = 0; j < l; ++j) {
    const auto& w = windows_[j].weights();
    for (int k = 0; k < samples_; ++k) {
      for (int d = 0; d < w.size() && d <= k; ++d) A(2 * m + k * l + j, m + (k - d) * l + j) = w[d];
      b[2 * m + k * l + j] = eps[j];
    }
  }
  return HPolytope(A, b);
}

WindowNormBall::LpBlock WindowNormBall::add_to(LinearProgram& lp, const Eigen::Ref<const Eigen::VectorXd>& offset,
                                               const Eigen::Ref<const Eigen::MatrixXd>& map, int first_col,
                                               const Eigen::Ref<const Eigen::VectorXd>& eps_fixed) const {
  check_size(offset.size(), "the offset");
  check_size(map.rows(), "the map");
  if (first_col < 0 || first_col + map.cols() > lp.num_variables())
    throw InputError("WindowNormBall::add_to: the map's columns are not variables of the LP");
  const bool fixed = eps_fixed.size() > 0;
  if (fixed && (eps_fixed.size() != outputs() || (eps_fixed.array() < 0).any()))
    throw InputError("WindowNormBall::add_to: eps needs one non-negative entry per output");
  const int l = outputs(), m = samples_ * l;
  LpBlock blk;
  blk.first_t = lp.add_variables(m, 0, inf);
  if (!fixed) blk.first_eps = lp.add_variables(l, 0, inf);
  blk.first_row = lp.num_rows();
  // |offset - map x| <= T  <=>  map x + T >= offset  and  map x - T <= offset.
  for (int r = 0; r < m; ++r) {
    std::vector<std::pair<int, double>> row;
    for (Eigen::Index c = 0; c < map.cols(); ++c)
      if (map(r, c) != 0) row.emplace_back(first_col + static_cast<int>(c), map(r, c));
    row.emplace_back(blk.first_t + r, 1.0);
    lp.add_row(row, offset[r], inf);
    row.back().second = -1.0;
    lp.add_row(row, -inf, offset[r]);
  }
  // W T <= 1 (x) eps, row by row.
  for (int j = 0; j < l; ++j) {
    const auto& w = windows_[j].weights();
    for (int k = 0; k < samples_; ++k) {
      std::vector<std::pair<int, double>> row;
      for (int d = 0; d < w.size() && d <= k; ++d)
        if (w[d] != 0) row.emplace_back(blk.first_t + (k - d) * l + j, w[d]);
      if (fixed) {
        lp.add_row(row, -inf, eps_fixed[j]);
      } else {
        row.emplace_back(blk.first_eps + j, -1.0);
        lp.add_row(row, -inf, 0.0);
      }
    }
  }
  blk.num_rows = lp.num_rows() - blk.first_row;
  return blk;
}

}  // namespace sets
