#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Cholesky>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "sets/core/error.hpp"
#include "sets/examples/farah.hpp"
#include "sets/methods/ss_uncertainty/level_set_uncertainty.hpp"

namespace {

using sets::StateSpaceModel;

// A hand-made regression: 1 state equation (parameter 0) and 1 output equation (parameter 1)
// over three samples.
sets::CanonicalRegression tiny_regression() {
  sets::CanonicalRegression r;
  r.equations = 2;
  r.state_equations = 1;
  r.Psi = Eigen::MatrixXd::Zero(6, 2);
  r.y.resize(6);
  for (int t = 0; t < 3; ++t) {
    r.Psi(2 * t, 0) = 1.0;
    r.Psi(2 * t + 1, 1) = 1.0;
    r.equation.insert(r.equation.end(), {0, 1});
    r.sample.insert(r.sample.end(), {t, t});
  }
  r.y << 1.0, 10.0, 1.1, 13.0, 0.9, 7.0;  // state mean 1 (residuals +-0.1), output mean 10 (+-3)
  return r;
}

TEST(LevelSetUncertainty, ResidualSelectionsAndNorms) {
  const auto r = tiny_regression();
  sets::LevelSetOptions o;
  auto d = sets::level_set_domain(r, o);
  EXPECT_NEAR(d.theta[0], 1.0, 1e-12);
  EXPECT_NEAR(d.theta[1], 10.0, 1e-12);
  EXPECT_NEAR(d.ell, 3.0, 1e-12);
  EXPECT_NEAR(d.j_min, 0.5 * (0.01 + 0.01 + 9 + 9), 1e-12);
  EXPECT_NEAR(d.j_d, d.j_min + 9.0, 1e-12);
  o.residuals = sets::ResidualSelection::states;
  EXPECT_NEAR(sets::level_set_domain(r, o).ell, 0.1, 1e-12);
  o.residuals = sets::ResidualSelection::all;
  o.norm = sets::ResidualNorm::sample_euclidean;
  EXPECT_NEAR(sets::level_set_domain(r, o).ell, std::sqrt(9.01), 1e-12);
  o.norm = sets::ResidualNorm::per_equation;
  const auto pe = sets::level_set_domain(r, o);
  EXPECT_NEAR(pe.ell_per_equation[0], 0.1, 1e-12);
  EXPECT_NEAR(pe.ell_per_equation[1], 3.0, 1e-12);
  // Normalised criterion: dtheta_e^2 * 3 / l_e^2 <= 2 in each coordinate direction.
  const auto pbox = sets::outer_box(pe.ellipsoid);
  EXPECT_NEAR(pbox[0].upper() - 1.0, 0.1 * std::sqrt(2.0 / 3), 1e-9);
  EXPECT_NEAR(pbox[1].upper() - 10.0, 3.0 * std::sqrt(2.0 / 3), 1e-9);
  // Domain: 1/2 dtheta^T R dtheta <= l^2 with R = 3 I: half-axes sqrt(2 l^2 / 3).
  const auto box = sets::outer_box(d.ellipsoid);
  EXPECT_NEAR(box[1].upper() - 10.0, std::sqrt(2 * 9.0 / 3), 1e-9);
  EXPECT_GE(box[1].upper() - 10.0, std::sqrt(2 * 9.0 / 3));
}

// level_set_domain(id) reuses id.theta instead of factorising Psi again: the domain must be the
// one level_set_domain(id.regression) computes, to the last bit, under every residual norm.
TEST(LevelSetUncertainty, DomainFromIdentificationEqualsDomainFromRegression) {
  const auto sys = sets::farah::system();
  std::mt19937_64 rng(7);
  const auto data = sets::farah::simulate(sys, 300, 20.0, rng);
  sets::PropagatorOptions po;
  po.order = 3;
  po.past = 10;
  const auto id = sets::identify_propagator(data.u, data.y, po);
  for (const auto norm : {sets::ResidualNorm::entrywise, sets::ResidualNorm::sample_euclidean,
                          sets::ResidualNorm::per_equation}) {
    sets::LevelSetOptions o;
    o.norm = norm;
    const auto a = sets::level_set_domain(id, o), b = sets::level_set_domain(id.regression, o);
    EXPECT_EQ(a.theta, b.theta) << sets::to_string(norm);
    EXPECT_EQ(a.R, b.R);
    EXPECT_EQ(a.residuals, b.residuals);
    EXPECT_EQ(a.ell_per_equation, b.ell_per_equation);
    EXPECT_EQ(a.ell, b.ell);
    EXPECT_EQ(a.ell_row, b.ell_row);
    EXPECT_EQ(a.j_min, b.j_min);
    EXPECT_EQ(a.j_d, b.j_d);
    EXPECT_EQ(a.ellipsoid.center(), b.ellipsoid.center());
    EXPECT_EQ(a.ellipsoid.shape(), b.ellipsoid.shape());
  }
  sets::PropagatorResult empty;
  EXPECT_THROW(sets::level_set_domain(empty), sets::InputError);
}

TEST(LevelSetUncertainty, FpsLeavesOutRowsWithoutParametersAndReportsThem) {
  auto r = tiny_regression();
  r.Psi.row(1).setZero();  // a residual-only row (unit C row with D known)
  const auto fps = sets::regression_fps(r, 2.0);
  EXPECT_EQ(fps.size(), 5);
  ASSERT_EQ(fps.falsified_rows().size(), 1u);  // |10| > 2
  EXPECT_EQ(fps.falsified_rows()[0], 1);
  EXPECT_EQ(fps.contains(Eigen::Vector2d(1.0, 10.0)), sets::BoolInterval::no);  // the data contradict the bound
  EXPECT_TRUE(sets::pui(fps).empty());
  EXPECT_NE(sets::regression_fps(r, 10.0).contains(Eigen::Vector2d(1.0, 10.0)), sets::BoolInterval::no);
}

// Property: with bounded output noise |v| <= vbar and l >= vbar, the FPS of the canonical
// regression (built on the exact canonical states) contains the true parameters; and the true
// parameters inside the ellipsoid lie inside each of its pair projections.
RC_GTEST_PROP(LevelSetUncertainty, BoundedNoiseFpsContainsTruth, ()) {
  const auto sys = sets::farah::system();
  const auto rows = sets::select_rows(sys.A, sys.C, sets::RowSelection::output_major);
  const sets::CanonicalStructure st(rows, 2, 2, false);
  const auto canon = sets::canonical_form(sys, rows);
  const auto truth = st.to_parameters(canon);
  const unsigned seed = *rc::gen::arbitrary<unsigned>();
  const double vbar = *rc::gen::element(0.01, 0.1, 1.0, 5.0);
  const double factor = 1.0 + *rc::gen::inRange(0, 100) / 100.0;
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution coin(0.5);
  std::uniform_real_distribution<double> U(-vbar, vbar);
  const int N = 150;
  Eigen::MatrixXd u(N, 2), y(N, 2), X(3, N);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  for (int t = 0; t < N; ++t) {
    u.row(t) << (coin(rng) ? 1.0 : -1.0), (coin(rng) ? 1.0 : -1.0);
    X.col(t) = x;
    y.row(t) = (canon.C * x).transpose();
    y(t, 0) += U(rng);
    y(t, 1) += U(rng);
    x = canon.A * x + canon.B * u.row(t).transpose();
  }
  const auto reg = sets::canonical_regression(st, X, 0, u, y);
  const auto fps = sets::regression_fps(reg, factor * vbar);
  RC_ASSERT(fps.contains(truth) != sets::BoolInterval::no);
  const auto dom = sets::level_set_domain(reg);
  if (sets::contains(dom.ellipsoid, truth) == sets::BoolInterval::yes) {
    for (int i = 0; i < truth.size(); ++i)
      for (int j = i + 1; j < truth.size(); ++j) {
        const auto v = sets::pair_view(dom.ellipsoid, i, j);
        RC_ASSERT(sets::contains(v.projection, Eigen::Vector2d(truth[i], truth[j])) != sets::BoolInterval::no);
      }
  }
}

// A slice through the centre lies inside the projection (sampled on the slice's boundary).
RC_GTEST_PROP(LevelSetUncertainty, SliceLiesInsideProjection, ()) {
  const int n = *rc::gen::inRange(3, 7);
  std::mt19937_64 rng(*rc::gen::arbitrary<unsigned>());
  std::normal_distribution<double> g;
  Eigen::MatrixXd L(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) L(i, j) = g(rng);
  const Eigen::MatrixXd R = L * L.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd c(n);
  for (int i = 0; i < n; ++i) c[i] = g(rng);
  const auto E = sets::Ellipsoid::from_level_set(c, R, 2.0);
  const auto v = sets::pair_view(E, 0, n - 1);
  RC_ASSERT(v.slice.has_value());
  const Eigen::LLT<Eigen::MatrixXd> llt(v.slice->shape());
  const Eigen::MatrixXd Ls = llt.matrixL();
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * 3.141592653589793 * k / 16;
    const Eigen::Vector2d p = v.slice->center() + 0.999 * (Ls * Eigen::Vector2d(std::cos(a), std::sin(a)));
    RC_ASSERT(sets::contains(v.projection, p) != sets::BoolInterval::no);
  }
}

// ------------------------------------------------------------------ the app's bad-input paths

std::filesystem::path app_path() {
  return std::filesystem::path(SETS_BINARY_DIR) / "apps" / "sets-ss-uncertainty" / "sets-ss-uncertainty";
}

int run_app(const std::string& args) {
  const std::string cmd = app_path().string() + " " + args + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::filesystem::path write_csv(const std::string& name, bool constant_input) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream out(path);
  out << "time,u1,y1\n";
  std::mt19937 rng(3);
  double x = 0;
  for (int t = 0; t < 300; ++t) {
    const double u = constant_input ? 1.0 : (rng() % 2 ? 1.0 : -1.0);
    out << t << "," << u << "," << x << "\n";
    x = 0.5 * x + u;
  }
  return path;
}

TEST(SsUncertaintyApp, BadInputGivesExitCodeOne) {
  if (!std::filesystem::exists(app_path())) GTEST_SKIP() << "sets-ss-uncertainty not built";
  const auto good = write_csv("farah_good.csv", false);
  const auto flat = write_csv("farah_flat.csv", true);
  EXPECT_EQ(run_app("--data " + good.string() + " --inputs u1 --outputs y1 --order 1 --past 10"), 0);
  EXPECT_EQ(run_app("--data " + flat.string() + " --inputs u1 --outputs y1 --order 1 --past 10"), 1);  // constant input
  EXPECT_EQ(run_app("--data " + good.string() + " --inputs u1 --outputs y1 --order 12 --past 10"), 1);  // order > p
  EXPECT_EQ(run_app("--data " + good.string() + " --inputs u1 --outputs y1 --order 11 --past 11"), 1);  // > support
  EXPECT_EQ(run_app("--data " + good.string() + " --inputs u9 --outputs y1 --order 1"), 1);  // no such column
  EXPECT_EQ(run_app("--runs 2 --past 2"), 1);  // p < n_x in the simulation
  std::ofstream(std::filesystem::temp_directory_path() / "farah_bad.csv") << "u,y\n1,2\n1,x\n";
  EXPECT_EQ(run_app("--data " + (std::filesystem::temp_directory_path() / "farah_bad.csv").string() +
                    " --inputs u --outputs y --order 1"),
            1);
}

}  // namespace
