#include "sets/models/transfer_function.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sets/models/orthonormal_basis.hpp"

namespace {
using sets::TransferFunction;
using cd = std::complex<double>;
constexpr double pi = std::numbers::pi;

// (0.5 + 0.2 z^-1) / (1 - 1.2 z^-1 + 0.72 z^-2): poles 0.6 +- 0.6i, |p| = 0.6 sqrt 2.
TransferFunction example() { return {Eigen::Vector2d(0.5, 0.2), Eigen::Vector3d(1, -1.2, 0.72), {}}; }

TEST(TransferFunction, EvaluatesTheRationalFunctionOnTheUnitCircle) {
  const TransferFunction G = example();
  for (double w : {0.0, 0.3, 1.7, pi}) {
    const cd z = std::polar(1.0, w);
    const cd expect = (0.5 + 0.2 / z) / (1.0 - 1.2 / z + 0.72 / (z * z));
    EXPECT_NEAR(std::abs(G(w) - expect), 0, 1e-13) << w;
  }
}

TEST(TransferFunction, DerivativeMatchesFiniteDifferences) {
  const TransferFunction G = example();
  for (double w : {0.2, 0.8, 2.5}) {
    const double h = 1e-6;
    const cd fd = (G(w + h) - G(w - h)) / (2 * h);
    EXPECT_NEAR(std::abs(G.derivative(w) - fd), 0, 1e-6) << w;
  }
}

TEST(TransferFunction, PolesAndStability) {
  const Eigen::VectorXcd p = example().poles();
  ASSERT_EQ(p.size(), 2);
  for (Eigen::Index i = 0; i < 2; ++i) EXPECT_NEAR(std::abs(p[i]), 0.6 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(std::abs(p[0].real()), 0.6, 1e-12);
  EXPECT_TRUE(example().stable());
  EXPECT_FALSE(example().stable(0.2));  // 0.849 > 1 - 0.2
  const TransferFunction unstable{Eigen::VectorXd::Ones(1), Eigen::Vector2d(1, -1.1), {}};
  EXPECT_FALSE(unstable.stable());
}

TEST(TransferFunction, FilterGivesTheImpulseResponse) {
  // 1 / (1 - 0.5 z^-1): h(s) = 0.5^s.
  const TransferFunction G{Eigen::VectorXd::Ones(1), Eigen::Vector2d(1, -0.5), {0.5}};
  Eigen::VectorXd d = Eigen::VectorXd::Zero(10);
  d[0] = 1;
  const Eigen::VectorXd h = G.filter(d);
  for (int s = 0; s < 10; ++s) EXPECT_DOUBLE_EQ(h[s], std::pow(0.5, s));
}

TEST(TransferFunction, SupremumBoundsHoldOnADenseGrid) {
  // With and without known pole moduli (the bases' case and the general one).
  TransferFunction with = example();
  with.pole_moduli = {0.6 * std::sqrt(2.0), 0.6 * std::sqrt(2.0)};
  for (const TransferFunction& G : {example(), with}) {
    const double H = G.hinf_bound(), D = G.derivative_bound();
    double hmax = 0, dmax = 0;
    for (int i = 0; i <= 100000; ++i) {
      const double w = pi * i / 100000;
      hmax = std::max(hmax, std::abs(G(w)));
      dmax = std::max(dmax, std::abs(G.derivative(w)));
    }
    EXPECT_GE(H, hmax);
    EXPECT_LE(H, 1.01 * hmax);  // tight: grid maximum plus a small remainder
    EXPECT_GE(D, dmax);
  }
}

TEST(TransferFunction, PrintsNumeratorOverDenominator) {
  EXPECT_EQ(example().to_string(), "(0.5 + 0.2 z^-1) / (1 - 1.2 z^-1 + 0.72 z^-2)");
}

TEST(TransferFunction, TheBasesAreBuiltOfIt) {
  const sets::OrthonormalBasis B = sets::OrthonormalBasis::laguerre(0.5);
  const TransferFunction& f = B.fronts()[0];
  EXPECT_NEAR(std::abs(B.frequency_responses(0.7, 1)[0] - f(0.7)), 0, 1e-15);
}

}  // namespace
