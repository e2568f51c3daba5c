#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Eigenvalues>

#include <random>

#include "sets/core/error.hpp"
#include "sets/examples/farah.hpp"
#include "sets/methods/ss_uncertainty/state_enclosure.hpp"

namespace {

using sets::StateSpaceModel;

// A simulated data set with everything the guarantee speaks about: the true canonical states,
// the noise bound and the realised tail r_j(t) = C_j A^p x(t-p).
struct Case {
  StateSpaceModel system;
  std::vector<sets::ObservabilityRow> rows;
  Eigen::MatrixXd u, y, xc;  // xc: true canonical states, 3 x (N + 4) (a few beyond the data)
  Eigen::VectorXd vbar, tail, truth;
  int p = 20;
  bool estimate_d = false;
};

// A random stable, observable 3-state system with 2 inputs and 2 outputs (spectral radius in
// [0.3, 0.85]); D = 0 unless estimate_d.
StateSpaceModel random_system(std::mt19937_64& rng, bool with_d) {
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> U(0.3, 0.85);
  StateSpaceModel s;
  for (;;) {
    s.A = Eigen::MatrixXd::NullaryExpr(3, 3, [&] { return g(rng); });
    const double rho = s.A.eigenvalues().cwiseAbs().maxCoeff();
    if (rho < 1e-3) continue;
    s.A *= U(rng) / rho;
    s.B = Eigen::MatrixXd::NullaryExpr(3, 2, [&] { return g(rng); });
    s.C = Eigen::MatrixXd::NullaryExpr(2, 3, [&] { return g(rng); });
    s.D = with_d ? Eigen::MatrixXd(Eigen::MatrixXd::NullaryExpr(2, 2, [&] { return g(rng); }))
                 : Eigen::MatrixXd::Zero(2, 2);
    if (sets::observability_rank(s.A, s.C, 1e-6) == 3) return s;
  }
}

Case make_case(std::uint64_t seed, bool paper_system, int noise_kind, double snr_db, int p, int N, bool estimate_d,
               bool nonzero_x0, sets::RowSelection selection) {
  std::mt19937_64 rng(seed);
  Case c;
  c.p = p;
  c.estimate_d = estimate_d;
  c.system = paper_system ? sets::farah::system() : random_system(rng, estimate_d);
  c.rows = sets::select_rows(c.system.A, c.system.C, selection);
  const auto canon = sets::canonical_form(c.system, c.rows);
  c.truth = sets::CanonicalStructure(c.rows, 2, 2, estimate_d).to_parameters(canon);
  Eigen::MatrixXd T(3, 3);
  for (int k = 0; k < 3; ++k) {
    Eigen::RowVectorXd r = c.system.C.row(c.rows[static_cast<std::size_t>(k)].output);
    for (int l = 0; l < c.rows[static_cast<std::size_t>(k)].lag; ++l) r = r * c.system.A;
    T.row(k) = r;
  }
  std::bernoulli_distribution coin(0.5);
  std::normal_distribution<double> gauss;
  const int extra = 4;
  c.u.resize(N + extra, 2);
  for (int t = 0; t < N + extra; ++t) c.u.row(t) << (coin(rng) ? 1.0 : -1.0), (coin(rng) ? 1.0 : -1.0);
  Eigen::MatrixXd x(3, N + extra + 1);
  x.col(0) = nonzero_x0 ? Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(3, [&] { return 3 * gauss(rng); }))
                        : Eigen::VectorXd(Eigen::VectorXd::Zero(3));
  Eigen::MatrixXd y0(N + extra, 2);
  for (int t = 0; t < N + extra; ++t) {
    y0.row(t) = (c.system.C * x.col(t) + c.system.D * c.u.row(t).transpose()).transpose();
    x.col(t + 1) = c.system.A * x.col(t) + c.system.B * c.u.row(t).transpose();
  }
  c.xc = T * x.leftCols(N + extra);
  // Realised tail over every time the enclosures refer to (up to N - 1 + max lag).
  Eigen::MatrixXd CAp = c.system.C;
  for (int k = 0; k < p; ++k) CAp = CAp * c.system.A;
  c.tail = Eigen::VectorXd::Zero(2);
  for (int t = p; t < N + extra; ++t)
    c.tail = c.tail.cwiseMax((CAp * x.col(t - p)).cwiseAbs());
  c.tail *= 1 + 1e-9;
  c.vbar.resize(2);
  std::uniform_real_distribution<double> U(-1, 1);
  c.y = y0.topRows(N);
  c.u.conservativeResize(N, 2);
  for (int j = 0; j < 2; ++j) {
    const double var = (y0.col(j).array() - y0.col(j).mean()).square().mean();
    c.vbar[j] = std::sqrt(3 * var / std::pow(10.0, snr_db / 10));
    for (int t = 0; t < N; ++t) {
      // 0: uniform; 1: at the bound with a random sign (the hardest bounded noise); 2: a
      // slow square wave at the bound (correlated with nothing in particular).
      const double v = noise_kind == 0 ? U(rng) : noise_kind == 1 ? (coin(rng) ? 1.0 : -1.0) : ((t / 37) % 2 ? 1.0 : -1.0);
      c.y(t, j) += c.vbar[j] * v;
    }
    // The bound the guarantee assumes: the realised noise (y is rounded, and so is the true state
    // the test compares with), enlarged by 1e-9 relative so that float truths are inside.
    c.vbar[j] = (c.y.col(j) - y0.col(j).head(N)).cwiseAbs().maxCoeff() * (1 + 1e-9);
  }
  return c;
}

sets::PropagatorResult identify(const Case& c) {
  sets::PropagatorOptions o;
  o.order = 3;
  o.past = c.p;
  o.rows = c.rows;
  o.estimate_d = c.estimate_d;
  return sets::identify_propagator(c.u, c.y, o);
}

// The guarantee, sampled: under bounded noise and a true tail bound, every enclosure holds the
// true canonical state, the unit steps hold the true differences, the data contradict nothing,
// and the guaranteed FPS contains the true parameters — for the paper's system and random ones,
// both row orders, D known or estimated, x(0) zero or not, noise uniform, at the bound or a
// square wave, 5 to 40 dB.
RC_GTEST_PROP(StateEnclosure, TrueStatesAndParametersAreInside, ()) {
  const bool paper = *rc::gen::arbitrary<bool>();
  const int noise_kind = *rc::gen::inRange(0, 3);
  const double snr = *rc::gen::element(5.0, 20.0, 40.0);
  const int p = *rc::gen::element(8, 12, 20);
  const bool estimate_d = *rc::gen::arbitrary<bool>();
  const bool x0 = *rc::gen::arbitrary<bool>();
  const auto selection = *rc::gen::arbitrary<bool>() ? sets::RowSelection::output_major : sets::RowSelection::lag_major;
  const Case c = make_case(*rc::gen::arbitrary<std::uint64_t>(), paper, noise_kind, snr, p,
                           *rc::gen::inRange(250, 700), estimate_d, x0, selection);
  sets::PropagatorResult id;
  try {
    id = identify(c);
  } catch (const sets::InputError&) {
    RC_DISCARD("not identifiable from these data");
  }
  sets::GuaranteedSetAssumptions a;
  a.noise_bound = c.vbar;
  a.tail_bound = c.tail;
  const auto X = sets::enclose_states(id, c.u, c.y, a);
  RC_ASSERT(X.contradictions.empty());
  for (int k = 0; k < 3; ++k)
    for (int col = 0; col < X.states.cols(); ++col) {
      const double truth = c.xc(k, X.first + col);
      if (!(X.states(k, col).lower() <= truth && truth <= X.states(k, col).upper()))
        RC_FAIL("state " + std::to_string(k) + " lag " + std::to_string(id.rows[k].lag) + " output " +
                std::to_string(id.rows[k].output) + " col " + std::to_string(col) + " of " +
                std::to_string(X.states.cols()) + ": " + sets::to_string(X.states(k, col)) + " truth " +
                std::to_string(truth) + " xhat " + std::to_string(id.states(k, col)));
    }
  const sets::CanonicalStructure& st = id.structure;
  for (int i = 0; i < 3; ++i)
    if (st.a_unit(i) >= 0)
      for (int col = 0; col + 1 < X.states.cols(); ++col) {
        const double diff = c.xc(i, X.first + col + 1) - c.xc(st.a_unit(i), X.first + col);
        RC_ASSERT(X.unit_steps(i, col).lower() <= diff && diff <= X.unit_steps(i, col).upper());
      }
  const auto fps = sets::guaranteed_fps(id, c.u, c.y, X, c.vbar);
  RC_ASSERT(fps.falsified_rows().empty());
  RC_ASSERT(fps.contains(c.truth) != sets::BoolInterval::no);
}

// A deterministic state-error bound the user gives: the set holds the truth when the bound does.
TEST(StateEnclosure, UserStateBoundCarriesTheTruth) {
  const Case c = make_case(7, true, 0, 30, 20, 600, false, false, sets::RowSelection::output_major);
  const auto id = identify(c);
  Eigen::VectorXd err = Eigen::VectorXd::Zero(3);
  for (int col = 0; col < id.states.cols(); ++col)
    err = err.cwiseMax((c.xc.col(id.first_state + col) - id.states.col(col)).cwiseAbs());
  sets::GuaranteedSetAssumptions a;
  a.noise_bound = c.vbar;
  a.state_error_bound = 1.001 * err;
  const auto X = sets::enclose_states(id, c.u, c.y, a);
  EXPECT_TRUE(X.contradictions.empty());
  const auto fps = sets::guaranteed_fps(id, c.u, c.y, X, c.vbar);
  EXPECT_NE(fps.contains(c.truth), sets::BoolInterval::no);
  const auto box = sets::pui(fps);
  ASSERT_FALSE(box.empty());
  EXPECT_TRUE(sets::contains(box.box, c.truth));
  // A bound the data contradict (state 1 is the measured output up to the noise) is reported.
  a.state_error_bound.setZero();
  a.noise_bound *= 0.01;
  EXPECT_FALSE(sets::enclose_states(id, c.u, c.y, a).contradictions.empty());
}

TEST(StateEnclosure, DataContradictingTheNoiseBoundAreReported) {
  const Case c = make_case(9, true, 0, 20, 20, 500, false, false, sets::RowSelection::output_major);
  const auto id = identify(c);
  sets::GuaranteedSetAssumptions a;
  a.noise_bound = 0.2 * c.vbar;  // the residuals are larger than this allows
  a.tail_bound = c.tail;
  const auto X = sets::enclose_states(id, c.u, c.y, a);
  ASSERT_FALSE(X.contradictions.empty());
  EXPECT_NE(X.contradictions[0].find("output 1"), std::string::npos) << X.contradictions[0];
}

TEST(StateEnclosure, BadBoundsAreRejected) {
  const Case c = make_case(3, true, 0, 20, 20, 300, false, false, sets::RowSelection::output_major);
  const auto id = identify(c);
  sets::GuaranteedSetAssumptions a;
  a.noise_bound = c.vbar;
  EXPECT_THROW(sets::enclose_states(id, c.u, c.y, a), sets::InputError);  // neither tail nor state bound
  a.tail_bound = Eigen::VectorXd::Constant(3, 0.1);                         // one per output is needed
  EXPECT_THROW(sets::enclose_states(id, c.u, c.y, a), sets::InputError);
  a.tail_bound = Eigen::Vector2d(0.1, -1.0);
  EXPECT_THROW(sets::enclose_states(id, c.u, c.y, a), sets::InputError);
  a.tail_bound = c.tail;
  EXPECT_THROW(sets::enclose_states(id, c.u.topRows(200), c.y.topRows(200), a), sets::InputError);
}

TEST(StateEnclosure, FirTailOfThePaperSystem) {
  const auto s = sets::farah::system();
  const Eigen::VectorXd t20 = sets::fir_tail_bound(s, 20, 1.0), t10 = sets::fir_tail_bound(s, 10, 1.0);
  // Spectral radius 0.653: the tail shrinks by about 0.653^10 from p = 10 to 20.
  EXPECT_GT(t20.minCoeff(), 0.0);
  EXPECT_LT(t20.maxCoeff(), 0.05 * t10.maxCoeff());
  EXPECT_NEAR(sets::fir_tail_bound(s, 20, 2.0)[0], 2 * t20[0], 1e-12 * t20[0]);
}

}  // namespace
