#include <gtest/gtest.h>

#include <Eigen/QR>

#include <random>

#include "sets/core/error.hpp"
#include "sets/examples/farah.hpp"
#include "sets/methods/ss_uncertainty/propagator_identification.hpp"

namespace {

using sets::StateSpaceModel;

Eigen::MatrixXd binary_input(int N, int nu, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution coin(0.5);
  Eigen::MatrixXd u(N, nu);
  for (int t = 0; t < N; ++t)
    for (int m = 0; m < nu; ++m) u(t, m) = coin(rng) ? 1.0 : -1.0;
  return u;
}

TEST(PropagatorIdentification, CanonicalFormOfThePrintedSystem) {
  const auto sys = sets::farah::system();
  const auto rows = sets::select_rows(sys.A, sys.C, sets::RowSelection::output_major);
  ASSERT_EQ(rows.size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rows[k], (sets::ObservabilityRow{k, 0}));
  const auto c = sets::canonical_form(sys, rows);
  // The characteristic polynomial z^3 + 0.1 z^2 - 0.24 z - 0.164 is printed in the paper and is
  // an invariant; compare it with the eigenvalues of A computed independently.
  const Eigen::Vector3d last = c.A.row(2).transpose();
  EXPECT_NEAR(last(0), 0.164, 1e-12);
  EXPECT_NEAR(last(1), 0.24, 1e-12);
  EXPECT_NEAR(last(2), -0.1, 1e-12);
  EXPECT_NEAR(c.A.trace(), sys.A.trace(), 1e-12);
  // Same transfer function: Markov parameters agree.
  Eigen::MatrixXd Ak = Eigen::MatrixXd::Identity(3, 3), Ack = Ak;
  for (int k = 0; k < 6; ++k) {
    EXPECT_LT((sys.C * Ak * sys.B - c.C * Ack * c.B).norm(), 1e-9);
    Ak = Ak * sys.A;
    Ack = Ack * c.A;
  }
  // B_c = Gamma_1 B: first row is C(1,:) B = [6, -1].
  EXPECT_NEAR(c.B(0, 0), 6.0, 1e-12);
  EXPECT_NEAR(c.B(0, 1), -1.0, 1e-12);
}

TEST(PropagatorIdentification, NoiseFreeDataReproduceTheCanonicalParameters) {
  const auto sys = sets::farah::system();
  const auto u = binary_input(1000, 2, 7);
  const auto y = sets::simulate(sys, u);
  sets::PropagatorOptions o;
  o.order = 3;
  o.past = 20;
  const auto r = sets::identify_propagator(u, y, o);
  const auto truth = r.structure.to_parameters(sets::canonical_form(sys, r.rows));
  ASSERT_EQ(truth.size(), 12);
  const auto names = r.structure.parameter_names();
  EXPECT_EQ(names[0], "-a0");
  EXPECT_EQ(names[3], "c0^2");
  EXPECT_EQ(names[6], "b0^1");
  EXPECT_EQ(names[7], "b0^2");
  for (int k = 0; k < truth.size(); ++k) EXPECT_NEAR(r.theta(k), truth(k), 1e-4) << names[k];
  // Equation (6) read from the propagator agrees too.
  const auto c = sets::canonical_form(sys, r.rows);
  EXPECT_LT((r.propagator_model.A - c.A).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT((r.propagator_model.C - c.C).cwiseAbs().maxCoeff(), 1e-4);
}

TEST(PropagatorIdentification, EstimatedDIsNearZeroForNoiseFreeData) {
  const auto sys = sets::farah::system();
  const auto u = binary_input(800, 2, 3);
  const auto y = sets::simulate(sys, u);
  sets::PropagatorOptions o;
  o.order = 3;
  o.estimate_d = true;
  const auto r = sets::identify_propagator(u, y, o);
  EXPECT_EQ(r.structure.parameter_count(), 16);
  EXPECT_LT(r.d.cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT(r.model.D.cwiseAbs().maxCoeff(), 1e-4);
}

TEST(PropagatorIdentification, UserRowsGiveAnotherCanonicalForm) {
  const auto sys = sets::farah::system();
  const auto u = binary_input(1000, 2, 11);
  const auto y = sets::simulate(sys, u);
  sets::PropagatorOptions o;
  o.order = 3;
  o.rows = {{0, 0}, {0, 1}, {1, 0}};  // y1, y2, y1 shifted: two free rows of A_c
  o.past = 30;  // this form amplifies the truncation error A^p more than the paper's form
  const auto r = sets::identify_propagator(u, y, o);
  const auto truth = r.structure.to_parameters(sets::canonical_form(sys, o.rows));
  EXPECT_EQ(r.structure.parameter_count(), 2 * 3 + 3 * 2);
  EXPECT_LT((r.theta - truth).cwiseAbs().maxCoeff(), 1e-4);
}

TEST(PropagatorIdentification, BadInputIsRejected) {
  const auto sys = sets::farah::system();
  const auto u = binary_input(600, 2, 5);
  const auto y = sets::simulate(sys, u);
  sets::PropagatorOptions o;
  o.order = 3;
  o.past = 2;  // p < n_x
  EXPECT_THROW(sets::identify_propagator(u, y, o), sets::InputError);
  o.past = 20;
  // Noise-free data of a second-order system with A^2 = 0 (the truncation is exact): Gamma_p K^
  // has rank 2, so order 3 is more than the data support.
  StateSpaceModel fir{Eigen::MatrixXd::Zero(2, 2), Eigen::MatrixXd::Identity(2, 2),
                      Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Zero(2, 2)};
  fir.A(0, 1) = 1.0;
  try {
    sets::identify_propagator(u, sets::simulate(fir, u), o);
    FAIL() << "order 3 accepted for second-order data";
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("larger than the data support"), std::string::npos) << e.what();
  }
  o.order = 41;  // larger than min(n_y p, n_u p)
  EXPECT_THROW(sets::identify_propagator(u, y, o), sets::InputError);
  o.order = 3;
  Eigen::MatrixXd uc = u;
  uc.col(1).setConstant(1.0);
  try {
    sets::identify_propagator(uc, sets::simulate(sys, uc), o);
    FAIL() << "constant input accepted";
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("input column 2 is constant"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sets::identify_propagator(u.topRows(40), y.topRows(40), o), sets::InputError);
  // Non-observable (A, C): the third state never reaches the outputs (and the observable part
  // is nilpotent, so the data show exactly rank 2).
  StateSpaceModel bad = sys;
  bad.A << 0, 1, 0, 0, 0, 0, 0, 0, 0.5;
  bad.C << 1, 0, 0, 0, 1, 0;
  EXPECT_THROW(sets::canonical_form(bad, {{0, 0}, {0, 1}, {1, 0}}), sets::InputError);
  EXPECT_THROW(sets::select_rows(bad.A, bad.C, sets::RowSelection::lag_major), sets::InputError);
  EXPECT_THROW(sets::identify_propagator(u, sets::simulate(bad, u), o), sets::InputError);
}

}  // namespace

namespace {

// Table I at 20 dB: over Monte Carlo runs the mean of every estimate is within a fraction of
// its standard deviation of the true canonical value (40 runs keep the test fast; the app runs
// 1000 and shows |bias|/std of at most about 0.12).
TEST(PropagatorIdentification, MonteCarloMeansAgreeWithTheTrueValues) {
  const auto sys = sets::farah::system();
  const auto rows = sets::select_rows(sys.A, sys.C, sets::RowSelection::output_major);
  const auto truth = sets::CanonicalStructure(rows, 2, 2, false).to_parameters(sets::canonical_form(sys, rows));
  const int R = 40;
  Eigen::MatrixXd TH(truth.size(), R);
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> g;
  for (int k = 0; k < R; ++k) {
    const auto u = binary_input(1000, 2, 100 + k);
    Eigen::MatrixXd y = sets::simulate(sys, u);
    for (int j = 0; j < 2; ++j) {
      const double sd = std::sqrt((y.col(j).array() - y.col(j).mean()).square().mean() / 100.0);
      for (int t = 0; t < y.rows(); ++t) y(t, j) += sd * g(rng);
    }
    sets::PropagatorOptions o;
    o.order = 3;
    o.rows = rows;
    TH.col(k) = sets::identify_propagator(u, y, o).theta;
  }
  const Eigen::VectorXd mean = TH.rowwise().mean();
  for (int i = 0; i < truth.size(); ++i) {
    const double sd = std::sqrt((TH.row(i).array() - mean[i]).square().sum() / (R - 1));
    EXPECT_GT(sd, 0.0);
    // The standard error of the mean is sd / sqrt(40) = 0.16 sd; allow 0.6 sd.
    EXPECT_LT(std::abs(mean[i] - truth[i]), 0.6 * sd) << "parameter " << i;
  }
}

}  // namespace

namespace {

// The whole-Psi column-pivoted QR that regression_least_squares replaces.
sets::RegressionLeastSquares whole_psi_least_squares(const sets::CanonicalRegression& r) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(r.Psi);
  qr.setThreshold(sets::least_squares_rank_threshold);
  return {qr.rank() == r.Psi.cols() ? Eigen::VectorXd(qr.solve(r.y)) : Eigen::VectorXd(), static_cast<int>(qr.rank())};
}

}  // namespace

// One QR per equation's block gives the least-squares theta~ and the rank of one QR of Psi: on
// identified regressions (D known or estimated, both row orders), on one whose input columns are
// equal (every B block rank deficient) and on a Psi whose columns mix equations (one QR).
TEST(PropagatorIdentification, EquationwiseLeastSquaresEqualsOneQrOfPsi) {
  const auto sys = sets::farah::system();
  for (const bool estimate_d : {false, true})
    for (const auto selection : {sets::RowSelection::output_major, sets::RowSelection::lag_major}) {
      const Eigen::MatrixXd u = binary_input(400, 2, 11);
      Eigen::MatrixXd y = sets::simulate(sys, u);
      std::mt19937_64 rng(3);
      std::normal_distribution<double> g(0.0, 0.5);
      for (Eigen::Index t = 0; t < y.rows(); ++t) y(t, 0) += g(rng), y(t, 1) += g(rng);
      sets::PropagatorOptions o;
      o.order = 3;
      o.past = 10;
      o.estimate_d = estimate_d;
      o.selection = selection;
      const auto id = sets::identify_propagator(u, y, o);
      const auto blocks = sets::regression_least_squares(id.regression), whole = whole_psi_least_squares(id.regression);
      ASSERT_EQ(blocks.rank, whole.rank);
      ASSERT_EQ(blocks.rank, id.regression.Psi.cols());
      EXPECT_LT((blocks.theta - whole.theta).norm(), 1e-12 * whole.theta.norm());
      EXPECT_EQ(blocks.theta, id.theta);
      // Equal input columns: the B columns of every state equation are equal.
      sets::CanonicalRegression equal = id.regression;
      const sets::CanonicalStructure& st = id.structure;
      for (int i = 0; i < st.nx(); ++i) equal.Psi.col(st.b_offset(i) + 1) = equal.Psi.col(st.b_offset(i));
      EXPECT_EQ(sets::regression_least_squares(equal).rank, whole_psi_least_squares(equal).rank);
      EXPECT_LT(sets::regression_least_squares(equal).rank, equal.Psi.cols());
      EXPECT_EQ(sets::regression_least_squares(equal).theta.size(), 0);
      // A column with entries in two equations: one QR of the whole Psi, the same answer.
      sets::CanonicalRegression mixed = id.regression;
      mixed.Psi(0, st.b_offset(st.nx() - 1)) += 0.5;
      const auto m1 = sets::regression_least_squares(mixed), m2 = whole_psi_least_squares(mixed);
      EXPECT_EQ(m1.rank, m2.rank);
      EXPECT_EQ(m1.theta, m2.theta);
    }
}
