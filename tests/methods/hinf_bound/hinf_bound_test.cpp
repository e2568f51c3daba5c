// Tests of hinf_bound (Hakvoort-Van den Hof), the entry point: input checks and the guarantee of the whole procedure (bounded noise):
// src/methods/hinf_bound/hinf_bound.cpp.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <string>

#include "sets/core/error.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"
#include "support/hinf_fixtures.hpp"

using namespace sets;
using namespace sets::testing;

TEST(HinfInput, GridOutsideZeroPiIsRejected) {
  Eigen::VectorXd g = uniform_grid(10);
  EXPECT_NO_THROW(check_frequency_grid(g));
  g[9] = 3.2;
  EXPECT_THROW(check_frequency_grid(g), InputError);
  g = uniform_grid(10);
  g[0] = -0.1;
  try {
    check_frequency_grid(g);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("w[0]"), std::string::npos) << e.what();
  }
  g = uniform_grid(10);
  g[4] = g[3];
  EXPECT_THROW(check_frequency_grid(g), InputError);
}

TEST(HinfInput, RhoMustBeBelowOne) {
  HinfPriors p;
  p.rho = 1.0;
  EXPECT_THROW(check_priors(p), InputError);
  p.rho = 1.5;
  EXPECT_THROW(check_priors(p), InputError);
  p.rho = 0.5;
  p.rho_ic = 1.0;
  EXPECT_THROW(check_priors(p), InputError);
  // ... and the full procedure refuses it too, naming rho.
  Eigen::VectorXd u = Eigen::VectorXd::Random(200), y = Eigen::VectorXd::Random(200);
  HinfPriors q;
  q.rho = 1.0;
  try {
    uncertainty_set(u, y, OrthonormalBasis::fir(), 5, uniform_grid(10), q);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rho"), std::string::npos);
  }
}

// Bounded noise: G0 in every region and ||W (G0 - Ghat)||_inf <= b on a dense grid, always.
RC_GTEST_PROP(HinfWorstCase, TrueSystemIsInsideTheBoundedNoiseSet, ()) {
  const double rho = 0.7, M = 1;
  FirstOrderSum G0;
  const int terms = *rc::gen::inRange(1, 3);
  double csum = 0;
  for (int i = 0; i < terms; ++i) {
    const double c = *rc::gen::inRange(-40, 40) / 100.0, p = *rc::gen::inRange(-65, 65) / 100.0;
    G0.c.push_back(c);
    G0.p.push_back(p);
    csum += std::abs(c);
  }
  RC_PRE(csum > 0.05);  // |g0(k)| <= sum|c_i| |p_i|^k <= 0.8 * 0.65^k <= M rho^k
  const double vbar = *rc::gen::inRange(1, 30) / 100.0;
  std::mt19937_64 rng(*rc::gen::arbitrary<unsigned>());
  std::uniform_real_distribution<double> U(-1, 1);
  const int pre = 100, N = 200;
  Eigen::VectorXd u(pre + N);
  for (auto& x : u) x = U(rng);
  Eigen::VectorXd y = G0.simulate(u);
  for (auto& x : y) x += vbar * U(rng);
  HinfPriors priors;
  priors.M = M;
  priors.rho = rho;
  priors.u_bar = 1;
  HinfBoundOptions opt;
  opt.uncertainty.noise = NoiseModel::bounded;
  opt.uncertainty.v_bar = vbar;
  opt.weight.degree = 6;
  opt.nominal.iterations = 4;  // keeps the property fast; the guarantee does not depend on it
  const Eigen::VectorXd grid = uniform_grid(16);
  const HinfBoundResult R = hinf_bound(HinfData{u.tail(N), y.tail(N), {}},
                                       HinfStructure{OrthonormalBasis::fir(), 8, priors, grid}, opt);
  RC_ASSERT(!R.set.empty());
  for (int j = 0; j < grid.size(); ++j) RC_ASSERT(R.set.regions[j].contains(G0(grid[j])));
  const auto G = [&](double w) { return G0(w); };
  RC_ASSERT(weighted_error(G, R.nominal.model, R.weight.h, 2048) <= R.bound.b);
  RC_ASSERT(weighted_error(G, R.nominal.model, Eigen::VectorXd::Ones(1), 2048) <= R.unweighted.b);
  RC_ASSERT(R.bound.b >= R.bound.b_grid);
  // The data-based bound: the coefficient box holds theta0 (FIR: g0(k) = sum_i c_i p_i^k), and
  // b_data bounds the true weighted error on a dense grid (4096 points: 256 per grid cell).
  for (int k = 0; k < 8; ++k) {
    double g = 0;
    for (int i = 0; i < terms; ++i) g += G0.c[i] * std::pow(G0.p[i], k);
    RC_ASSERT(std::abs(g - R.set.theta_ref[k]) <= R.set.theta_radius[k]);
  }
  RC_ASSERT(std::isfinite(R.bound.b_data));
  RC_ASSERT(R.bound.b_data >= R.bound.b_grid);
  RC_ASSERT(weighted_error(G, R.nominal.model, R.weight.h, 4096) <= R.bound.b_data);
  RC_ASSERT(weighted_error(G, R.nominal.model, Eigen::VectorXd::Ones(1), 4096) <= R.unweighted.b_data);
}

TEST(HinfWorstCase, FalsifiedPriorsGiveAnEmptySet) {
  const HinfBoundResult R = first_order_run(5, 0.5, 0.01, NoiseModel::bounded);  // noise far above the claimed bound
  EXPECT_TRUE(R.set.empty());
  EXPECT_EQ(R.set.consistency.falsified, sets::Falsified::yes);
  EXPECT_FALSE(R.set.consistency.conflict.samples.empty());  // which samples conflict, for the user
  EXPECT_NE(R.set.consistency.message().find("falsify"), std::string::npos) << R.set.consistency.message();
}

TEST(HinfWorstCase, ConsistentDataSayNotFalsifiedAndTheStochasticModelDoesNotAsk) {
  const HinfBoundResult R = first_order_run(6, 0.01, 0.02, NoiseModel::bounded);  // inside the claimed bound
  EXPECT_FALSE(R.set.empty());
  EXPECT_NE(R.set.consistency.falsified, sets::Falsified::yes);
  EXPECT_EQ(first_order_run(6, 0.01, 0.02, NoiseModel::stochastic).set.consistency.falsified, sets::Falsified::unknown);
}
