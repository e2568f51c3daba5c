// Tests of hinf_bound (Hakvoort-Van den Hof), step 1, the frequency-domain uncertainty set (regions, coefficient box, tail, stochastic sets):
// src/methods/hinf_bound/uncertainty_set.cpp.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

#include "sets/core/error.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"
#include "support/hinf_fixtures.hpp"

using namespace sets;
using namespace sets::testing;

TEST(HinfInput, DataAndOrderChecks) {
  Eigen::VectorXd u = Eigen::VectorXd::Random(100), y = Eigen::VectorXd::Random(99);
  HinfPriors p;
  EXPECT_THROW(uncertainty_set(u, y, OrthonormalBasis::fir(), 5, uniform_grid(10), p), InputError);
  y = Eigen::VectorXd::Random(100);
  EXPECT_THROW(uncertainty_set(u, y, OrthonormalBasis::fir(), 0, uniform_grid(10), p), InputError);
  EXPECT_THROW(uncertainty_set(u, y, OrthonormalBasis::fir(), 60, uniform_grid(10), p), InputError);
  // Laguerre/Kautz need the impulse-response prior for the initial conditions.
  EXPECT_THROW(uncertainty_set(u, y, OrthonormalBasis::laguerre(0.5), 5, uniform_grid(10), p), InputError);
  UncertaintyOptions o;
  o.alpha = 1.0;
  EXPECT_THROW(uncertainty_set(u, y, OrthonormalBasis::fir(), 5, uniform_grid(10), p, o), InputError);
}

RC_GTEST_PROP(HinfRegion, MaxDistanceBoundsEveryPointOfTheRegion, ()) {
  const double a = *rc::gen::inRange(1, 100) / 10.0, b = *rc::gen::inRange(1, 100) / 10.0;
  const double rot = *rc::gen::inRange(0, 628) / 100.0;
  FrequencyRegion P;
  P.centre = cd(*rc::gen::inRange(-50, 50) / 10.0, *rc::gen::inRange(-50, 50) / 10.0);
  const cd p(*rc::gen::inRange(-50, 50) / 10.0, *rc::gen::inRange(-50, 50) / 10.0);
  const bool ellipse = *rc::gen::arbitrary<bool>();
  Eigen::Matrix2d R;
  R << std::cos(rot), -std::sin(rot), std::sin(rot), std::cos(rot);
  if (ellipse) {
    P.shape = RegionShape::ellipse;
    P.Q = R * Eigen::Vector2d(a * a, b * b).asDiagonal() * R.transpose();
  } else {
    P.half_re = a;
    P.half_im = b;
  }
  const double d = P.max_distance(p);
  std::mt19937_64 rng(*rc::gen::arbitrary<unsigned>());
  std::uniform_real_distribution<double> U(-1, 1);
  double far = 0;
  for (int i = 0; i < 2000; ++i) {
    Eigen::Vector2d x(U(rng), U(rng));
    if (ellipse) {
      if (x.norm() > 1) x /= x.norm();  // boundary points too
      x = R * Eigen::Vector2d(a * x[0], b * x[1]);
    } else {
      x = Eigen::Vector2d(a * x[0], b * x[1]);
      if (i < 4) x = Eigen::Vector2d(i % 2 ? a : -a, i / 2 ? b : -b);
    }
    const cd g = P.centre + cd(x[0], x[1]);
    RC_ASSERT(P.contains(g, 1e-9));
    far = std::max(far, std::abs(g - p));
  }
  if (ellipse)  // the farthest point is on the boundary: sample it densely for the tightness check
    for (int i = 0; i < 4096; ++i) {
      const Eigen::Vector2d x = R * Eigen::Vector2d(a * std::cos(2 * pi * i / 4096), b * std::sin(2 * pi * i / 4096));
      far = std::max(far, std::abs(P.centre + cd(x[0], x[1]) - p));
    }
  RC_ASSERT(far <= d * (1 + 1e-12));
  RC_ASSERT(d <= far * 1.01 + 1e-9);  // and it is tight
}

// The tail slope bound: T = sum_{k>=n} M rho^k F_k with all coefficients at the prior's edge
// (FIR: T = M rho^n z^-(n+1) / (1 - rho z^-1)); its derivative on a dense grid stays below tail_beta,
// and tail_beta falls like rho^n.
TEST(HinfDataBound, TailSlopeBoundHolds) {
  for (const int n : {4, 10, 20}) {
    HinfPriors p;
    p.M = 1.5;
    p.rho = 0.8;
    p.u_bar = 0;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    Eigen::VectorXd u(200), y(200);
    for (auto& x : u) x = U(rng);
    for (auto& x : y) x = U(rng);
    const UncertaintySet S = uncertainty_set(u, y, OrthonormalBasis::fir(), n, uniform_grid(5), p);
    double slope = 0;
    for (int i = 0; i <= 20000; ++i) {
      const double w = pi * i / 20000, h = 1e-6;
      auto T = [&](double x) {
        const cd z = std::polar(1.0, -x);
        return p.M * std::pow(p.rho, n) * std::pow(z, n + 1) / (1.0 - p.rho * z);
      };
      slope = std::max(slope, std::abs(T(w + h) - T(w - h)) / (2 * h));
    }
    EXPECT_LE(slope, S.tail_beta * (1 + 1e-6)) << "n = " << n;  // equality at w = 0 for FIR
    EXPECT_LE(S.tail_beta, 3 * slope) << "n = " << n;  // not wildly pessimistic for FIR
  }
}

// Stochastic noise: a small Monte Carlo. With alpha = 0.9 simultaneous over the grid, at most
// 10% of the runs may have a region that misses G0; 40 runs allow 4 + 3 sd = 10 (the app runs 200+).
TEST(HinfStochastic, RegionsCoverTheTrueSystemAtTheStatedLevel) {
  const FirstOrderSum G0{{0.4, 0.2}, {0.6, -0.5}};
  const HinfPriors p{.M = 1, .rho = 0.7, .u_bar = 1};
  const Eigen::VectorXd grid = uniform_grid(30);
  ColouredNoiseRuns data(G0, 11);
  int miss = 0, ellipse_miss = 0;
  const int runs = 40;
  for (int r = 0; r < runs; ++r) {
    const auto [u, y] = data.next();
    UncertaintyOptions o;
    o.alpha = 0.9;
    const UncertaintySet S = uncertainty_set(u.tail(500), y.tail(500), OrthonormalBasis::fir(), 10, grid, p, o);
    o.shape = RegionShape::ellipse;
    const UncertaintySet E = uncertainty_set(u.tail(500), y.tail(500), OrthonormalBasis::fir(), 10, grid, p, o);
    bool m = false, me = false;
    for (int j = 0; j < grid.size(); ++j) {
      m |= !S.regions[j].contains(G0(grid[j]));
      me |= !E.regions[j].contains(G0(grid[j]));
    }
    miss += m;
    ellipse_miss += me;
    // The ellipse is no wider than the rectangle's circumscribing box times sqrt(2) (sanity).
    EXPECT_GT(S.terms[0].noise_re, 0);
  }
  EXPECT_LE(miss, 10);
  EXPECT_LE(ellipse_miss, 10);
}

// Closed loop: u = r - 0.3 y correlates u with the noise; IV with the reference stays close to
// G0 where least squares is biased.
TEST(HinfStochastic, InstrumentalVariablesRemoveTheClosedLoopBias) {
  const FirstOrderSum G0{{0.8}, {0.5}};
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> U(-1, 1);
  std::normal_distribution<double> Nn(0, 0.5);
  const int N = 6000;
  Eigen::VectorXd r(N), u(N), y(N), v(N);
  for (auto& x : r) x = U(rng);
  double xs = 0, e1 = 0;
  for (int t = 0; t < N; ++t) {
    const double e = Nn(rng);
    v[t] = e + 0.9 * e1;  // MA(1) noise: correlated with the feedback
    e1 = e;
    y[t] = 0.8 * xs + v[t];
    u[t] = r[t] - 0.3 * y[t];
    xs = 0.5 * xs + u[t];
  }
  HinfPriors p;
  p.M = 1;
  p.rho = 0.6;
  p.u_bar = 2;
  const Eigen::VectorXd grid = uniform_grid(8);
  const UncertaintySet ls = uncertainty_set(u, y, OrthonormalBasis::fir(), 12, grid, p);
  const UncertaintySet iv = uncertainty_set(u, y, OrthonormalBasis::fir(), 12, grid, p, {}, r);
  double els = 0, eiv = 0;
  for (int j = 0; j < grid.size(); ++j) {
    els = std::max(els, std::abs(ls.estimate[j] - G0(grid[j])));
    eiv = std::max(eiv, std::abs(iv.estimate[j] - G0(grid[j])));
  }
  EXPECT_LT(eiv, els);
  EXPECT_LT(eiv, 0.15);
}
