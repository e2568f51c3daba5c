// Orthonormal bases (FIR, Laguerre, Kautz): orthonormal impulse responses, frequency responses
// that are their transforms, and the sup/derivative bounds the H-infinity method relies on.

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <complex>
#include <numbers>

#include "sets/core/error.hpp"
#include "sets/models/orthonormal_basis.hpp"

using namespace sets;
using cd = std::complex<double>;
constexpr double pi = std::numbers::pi;

namespace {

std::vector<OrthonormalBasis> bases() {
  return {OrthonormalBasis::fir(), OrthonormalBasis::laguerre(0.6), OrthonormalBasis::laguerre(-0.3),
          OrthonormalBasis::kautz(std::polar(0.9, 0.7))};
}

}  // namespace

TEST(HinfBasis, ImpulseResponsesAreOrthonormal) {
  for (const auto& B : bases()) {
    const Eigen::MatrixXd F = B.impulse_responses(3000, 10);
    const Eigen::MatrixXd G = F.transpose() * F;
    EXPECT_LT((G - Eigen::MatrixXd::Identity(10, 10)).cwiseAbs().maxCoeff(), 1e-8) << B.describe();
  }
}

TEST(HinfBasis, FrequencyResponseIsTheTransformOfTheImpulseResponse) {
  for (const auto& B : bases()) {
    const Eigen::MatrixXd F = B.impulse_responses(3000, 6);
    for (double w : {0.0, 0.4, 1.3, 3.0}) {
      const Eigen::VectorXcd Fw = B.frequency_responses(w, 6);
      for (int k = 0; k < 6; ++k) {
        cd s = 0;
        for (int t = 0; t < F.rows(); ++t) s += F(t, k) * std::polar(1.0, -w * t);
        EXPECT_LT(std::abs(s - Fw[k]), 1e-8) << B.describe() << " k=" << k << " w=" << w;
      }
    }
  }
}

TEST(HinfBasis, SupAndDerivativeBoundsHoldOnADenseGrid) {
  for (const auto& B : bases()) {
    const int K = 30, m = B.block();
    const double H0 = B.hinf_bound(), D0 = B.front_derivative_bound(), Lp = B.allpass_derivative_bound();
    const double h = 1e-6;
    for (int i = 0; i <= 3000; ++i) {
      const double w = pi * i / 3000;
      const Eigen::VectorXcd F = B.frequency_responses(w, K);
      const Eigen::VectorXcd Fp = (B.frequency_responses(w + h, K) - B.frequency_responses(w - h, K)) / (2 * h);
      for (int k = 0; k < K; ++k) {
        ASSERT_LE(std::abs(F[k]), H0 * (1 + 1e-12)) << B.describe();
        ASSERT_LE(std::abs(Fp[k]), (D0 + (k / m) * H0 * Lp) * (1 + 1e-5) + 1e-6) << B.describe() << " k=" << k;
      }
    }
  }
}

TEST(HinfBasis, BadPolesAreInputErrors) {
  EXPECT_THROW(OrthonormalBasis::laguerre(1.0), InputError);
  EXPECT_THROW(OrthonormalBasis::laguerre(-1.2), InputError);
  EXPECT_THROW(OrthonormalBasis::kautz(cd(0.5, 0)), InputError);
  EXPECT_THROW(OrthonormalBasis::kautz(std::polar(1.0, 0.3)), InputError);
}
