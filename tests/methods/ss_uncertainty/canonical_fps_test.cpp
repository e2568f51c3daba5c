#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <random>

#include "sets/core/error.hpp"
#include "sets/examples/farah.hpp"
#include "sets/methods/ss_uncertainty/canonical_fps.hpp"
#include "sets/methods/ss_uncertainty/level_set_uncertainty.hpp"

namespace {

// Rows of two independent blocks (parameters {0, 2} and {1, 3, 4}) and rows without parameters;
// true regressors inside the interval regressors, |noise| <= delta.
struct BlockData {
  sets::IntervalMatrix Psi;
  sets::IntervalVector Y;
  Eigen::VectorXd theta;
};

BlockData block_data(std::uint64_t seed, double radius, int N) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  BlockData d;
  d.theta = Eigen::VectorXd::NullaryExpr(5, [&] { return 2 * U(rng); });
  d.Psi = sets::IntervalMatrix::Constant(N, 5, sets::Interval(0.0));
  d.Y.resize(N);
  const std::vector<std::vector<int>> blocks{{0, 2}, {1, 3, 4}};
  for (int t = 0; t < N; ++t) {
    double value = 0;
    if (t % 7 != 6) {
      for (int j : blocks[static_cast<std::size_t>(t % 2)]) {
        const double phi = U(rng), r = radius * std::abs(U(rng)), shift = r * U(rng);
        d.Psi(t, j) = sets::Interval(phi - r, phi + r);  // contains the true regressor phi + shift
        value += (phi + shift) * d.theta[j];
      }
    }
    const double delta = 0.1;
    d.Y[t] = sets::interval_around(value + delta * U(rng), delta);
  }
  return d;
}

TEST(CanonicalFps, BlocksFollowTheSharedParameters) {
  const auto d = block_data(1, 0.0, 70);
  const sets::CanonicalFps fps(d.Psi, d.Y);
  ASSERT_EQ(fps.blocks().size(), 2u);
  EXPECT_EQ(fps.blocks()[0].parameters, (std::vector<int>{0, 2}));
  EXPECT_EQ(fps.blocks()[1].parameters, (std::vector<int>{1, 3, 4}));
  EXPECT_EQ(fps.size(), 60);  // 10 rows without parameters are checks
  EXPECT_TRUE(fps.falsified_rows().empty());
  EXPECT_FALSE(fps.has_interval_regressors());
  sets::IntervalMatrix lonely = d.Psi;
  lonely.col(4).setConstant(sets::Interval(0.0));  // parameter 4 in no row
  EXPECT_THROW(sets::CanonicalFps(lonely, d.Y), sets::InputError);
}

// The constructor from exact regressors groups the same rows into the same blocks with the same
// sets as the one from interval regressors (a row whose zero pattern joins the two blocks makes
// one block of all five parameters), and rejects a parameter in no row and a wrong length alike.
TEST(CanonicalFps, ExactRegressorsGiveTheSameBlocksAsDegenerateIntervals) {
  for (const bool join : {false, true}) {
    auto d = block_data(3, 0.0, 50);
    if (join) d.Psi(44, 4) = sets::Interval(0.5);  // row 44 holds parameters 0, 2 and now 4
    const Eigen::MatrixXd point = sets::midpoint(d.Psi);
    const sets::CanonicalFps a(d.Psi, d.Y), b(point, d.Y);
    ASSERT_EQ(a.blocks().size(), join ? 1u : 2u);
    ASSERT_EQ(a.blocks().size(), b.blocks().size());
    for (std::size_t k = 0; k < a.blocks().size(); ++k) {
      const auto &x = a.blocks()[k], &y = b.blocks()[k];
      EXPECT_EQ(x.parameters, y.parameters);
      EXPECT_EQ(x.rows, y.rows);
      ASSERT_EQ(x.set.size(), y.set.size());
      const sets::IntervalMatrix px = x.set.regressors(), py = y.set.regressors();
      const sets::IntervalVector yx = x.set.outputs(), yy = y.set.outputs();
      EXPECT_EQ(sets::lower(px), sets::lower(py));
      EXPECT_EQ(sets::upper(px), sets::upper(py));
      EXPECT_EQ(sets::lower(yx), sets::lower(yy));
      EXPECT_EQ(sets::upper(yx), sets::upper(yy));
    }
    EXPECT_EQ(a.falsified_rows(), b.falsified_rows());
    EXPECT_EQ(a.contains(d.theta), b.contains(d.theta));
  }
  const auto d = block_data(4, 0.0, 30);
  Eigen::MatrixXd lonely = sets::midpoint(d.Psi);
  lonely.col(4).setZero();
  EXPECT_THROW(sets::CanonicalFps(lonely, d.Y), sets::InputError);
  const Eigen::MatrixXd short_psi = lonely.topRows(20);
  EXPECT_THROW(sets::CanonicalFps(short_psi, d.Y), sets::InputError);
}

// Exact regressors: the PUIs per block are those of the one FPS in every parameter (both are
// certified, so they agree up to the LP tolerance), and membership agrees.
RC_GTEST_PROP(CanonicalFps, BlockPuisEqualThePuisOfTheWholeSet, ()) {
  const auto d = block_data(*rc::gen::arbitrary<std::uint64_t>(), 0.0, 80);
  const sets::CanonicalFps blocks(d.Psi, d.Y);
  std::vector<int> keep;
  for (int t = 0; t < d.Psi.rows(); ++t)
    if (t % 7 != 6) keep.push_back(t);
  sets::IntervalMatrix phi(static_cast<Eigen::Index>(keep.size()), 5);
  sets::IntervalVector y(static_cast<Eigen::Index>(keep.size()));
  for (std::size_t k = 0; k < keep.size(); ++k) {
    phi.row(static_cast<Eigen::Index>(k)) = d.Psi.row(keep[k]);
    y[static_cast<Eigen::Index>(k)] = d.Y[keep[k]];
  }
  const auto whole = sets::FeasibleParameterSet::from_interval_data(phi, y);
  const auto a = sets::pui(blocks), b = sets::pui(whole);
  RC_ASSERT(!a.empty() && !b.empty() && a.guaranteed);
  RC_ASSERT(sets::contains(a.box, d.theta));
  for (int j = 0; j < 5; ++j) {
    const double scale = 1 + std::abs(b.box[j].lower()) + std::abs(b.box[j].upper());
    RC_ASSERT(std::abs(a.box[j].lower() - b.box[j].lower()) <= 1e-7 * scale);
    RC_ASSERT(std::abs(a.box[j].upper() - b.box[j].upper()) <= 1e-7 * scale);
  }
  // The assembled attaining points attain the ends and are (LP-)feasible points of the whole
  // set: the fraction of rows of the whole set they violate by more than 1e-6 is zero.
  const Eigen::MatrixXd A = sets::midpoint(sets::IntervalMatrix(phi));
  for (int l = 0; l < 5; ++l) {
    const double scale = 1 + std::abs(a.box[l].lower()) + std::abs(a.box[l].upper());
    RC_ASSERT(std::abs(a.lower_points(l, l) - a.box[l].lower()) <= 1e-6 * scale);
    RC_ASSERT(std::abs(a.upper_points(l, l) - a.box[l].upper()) <= 1e-6 * scale);
    for (const Eigen::VectorXd& x : {Eigen::VectorXd(a.lower_points.col(l)), Eigen::VectorXd(a.upper_points.col(l))}) {
      const Eigen::VectorXd v = A * x;
      for (Eigen::Index k = 0; k < v.size(); ++k)
        RC_ASSERT(v[k] >= y[k].lower() - 1e-6 && v[k] <= y[k].upper() + 1e-6);
    }
  }
  const Eigen::VectorXd probe = a.central + 0.3 * (a.box[0].upper() - a.box[0].lower()) * Eigen::VectorXd::Ones(5);
  RC_ASSERT(blocks.contains(probe) == whole.contains(probe));
}

// Interval regressors: the true parameters are always inside (sampling test of the guarantee).
RC_GTEST_PROP(CanonicalFps, TrueParametersInsideWithIntervalRegressors, ()) {
  const auto d = block_data(*rc::gen::arbitrary<std::uint64_t>(), 0.05, 60);
  const sets::CanonicalFps fps(d.Psi, d.Y);
  RC_ASSERT(fps.has_interval_regressors());
  RC_ASSERT(fps.contains(d.theta) != sets::BoolInterval::no);
  const auto r = sets::pui(fps);
  RC_ASSERT(!r.empty());
  RC_ASSERT(sets::contains(r.box, d.theta));
}

TEST(CanonicalFps, FalsifiedRowWithoutParametersEmptiesTheSet) {
  auto d = block_data(3, 0.0, 30);
  d.Y[6] = sets::Interval(0.5, 1.0);  // a row without parameters whose bound excludes 0
  const sets::CanonicalFps fps(d.Psi, d.Y);
  ASSERT_EQ(fps.falsified_rows(), std::vector<int>{6});
  EXPECT_EQ(fps.contains(d.theta), sets::BoolInterval::no);
  const auto r = sets::pui(fps);
  EXPECT_TRUE(r.empty());
  EXPECT_EQ(r.consistency.conflict.samples, std::vector<int>{6});
}

// The canonical regression of the paper's form splits into the blocks of Remark 1.
TEST(CanonicalFps, PaperRegressionSplitsByEquation) {
  const auto sys = sets::farah::system();
  const auto rows = sets::select_rows(sys.A, sys.C, sets::RowSelection::output_major);
  const sets::CanonicalStructure st(rows, 2, 2, false);
  const auto canon = sets::canonical_form(sys, rows);
  std::mt19937_64 rng(4);
  std::bernoulli_distribution coin(0.5);
  const int N = 60;
  Eigen::MatrixXd u(N, 2), y(N, 2), X(3, N);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  for (int t = 0; t < N; ++t) {
    u.row(t) << (coin(rng) ? 1.0 : -1.0), (coin(rng) ? 1.0 : -1.0);
    X.col(t) = x;
    y.row(t) = (canon.C * x).transpose();
    x = canon.A * x + canon.B * u.row(t).transpose();
  }
  const auto fps = sets::regression_fps(sets::canonical_regression(st, X, 0, u, y), 1e-9);
  ASSERT_EQ(fps.blocks().size(), 4u);
  const auto names = st.parameter_names();
  auto block_names = [&](std::size_t b) {
    std::vector<std::string> out;
    for (int j : fps.blocks()[b].parameters) out.push_back(names[static_cast<std::size_t>(j)]);
    return out;
  };
  EXPECT_EQ(block_names(0), (std::vector<std::string>{"b0^1", "b0^2"}));
  EXPECT_EQ(block_names(1), (std::vector<std::string>{"b1^1", "b1^2"}));
  EXPECT_EQ(block_names(2), (std::vector<std::string>{"-a0", "-a1", "-a2", "b2^1", "b2^2"}));
  EXPECT_EQ(block_names(3), (std::vector<std::string>{"c0^2", "c1^2", "c2^2"}));
  EXPECT_NE(fps.contains(st.to_parameters(canon)), sets::BoolInterval::no);
}

}  // namespace
