#pragma once
// A seeded source of uniform numbers and matrices for property tests.

#include <Eigen/Core>

#include <cstdint>
#include <random>

namespace sets::test {

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  /// Uniform in [lo, hi).
  double u(double lo = -1, double hi = 1) { return std::uniform_real_distribution<double>(lo, hi)(g); }
  /// r x c entries uniform in [-1, 1).
  Eigen::MatrixXd mat(Eigen::Index r, Eigen::Index c) {
    return Eigen::MatrixXd::NullaryExpr(r, c, [&] { return u(); });
  }
};

}  // namespace sets::test
