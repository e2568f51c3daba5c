// The example of sets-hinf-bound: the true system's poles, the simulated data, and priors that
// hold for the system they were derived from.

#include <gtest/gtest.h>

#include "sets/examples/hakvoort.hpp"

TEST(HakvoortExample, PolesAreThePrintedOnes) {
  const auto G = sets::hakvoort::system();
  const Eigen::VectorXcd p = G.poles();
  ASSERT_EQ(p.size(), 4);
  int resonance = 0;
  for (const auto z : p) resonance += std::abs(std::abs(z) - 0.97) < 1e-9 && std::abs(std::abs(std::arg(z)) - 0.6) < 1e-9;
  EXPECT_EQ(resonance, 2);
  EXPECT_TRUE(G.stable());
}

TEST(HakvoortExample, BoundedNoiseStaysBelowItsFilteredBound) {
  const auto G = sets::hakvoort::system();
  std::mt19937_64 rng(2);
  const auto d = sets::hakvoort::simulate(G, 500, 0.02, true, rng);
  ASSERT_EQ(d.u.size(), 500);
  EXPECT_LE(d.u.cwiseAbs().maxCoeff(), 1.0);
  std::mt19937_64 same(2);
  const auto clean = sets::hakvoort::simulate(G, 500, 0.0, true, same);  // same u, no noise
  EXPECT_EQ(clean.u, d.u);
  EXPECT_LE((d.y - clean.y).cwiseAbs().maxCoeff(), 0.02 / 0.3);
}

TEST(HakvoortExample, DerivedPriorsHoldForTheSystem) {
  const auto G = sets::hakvoort::system();
  sets::HinfPriors given;
  given.rho = 0.88, given.M = -1, given.M_ic = -1, given.rho_ic = -1;
  std::string note;
  const auto p = sets::hakvoort::priors_for(G, sets::OrthonormalBasis::fir(), given, note);
  EXPECT_NE(note.find("(holds)"), std::string::npos) << note;
  EXPECT_DOUBLE_EQ(p.rho_ic, 0.975);
  // FIR basis: g0(k) is the impulse response h0(k+1); the prior dominates it over the 200
  // coefficients it was derived from. (Not beyond: G0's resonance decays as 0.97^k, slower than
  // rho = 0.88, so with the FIR basis no M makes the prior hold for every k.)
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(201);
  delta[0] = 1;
  const Eigen::VectorXd h = sets::TransferFunction{G.b, G.a, {}}.filter(delta);
  for (int k = 0; k < 200; ++k) EXPECT_LE(std::abs(h[k + 1]), p.M * std::pow(p.rho, k)) << k;
  sets::check_priors(p);
}
