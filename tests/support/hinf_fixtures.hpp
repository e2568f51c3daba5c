#pragma once
// Test fixtures shared by the hinf_bound tests (one file per step of src/methods/hinf_bound/).
// expect_a_valid_weight asserts with GoogleTest: include only from tests.

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "sets/examples/hakvoort.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"

namespace sets::testing {

inline constexpr double pi = std::numbers::pi;
using cd = std::complex<double>;

// A grid of n frequencies at the midpoints of n equal cells of [0, pi].
inline Eigen::VectorXd uniform_grid(int n) {
  Eigen::VectorXd g(n);
  for (int j = 0; j < n; ++j) g[j] = pi * (j + 0.5) / n;
  return g;
}

// G0 = sum_i c_i z^-1 / (1 - p_i z^-1): FIR coefficients g0(k) = sum_i c_i p_i^k.
struct FirstOrderSum {
  std::vector<double> c, p;
  cd operator()(double w) const {
    const cd z = std::polar(1.0, -w);
    cd s = 0;
    for (size_t i = 0; i < c.size(); ++i) s += c[i] * z / (1.0 - p[i] * z);
    return s;
  }
  Eigen::VectorXd simulate(const Eigen::VectorXd& u) const {
    Eigen::VectorXd y = Eigen::VectorXd::Zero(u.size());
    for (size_t i = 0; i < c.size(); ++i) {
      double x = 0;
      for (Eigen::Index t = 0; t < u.size(); ++t) {
        y[t] += c[i] * x;  // strictly proper: x holds sum_{s>=1} p^{s-1} u(t-s)
        x = p[i] * x + u[t];
      }
    }
    return y;
  }
};

// The stochastic data sets of the hinf_bound Monte Carlo tests: 600 uniform inputs, G0's output
// plus coloured noise v(t) = 0.8 v(t-1) + e(t), e ~ N(0, 0.1^2). One generator per test; its
// distributions live across runs (std::normal_distribution caches a value), so the runs are the
// same as drawing them in the test's loop.
class ColouredNoiseRuns {
 public:
  ColouredNoiseRuns(FirstOrderSum G0, unsigned seed) : G0_(std::move(G0)), rng_(seed) {}
  struct Run {
    Eigen::VectorXd u, y;
  };
  Run next() {
    Eigen::VectorXd u(600), e(600), v(600);
    for (auto& x : u) x = U_(rng_);
    for (auto& x : e) x = noise_(rng_);
    v[0] = e[0];
    for (int t = 1; t < 600; ++t) v[t] = 0.8 * v[t - 1] + e[t];
    return {u, G0_.simulate(u) + v};
  }

 private:
  FirstOrderSum G0_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> U_{-1, 1};
  std::normal_distribution<double> noise_{0, 0.1};
};

// Options for a bounded-noise run |v(t)| <= v_bar: a weight of the given degree, 4 iterations of
// the nominal fit (the tests' systems converge in fewer).
inline HinfBoundOptions bounded_noise_options(double v_bar, int weight_degree) {
  HinfBoundOptions o;
  o.uncertainty.noise = NoiseModel::bounded;
  o.uncertainty.v_bar = v_bar;
  o.weight.degree = weight_degree;
  o.nominal.iterations = 4;
  return o;
}

// First-order G0 = 0.5 z^-1 / (1 - 0.5 z^-1), 300 uniform inputs, uniform output noise of the
// given amplitude; FIR basis of order 6, priors M = 1, rho = 0.6, the noise bound v_bar claimed.
inline HinfBoundResult first_order_run(unsigned seed, double noise, double v_bar, NoiseModel model) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd u(300);
  for (auto& x : u) x = U(rng);
  const FirstOrderSum G0{{0.5}, {0.5}};
  Eigen::VectorXd y = G0.simulate(u);
  for (auto& x : y) x += noise * U(rng);
  HinfPriors p;
  p.M = 1;
  p.rho = 0.6;
  HinfBoundOptions o;
  o.uncertainty.noise = model;
  o.uncertainty.v_bar = v_bar;
  return hinf_bound(HinfData{u, y, {}}, HinfStructure{OrthonormalBasis::fir(), 6, p, uniform_grid(10)}, o);
}

// The app's example (Kautz n = 40, 150 frequencies, its priors): the data set `run` of seed 1.
inline HinfBoundResult app_example_run(int N, int run, TransferFunction& G0) {
  G0 = sets::hakvoort::system();
  HinfStructure st;
  st.basis = OrthonormalBasis::kautz(std::polar(0.93, 0.66));
  st.order = 40;
  st.grid = midpoint_grid(150, 0, pi);
  HinfPriors given;
  given.rho = 0.88;
  given.M = -1;
  std::string note;
  st.priors = sets::hakvoort::priors_for(G0, st.basis, given, note);
  std::mt19937_64 rng(1);
  sets::hakvoort::Data d;
  for (int r = 1; r <= run; ++r) d = sets::hakvoort::simulate(G0, N, 0.02, false, rng);
  return hinf_bound(HinfData{d.u, d.y, {}}, st);
}

// The weight of R: certified positive on [0, pi], above delta on the grid, and G0 within the bound.
inline void expect_a_valid_weight(const HinfBoundResult& R, const TransferFunction& G0) {
  const double floor = 0.25 * R.delta.minCoeff() * R.delta.minCoeff();
  double lowest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 100000; ++i) lowest = std::min(lowest, std::norm(R.weight.inverse(pi * i / 99999)));
  EXPECT_GT(lowest, 0.5 * floor);
  for (Eigen::Index j = 0; j < R.set.frequencies.size(); ++j)
    EXPECT_GE(std::abs(R.weight.inverse(R.set.frequencies[j])), R.delta[j]);
  EXPECT_LE(weighted_error([&](double w) { return G0(w); }, R.nominal.model, R.weight.h), R.bound.b);
}

}  // namespace sets::testing
