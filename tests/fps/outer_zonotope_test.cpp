// The Alamo–Bravo–Camacho zonotope of a feasible parameter set: it contains the FPS (sampled),
// and it refuses interval regressors and data that falsify the model.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <random>

#include "sets/core/error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/fps/outer_zonotope.hpp"

namespace {

using sets::BoolInterval;
using sets::Zonotope;

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  double u(double lo = -1, double hi = 1) { return std::uniform_real_distribution<double>(lo, hi)(g); }
  Eigen::VectorXd vec(int n, double s = 1) { return Eigen::VectorXd::NullaryExpr(n, [&] { return s * u(); }); }
  Eigen::MatrixXd mat(int r, int c) { return Eigen::MatrixXd::NullaryExpr(r, c, [&] { return u(); }); }
};

}  // namespace

RC_GTEST_PROP(OuterZonotope, FpsZonotopeContainsTheFps, ()) {
  const int p = *rc::gen::inRange(2, 4);
  const int N = *rc::gen::inRange(p + 2, 30);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const Eigen::VectorXd theta = r.vec(p, 2);
  const Eigen::MatrixXd Phi = r.mat(N, p);
  const Eigen::VectorXd delta = Eigen::VectorXd::NullaryExpr(N, [&] { return r.u(0.05, 0.3); });
  Eigen::VectorXd y = Phi * theta;
  for (int t = 0; t < N; ++t) y[t] += delta[t] * r.u();
  const auto fps = sets::FeasibleParameterSet::from_data(Phi, y, delta);
  sets::FpsZonotopeOptions opt;
  opt.max_order = 4;
  const Zonotope Z = sets::outer_zonotope(fps, opt);
  RC_ASSERT(Z.num_generators() <= 4 * p + p + 1);
  RC_ASSERT(sets::contains(Z, theta) != BoolInterval::no);
  // Points of the FPS (rejection sampling in the PUI box) are inside the zonotope.
  const auto box = sets::pui(fps).box;
  int found = 0;
  for (int s = 0; s < 2000 && found < 30; ++s) {
    Eigen::VectorXd x(p);
    for (int i = 0; i < p; ++i) x[i] = box[i].lower() + (box[i].upper() - box[i].lower()) * r.u(0, 1);
    if (fps.contains(x) != BoolInterval::yes) continue;
    ++found;
    RC_ASSERT(sets::contains(Z, x) != BoolInterval::no);
  }
}

TEST(OuterZonotope, FpsZonotopeRejectsIntervalRegressorsAndFalsifiedData) {
  sets::IntervalMatrix Phi(1, 1);
  Phi(0, 0) = sets::Interval(0.9, 1.1);
  sets::IntervalVector Y(1);
  Y(0) = sets::Interval(0.9, 1.1);
  EXPECT_THROW(sets::outer_zonotope(sets::FeasibleParameterSet::from_interval_data(Phi, Y)),
               sets::UnsupportedError);
  Eigen::MatrixXd P(2, 1);
  P << 1, 1;
  sets::FpsZonotopeOptions opt;
  opt.initial = Zonotope(Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Constant(1, 1, 10.0));
  EXPECT_THROW(sets::outer_zonotope(sets::FeasibleParameterSet::from_data(P, Eigen::Vector2d(0, 5),
                                                                          Eigen::Vector2d(1, 1)),
                                    opt),
               sets::EmptySetError);
}
