// Discrete window norms and the window-norm ball (src/methods/tv_bound/window_norm.cpp,
// Salehpour & Johansson Definition 1, equations 5 and 7).

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "sets/core/error.hpp"
#include "sets/methods/tv_bound/window_norm.hpp"
#include "sets/numeric/linear_program.hpp"

TEST(TvBound, WindowNormOfKnownSignals) {
  const auto w = sets::WindowNorm::pulse(36, 1.0 / 35);
  EXPECT_NEAR(w(Eigen::VectorXd::Ones(100)), 36.0 / 35, 1e-12);  // full window of ones
  EXPECT_NEAR(w(Eigen::VectorXd::Ones(10)), 10.0 / 35, 1e-12);   // signal shorter than the window
  Eigen::VectorXd pulse = Eigen::VectorXd::Zero(50);
  pulse[20] = -7;
  EXPECT_NEAR(w(pulse), 7.0 / 35, 1e-12);  // a single spike: the sign does not matter
  // The unit pulse window gives the l-inf norm.
  EXPECT_NEAR(sets::WindowNorm::pulse(1, 1.0)(Eigen::Vector3d(1, -4, 2)), 4.0, 0);
}

TEST(TvBound, BadWindowsAreRejected) {
  EXPECT_THROW((void)sets::WindowNorm(Eigen::VectorXd()), sets::InputError);  // (void): not a declaration
  EXPECT_THROW(sets::WindowNorm::pulse(0, 1.0), sets::InputError);
  EXPECT_THROW(sets::WindowNorm(Eigen::Vector3d(0.5, 0.6, 0.1)), sets::InputError);  // increases at 1
  EXPECT_THROW(sets::WindowNorm(Eigen::Vector2d(0, 0)), sets::InputError);           // identically zero
  EXPECT_THROW(sets::WindowNorm(Eigen::Vector2d(1, -0.1)), sets::InputError);
  EXPECT_THROW(sets::WindowNorm(Eigen::Vector2d(1, NAN)), sets::InputError);
  try {
    sets::WindowNorm(Eigen::Vector3d(0.5, 0.4, 0.45));
    FAIL();
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sample 2"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(sets::WindowNorm(Eigen::Vector3d(0.5, 0.5, 0.0)));  // non-increasing is enough
}

// The lifted polytope (7) holds (V, |V|) exactly when every output's window norm is <= eps.
RC_GTEST_PROP(TvBound, LiftedWindowPolytopeIsTheWindowNormBall, ()) {
  const int samples = *rc::gen::inRange(1, 12), l = *rc::gen::inRange(1, 3);
  std::vector<sets::WindowNorm> ws;
  for (int j = 0; j < l; ++j) {
    const int L = *rc::gen::inRange(1, 6);
    Eigen::VectorXd w(L);
    double prev = 1;
    for (int d = 0; d < L; ++d) w[d] = prev = prev * (*rc::gen::inRange(1, 101)) / 100.0;
    ws.emplace_back(w);
  }
  const sets::WindowNormBall ball(ws, samples);
  Eigen::VectorXd V(samples * l);
  for (Eigen::Index i = 0; i < V.size(); ++i) V[i] = *rc::gen::inRange(-1000, 1001) / 100.0;
  const Eigen::VectorXd n = ball.norms(V);
  const double scale = *rc::gen::element(0.9, 1.0, 1.1);
  const Eigen::VectorXd eps = scale * n;
  const auto poly = ball.lifted_polytope(eps);
  Eigen::VectorXd z(2 * V.size());
  z << V, V.cwiseAbs();
  const bool inside = ((poly.A() * z - poly.b()).array() <= 1e-9 * (1 + n.maxCoeff())).all();
  const bool expected = scale >= 1.0 || n.maxCoeff() == 0;
  RC_ASSERT(inside == expected);
  RC_ASSERT(ball.contains(V, eps, 1e-12) == expected);
}

namespace {

// max c^T x over { x : ||x||_w <= eps } (the ball of one output, map = I) by WindowNormBall::add_to.
double max_over_ball(const sets::WindowNorm& w, const Eigen::VectorXd& c, double eps) {
  const int n = static_cast<int>(c.size());
  const sets::WindowNormBall ball({w}, n);
  sets::LinearProgram lp(n);
  ball.add_to(lp, Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n), 0, Eigen::VectorXd::Constant(1, eps));
  Eigen::VectorXd obj = Eigen::VectorXd::Zero(lp.num_variables());
  obj.head(n) = c;
  lp.set_objective(obj, sets::Sense::maximize);
  const sets::LpSolution s = lp.solve();
  EXPECT_TRUE(s.status == sets::LpStatus::optimal);
  return s.objective;
}

}  // namespace

TEST(WindowNorm, BallInAnLpHasTheKnownOptima) {
  // w = (1, 1/2, 1/4), eps = 2 over 6 samples. A single sample can reach eps / w(0) = 2; samples 0
  // and 5 are more than the window apart, so both reach 2; samples 0 and 1 share the row
  // w(1) x0 + w(0) x1 <= 2, so x0 + x1 <= 2 + x0 / 2 <= 3.
  const sets::WindowNorm w(Eigen::Vector3d(1, 0.5, 0.25));
  Eigen::VectorXd c = Eigen::VectorXd::Zero(6);
  c[5] = 1;
  EXPECT_NEAR(max_over_ball(w, c, 2.0), 2.0, 1e-9);
  c[0] = 1;
  EXPECT_NEAR(max_over_ball(w, c, 2.0), 4.0, 1e-9);
  c.setZero();
  c[0] = c[1] = 1;
  EXPECT_NEAR(max_over_ball(w, c, 2.0), 3.0, 1e-9);
  c[1] = -1;  // the sign does not matter: |x|
  EXPECT_NEAR(max_over_ball(w, c, 2.0), 3.0, 1e-9);
}

TEST(WindowNorm, SmallestEpsOfAFixedSignalIsItsWindowNorm) {
  // eps as an LP variable and no map columns: min eps with v in the ball is ||v||_w.
  const sets::WindowNorm w(Eigen::Vector4d(0.4, 0.3, 0.3, 0.1));
  const Eigen::VectorXd v = (Eigen::VectorXd(7) << 0.5, -2, 1, 0, 3, -0.25, 1).finished();
  const sets::WindowNormBall ball({w}, 7);
  sets::LinearProgram lp(0);
  const auto blk = ball.add_to(lp, v, Eigen::MatrixXd(7, 0), 0);
  ASSERT_GE(blk.first_eps, 0);
  Eigen::VectorXd obj = Eigen::VectorXd::Zero(lp.num_variables());
  obj[blk.first_eps] = 1;
  lp.set_objective(obj, sets::Sense::minimize);
  const sets::LpSolution s = lp.solve();
  ASSERT_TRUE(s.status == sets::LpStatus::optimal);
  EXPECT_NEAR(s.objective, w(v), 1e-9);
  // Hand computation: the largest row is k = 4: 0.4*3 + 0.3*0 + 0.3*1 + 0.1*2 = 1.7.
  EXPECT_NEAR(w(v), 1.7, 1e-12);
  EXPECT_NEAR(ball.norms(v)[0], 1.7, 1e-12);
}
