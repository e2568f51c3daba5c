// Feasible parameter sets and PUIs: soundness, tightness, exact 2-D comparison, falsification,
// bad input, and PUIs on several threads at once.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpq.h>

#include <random>
#include <thread>

#include "sets/core/error.hpp"
#include "sets/examples/bounded_error_regression.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/glpk_environment.hpp"
#include "sets/numeric/linear_program.hpp"

namespace {

using sets::FeasibleParameterSet;
using sets::IntervalMatrix;
using sets::IntervalVector;

struct Data {
  Eigen::MatrixXd Phi;
  Eigen::VectorXd y, delta, theta;
};

Data make_data(int p, int N, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Data d;
  d.theta = Eigen::VectorXd::NullaryExpr(p, [&] { return 2 * U(rng); });
  d.Phi = Eigen::MatrixXd::NullaryExpr(N, p, [&] { return U(rng); });
  d.delta = Eigen::VectorXd::NullaryExpr(N, [&] { return 0.05 + 0.1 * std::abs(U(rng)); });
  d.y = d.Phi * d.theta;
  for (int t = 0; t < N; ++t) d.y[t] += d.delta[t] * U(rng);
  return d;
}

}  // namespace

RC_GTEST_PROP(Pui, TrueParameterIsAlwaysInsideExactRegressors, ()) {
  const int p = *rc::gen::inRange(1, 6);
  const int N = *rc::gen::inRange(p + 1, 60);
  const Data d = make_data(p, N, *rc::gen::arbitrary<std::uint64_t>());
  const auto r = sets::pui(FeasibleParameterSet::from_data(d.Phi, d.y, d.delta));
  RC_ASSERT(r.consistency.certified_consistent());
  RC_ASSERT(r.guaranteed);
  RC_ASSERT(sets::contains(r.box, d.theta));
}

RC_GTEST_PROP(Pui, TrueParameterIsAlwaysInsideIntervalRegressors, ()) {
  // Errors in variables: each regressor entry is known only to an interval around the truth.
  const int p = *rc::gen::inRange(1, 5);
  const int N = *rc::gen::inRange(p + 2, 40);
  const auto seed = *rc::gen::arbitrary<std::uint64_t>();
  Data d = make_data(p, N, seed);
  std::mt19937_64 rng(seed + 1);
  std::uniform_real_distribution<double> U(0, 1);
  IntervalMatrix Phi(N, p);
  IntervalVector Y(N);
  for (int t = 0; t < N; ++t) {
    for (int j = 0; j < p; ++j) {
      const double r = 0.02 * U(rng), off = r * (2 * U(rng) - 1);
      Phi(t, j) = sets::interval_around(d.Phi(t, j) + off, r);
    }
    Y[t] = sets::interval_around(d.y[t], d.delta[t]);
  }
  const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
  RC_ASSERT(fps.contains(d.theta) != sets::BoolInterval::no);
  const auto all = sets::pui(fps, {.orthants = sets::OrthantSelection::all});
  RC_ASSERT(all.consistency.certified_consistent());
  RC_ASSERT(all.guaranteed);
  RC_ASSERT(sets::contains(all.box, d.theta));
}

RC_GTEST_PROP(Pui, EndsAreAttainedAndSampledPointsInside, ()) {
  const int p = *rc::gen::inRange(1, 5);
  const int N = *rc::gen::inRange(p + 1, 40);
  const Data d = make_data(p, N, *rc::gen::arbitrary<std::uint64_t>());
  const auto fps = FeasibleParameterSet::from_data(d.Phi, d.y, d.delta);
  const auto r = sets::pui(fps);
  RC_ASSERT(r.consistency.certified_consistent());
  const double tol = 1e-7;
  for (int l = 0; l < p; ++l) {
    for (const Eigen::VectorXd& x : {Eigen::VectorXd(r.lower_points.col(l)), Eigen::VectorXd(r.upper_points.col(l))}) {
      // feasible to LP tolerance
      const Eigen::VectorXd res = (d.y - d.Phi * x).cwiseAbs() - d.delta;
      RC_ASSERT(res.maxCoeff() <= tol);
    }
    RC_ASSERT(std::abs(r.lower_points(l, l) - r.box[l].lower()) <= tol * (1 + std::abs(r.box[l].lower())));
    RC_ASSERT(std::abs(r.upper_points(l, l) - r.box[l].upper()) <= tol * (1 + std::abs(r.box[l].upper())));
  }
  // Sample the box and keep the points the set certainly contains: all must be in the PUIs
  // (trivially) and, more to the point, convex combinations of attaining points stay feasible.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  for (int k = 0; k < 200; ++k) {
    Eigen::VectorXd x(p);
    for (int j = 0; j < p; ++j) x[j] = r.box[j].lower() + U(rng) * (r.box[j].upper() - r.box[j].lower());
    if (fps.contains(x) == sets::BoolInterval::yes) RC_ASSERT(sets::contains(r.box, x));
  }
}

// 2-D: the exact feasible polygon's vertices from all pairs of boundary lines in rational
// arithmetic; its bounding box must equal the PUI box to LP tolerance, and contain... inside it.
TEST(Pui, TwoDimensionalBoxEqualsExactPolygonBoundingBox) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Data d = make_data(2, 12, seed);
    const auto r = sets::pui(FeasibleParameterSet::from_data(d.Phi, d.y, d.delta));
    ASSERT_EQ(r.consistency.falsified, sets::Falsified::no);
    // half-planes a^T x <= b with exact data (y +- delta rounded outward as the FPS stores it)
    const auto fps = FeasibleParameterSet::from_data(d.Phi, d.y, d.delta);
    std::vector<std::array<CGAL::Gmpq, 3>> hp;  // a0, a1, b
    for (int t = 0; t < 12; ++t) {
      hp.push_back({d.Phi(t, 0), d.Phi(t, 1), fps.outputs()[t].upper()});
      hp.push_back({-d.Phi(t, 0), -d.Phi(t, 1), -fps.outputs()[t].lower()});
    }
    bool first = true;
    CGAL::Gmpq xmin, xmax, ymin, ymax;
    for (std::size_t i = 0; i < hp.size(); ++i)
      for (std::size_t j = i + 1; j < hp.size(); ++j) {
        const CGAL::Gmpq det = hp[i][0] * hp[j][1] - hp[i][1] * hp[j][0];
        if (det == 0) continue;
        const CGAL::Gmpq x = (hp[i][2] * hp[j][1] - hp[i][1] * hp[j][2]) / det;
        const CGAL::Gmpq y = (hp[i][0] * hp[j][2] - hp[i][2] * hp[j][0]) / det;
        bool ok = true;
        for (const auto& h : hp)
          if (h[0] * x + h[1] * y > h[2]) { ok = false; break; }
        if (!ok) continue;
        if (first || x < xmin) xmin = x;
        if (first || x > xmax) xmax = x;
        if (first || y < ymin) ymin = y;
        if (first || y > ymax) ymax = y;
        first = false;
      }
    ASSERT_FALSE(first) << "exact polygon empty for seed " << seed;
    // Guaranteed: the PUI box contains the exact bounding box ...
    EXPECT_LE(CGAL::Gmpq(r.box[0].lower()), xmin);
    EXPECT_GE(CGAL::Gmpq(r.box[0].upper()), xmax);
    EXPECT_LE(CGAL::Gmpq(r.box[1].lower()), ymin);
    EXPECT_GE(CGAL::Gmpq(r.box[1].upper()), ymax);
    // ... and is tight to LP tolerance.
    EXPECT_NEAR(r.box[0].lower(), xmin.to_double(), 1e-9);
    EXPECT_NEAR(r.box[0].upper(), xmax.to_double(), 1e-9);
    EXPECT_NEAR(r.box[1].lower(), ymin.to_double(), 1e-9);
    EXPECT_NEAR(r.box[1].upper(), ymax.to_double(), 1e-9);
  }
}

TEST(Pui, ConflictingDataAreReportedAsFalsification) {
  Data d = make_data(2, 30, 3);
  d.y[17] += 5;  // an outlier no parameter can explain within the bounds
  const auto r = sets::pui(FeasibleParameterSet::from_data(d.Phi, d.y, d.delta));
  ASSERT_TRUE(r.empty());
  EXPECT_EQ(r.consistency.falsified, sets::Falsified::yes);
  ASSERT_FALSE(r.consistency.conflict.samples.empty());
  EXPECT_NE(std::find(r.consistency.conflict.samples.begin(), r.consistency.conflict.samples.end(), 17),
            r.consistency.conflict.samples.end());
  EXPECT_NE(r.consistency.conflict.message().find("falsify"), std::string::npos);
}

TEST(Pui, BadInputNamesSampleAndField) {
  Data d = make_data(2, 10, 4);
  Eigen::VectorXd y = d.y;
  y[4] = NAN;
  try {
    FeasibleParameterSet::from_data(d.Phi, y, d.delta);
    FAIL();
  } catch (const sets::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sample 4"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("output"), std::string::npos);
  }
  Eigen::VectorXd delta = d.delta;
  delta[2] = -1;
  EXPECT_THROW(FeasibleParameterSet::from_data(d.Phi, d.y, delta), sets::InputError);
  EXPECT_THROW(FeasibleParameterSet::from_data(d.Phi.topRows(1), d.y.head(1), d.delta.head(1)),
               sets::InputError);
  EXPECT_THROW(FeasibleParameterSet::from_data(d.Phi, d.y.head(5), d.delta), sets::InputError);
}

TEST(Pui, PointRegressorColumnsAreNotSplitIntoOrthants) {
  // theta_1 has exact regressors and straddles 0; theta_0 has interval regressors. Remark 2 keeps
  // theta_1 free (sign 0) and reaches the same box as all orthants, with fewer pieces.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  const int N = 60;
  IntervalMatrix Phi(N, 2);
  IntervalVector Y(N);
  for (int t = 0; t < N; ++t) {
    const double a = U(rng), b = U(rng);
    Phi(t, 0) = sets::interval_around(a, 0.02);
    Phi(t, 1) = sets::Interval(b);
    Y[t] = sets::interval_around(0.8 * a + 0.01 * b, 0.1);
  }
  const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
  const auto r2 = sets::pui(fps);
  const auto all = sets::pui(fps, {.orthants = sets::OrthantSelection::all});
  ASSERT_FALSE(r2.empty());
  EXPECT_LT(r2.box[1].lower(), 0.0);
  EXPECT_GT(r2.box[1].upper(), 0.0);
  for (const auto& o : r2.orthants) EXPECT_EQ(o.signs.at(1), 0);
  EXPECT_LT(r2.orthants.size(), all.orthants.size());
  for (int j = 0; j < 2; ++j) {
    EXPECT_NEAR(r2.box[j].lower(), all.box[j].lower(), 1e-9);
    EXPECT_NEAR(r2.box[j].upper(), all.box[j].upper(), 1e-9);
  }
}

TEST(Pui, RemarkTwoExtendsAcrossZeroBounds) {
  // theta_2 = 0 exactly: the set straddles the face theta_2 = 0 and Remark 2 must visit both sides.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  const int N = 50;
  IntervalMatrix Phi(N, 2);
  IntervalVector Y(N);
  for (int t = 0; t < N; ++t) {
    const double a = U(rng), b = U(rng);
    Phi(t, 0) = sets::interval_around(a, 0.01);
    Phi(t, 1) = sets::interval_around(b, 0.01);
    Y[t] = sets::interval_around(0.7 * a + 0.0 * b, 0.05);
  }
  const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
  const auto r2 = sets::pui(fps);
  const auto all = sets::pui(fps, {.orthants = sets::OrthantSelection::all});
  EXPECT_GE(r2.orthants.size(), 2u);
  EXPECT_LT(r2.box[1].lower(), 0.0);
  EXPECT_GT(r2.box[1].upper(), 0.0);
  EXPECT_NEAR(r2.box[1].lower(), all.box[1].lower(), 1e-9);
  EXPECT_NEAR(r2.box[1].upper(), all.box[1].upper(), 1e-9);
}

TEST(Pui, RemarkTwoVisitsTheNextOrthantUnlessACertifiedEndProvesTheSetStaysOff) {
  // theta_0 + eps theta_1 >= 1e-5 with theta_1 in [1, L], L eps = 2e-5: the set crosses
  // theta_0 = 0 (down to theta_0 = -1e-5 at theta_1 = L), but only along an edge on which
  // theta_0 falls at the rate eps. GLPK stops minimising theta_0 at the vertex theta_1 = 1
  // (a reduced cost of eps is below its tolerance): floating-point end ~1e-5, far above the
  // 1e-9 tolerance, so the old rule never visited theta_0 < 0 and marked a PUI guaranteed
  // that missed (-5e-6, 0.9 L). The certified end of that piece is 0: the face is reached.
  for (const double eps : {1e-7, 1e-8}) {
    const double L = 2e-5 / eps;
    IntervalMatrix Phi(3, 2);
    IntervalVector Y(3);
    Phi(0, 0) = sets::Interval(1.0), Phi(0, 1) = sets::Interval(eps), Y[0] = sets::Interval(1e-5, 1.0);
    Phi(1, 0) = sets::Interval(0.0), Phi(1, 1) = sets::Interval(1.0), Y[1] = sets::Interval(1.0, L);
    Phi(2, 0) = sets::Interval(0.5, 0.5000001), Phi(2, 1) = sets::Interval(0.0), Y[2] = sets::Interval(-1.0, 1.0);
    const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
    const Eigen::Vector2d member(-5e-6, 0.9 * L);
    ASSERT_EQ(fps.contains(member), sets::BoolInterval::yes);
    for (const auto solver : {sets::PuiLpSolver::glpk, sets::PuiLpSolver::dense}) {
      const std::string where = (eps == 1e-7 ? "eps 1e-7" : "eps 1e-8") + std::string(solver == sets::PuiLpSolver::glpk ? ", GLPK" : ", dense");
      const sets::PuiResult r = sets::pui(fps, {.solver = solver});
      ASSERT_FALSE(r.empty()) << where;
      EXPECT_TRUE(sets::contains(r.box, member)) << where << ": theta_0 in [" << r.box[0].lower() << ", "
                                                  << r.box[0].upper() << "]";
      EXPECT_GE(r.orthants.size(), 2u) << where;
    }
  }
}

TEST(Pui, RemarkTwoFindsAPieceNotConnectedToTheLeastSquaresOrthant) {
  // phi in [-1, 1] with phi theta in [1, 2] holds for |theta| >= 1 only: the set is
  // [-5, -1] u [1, 5], two pieces that touch no face theta = 0. The least-squares estimate is
  // 0 (sign +); following faces alone gave a guaranteed PUI [1, 5] that missed theta = -3.
  IntervalMatrix Phi(2, 1);
  IntervalVector Y(2);
  Phi(0, 0) = sets::Interval(-1.0, 1.0), Y[0] = sets::Interval(1.0, 2.0);
  Phi(1, 0) = sets::Interval(1.0), Y[1] = sets::Interval(-5.0, 5.0);
  const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
  ASSERT_EQ(fps.contains(Eigen::VectorXd::Constant(1, -3.0)), sets::BoolInterval::yes);
  ASSERT_EQ(fps.contains(Eigen::VectorXd::Constant(1, 3.0)), sets::BoolInterval::yes);
  const sets::PuiResult r = sets::pui(fps);
  ASSERT_FALSE(r.empty());
  EXPECT_TRUE(r.guaranteed);
  EXPECT_LE(r.box[0].lower(), -5.0);
  EXPECT_GE(r.box[0].upper(), 5.0);
  EXPECT_EQ(r.orthants.size(), 2u);
}

TEST(Pui, RemarkTwoSkipsOnlyOrthantsAProvenBoxMisses) {
  // Narrow regressor intervals and theta far from every face: the box proven from p samples
  // lies in one orthant, so the other 2^3 - 1 are skipped without an LP, and the PUI is the
  // one of all orthants.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  const Eigen::Vector3d theta(0.8, -0.5, 1.2);
  const int N = 80;
  IntervalMatrix Phi(N, 3);
  IntervalVector Y(N);
  for (int t = 0; t < N; ++t) {
    Eigen::Vector3d phi(U(rng), U(rng), U(rng));
    for (int j = 0; j < 3; ++j) Phi(t, j) = sets::interval_around(phi[j], 0.001);
    Y[t] = sets::interval_around(phi.dot(theta) + 0.01 * U(rng), 0.02);
  }
  const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
  const sets::PuiResult r2 = sets::pui(fps);
  const sets::PuiResult all = sets::pui(fps, {.orthants = sets::OrthantSelection::all});
  EXPECT_TRUE(r2.guaranteed);
  EXPECT_EQ(r2.orthants.size(), 1u);
  EXPECT_EQ(all.orthants.size(), 8u);
  EXPECT_TRUE(sets::contains(r2.box, theta));
  for (int j = 0; j < 3; ++j) {
    EXPECT_EQ(r2.box[j].lower(), all.box[j].lower()) << j;
    EXPECT_EQ(r2.box[j].upper(), all.box[j].upper()) << j;
  }
}

TEST(Pui, SeveralThreadsAtOnceGiveTheSameAnswers) {
  // GLPK is not reentrant across problem objects shared between threads; each PUI call builds
  // its own problems on its own thread, which must be safe.
  std::vector<Data> data;
  std::vector<sets::PuiResult> serial;
  for (int k = 0; k < 8; ++k) {
    data.push_back(make_data(4, 300, 100 + k));
    serial.push_back(sets::pui(FeasibleParameterSet::from_data(data[k].Phi, data[k].y, data[k].delta)));
  }
  std::vector<sets::PuiResult> parallel(8);
  std::vector<std::thread> threads;
  for (int k = 0; k < 8; ++k)
    threads.emplace_back([&, k] {
      const sets::GlpkThreadEnvironment glpk;  // freed when the thread ends
      for (int rep = 0; rep < 3; ++rep)
        parallel[k] = sets::pui(FeasibleParameterSet::from_data(data[k].Phi, data[k].y, data[k].delta));
    });
  for (auto& t : threads) t.join();
  for (int k = 0; k < 8; ++k)
    for (int l = 0; l < 4; ++l) {
      EXPECT_EQ(parallel[k].box[l].lower(), serial[k].box[l].lower());
      EXPECT_EQ(parallel[k].box[l].upper(), serial[k].box[l].upper());
    }
}

// ---------------------------------------------------------------- support in any direction

namespace {

// Rejection samples of the set (points that `contains` certifies), drawn in the PUI box.
std::vector<Eigen::VectorXd> sample_set(const FeasibleParameterSet& fps, const IntervalVector& box, int tries,
                                        std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<Eigen::VectorXd> out;
  for (int k = 0; k < tries; ++k) {
    Eigen::VectorXd x(fps.dimension());
    for (int j = 0; j < x.size(); ++j) x[j] = box[j].lower() + U(rng) * (box[j].upper() - box[j].lower());
    if (fps.contains(x) == sets::BoolInterval::yes) out.push_back(x);
  }
  return out;
}

// Certified lower end of d^T x (x exact doubles): the check must not be fooled by rounding.
double dot_lower(const Eigen::VectorXd& d, const Eigen::VectorXd& x) {
  sets::Interval s(0.0);
  for (Eigen::Index j = 0; j < d.size(); ++j) s += sets::Interval(d[j]) * sets::Interval(x[j]);
  return s.lower();
}

std::vector<Eigen::VectorXd> random_directions(int p, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> G(0, 1);
  std::vector<Eigen::VectorXd> dirs;
  for (int k = 0; k < count; ++k) dirs.push_back(Eigen::VectorXd::NullaryExpr(p, [&] { return G(rng); }));
  return dirs;
}

}  // namespace

// Every point of the set (the true parameter and certified samples) lies below the support in
// every direction, and the support is tight: the H-polytope of the same strips (certified the
// same way, but with every row in one LP) gives the same values to LP tolerance.
RC_GTEST_PROP(FpsSupport, BoundsEverySampledPointAndMatchesThePolytope, ()) {
  const int p = *rc::gen::inRange(1, 5);
  const int N = *rc::gen::inRange(p + 1, 300);
  const auto seed = *rc::gen::arbitrary<std::uint64_t>();
  const Data d = make_data(p, N, seed);
  const auto fps = FeasibleParameterSet::from_data(d.Phi, d.y, d.delta);
  const auto dirs = random_directions(p, 12, seed + 2);
  sets::PuiOptions opt;
  opt.working_set = *rc::gen::arbitrary<bool>();
  const sets::FpsSupport s = sets::support(fps, dirs, opt);
  RC_ASSERT(s.consistency.certified_consistent());
  RC_ASSERT(s.guaranteed);
  RC_ASSERT(s.maxima.size() == dirs.size());
  std::vector<Eigen::VectorXd> points = sample_set(fps, s.box, 300, seed + 3);
  points.push_back(d.theta);
  RC_TAG(points.size() > 1 ? "sampled points" : "only the true parameter");
  const std::vector<double> poly = sets::support(fps.orthant_polytope({}), dirs);
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    RC_ASSERT(std::isfinite(s.maxima[k]));
    for (const auto& x : points) RC_ASSERT(dot_lower(dirs[k], x) <= s.maxima[k]);
    RC_ASSERT(std::abs(s.maxima[k] - poly[k]) <= 1e-6 * (1 + std::abs(poly[k])));
  }
}

// Interval regressors, every orthant: each orthant piece is an exact polyhedron, so the support
// is the largest of the pieces' supports.
RC_GTEST_PROP(FpsSupport, IntervalRegressorsTakeTheLargestOrthantPiece, ()) {
  const int p = *rc::gen::inRange(1, 4);
  const int N = *rc::gen::inRange(p + 2, 40);
  const auto seed = *rc::gen::arbitrary<std::uint64_t>();
  const Data d = make_data(p, N, seed);
  std::mt19937_64 rng(seed + 1);
  std::uniform_real_distribution<double> U(0, 1);
  IntervalMatrix Phi(N, p);
  IntervalVector Y(N);
  for (int t = 0; t < N; ++t) {
    for (int j = 0; j < p; ++j) Phi(t, j) = sets::interval_around(d.Phi(t, j), 0.02 * U(rng));
    Y[t] = sets::interval_around(d.y[t], d.delta[t]);
  }
  const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
  const auto dirs = random_directions(p, 6, seed + 2);
  const sets::FpsSupport s = sets::support(fps, dirs, {.orthants = sets::OrthantSelection::all});
  RC_ASSERT(s.consistency.certified_consistent());
  RC_ASSERT(s.guaranteed);
  std::vector<double> best(dirs.size(), -sets::inf);
  for (const auto& o : sets::all_orthants(p)) {
    const auto P = fps.orthant_polytope(o);
    if (sets::is_empty(P) == sets::BoolInterval::yes) continue;
    const auto v = sets::support(P, dirs);
    for (std::size_t k = 0; k < dirs.size(); ++k) best[k] = std::max(best[k], v[k]);
  }
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    RC_ASSERT(dot_lower(dirs[k], d.theta) <= s.maxima[k]);
    RC_ASSERT(std::abs(s.maxima[k] - best[k]) <= 1e-6 * (1 + std::abs(best[k])));
  }
}

TEST(FpsSupport, EmptySetAndBadDirections) {
  Eigen::MatrixXd Phi(3, 1);
  Phi << 1, 1, 1;
  const auto fps = FeasibleParameterSet::from_data(Phi, Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::Constant(0.1));
  const auto s = sets::support(fps, {Eigen::VectorXd::Ones(1)});
  EXPECT_TRUE(s.empty());
  EXPECT_FALSE(s.consistency.conflict.samples.empty());
  EXPECT_EQ(s.maxima[0], -sets::inf);
  EXPECT_THROW(sets::support(fps, {Eigen::VectorXd::Ones(2)}), sets::InputError);
}

// An unbounded set: bounded directions keep a finite value only if certifiable; unbounded ones
// are +inf, never a finite number.
TEST(FpsSupport, UnboundedDirectionIsInfinite) {
  Eigen::MatrixXd Phi(4, 2);
  Phi << 1, 0, 1, 0, 2, 0, 1, 0;  // theta_2 is not constrained at all
  const auto fps = FeasibleParameterSet::from_data(Phi, Eigen::Vector4d(1, 1, 2, 1), Eigen::Vector4d::Constant(0.1));
  const auto s = sets::support(fps, {Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 1)});
  ASSERT_EQ(s.consistency.falsified, sets::Falsified::no);
  EXPECT_EQ(s.maxima[0], sets::inf);
  EXPECT_EQ(s.maxima[1], sets::inf);
}

// add_strip grows its storage geometrically; the set it builds is the same as from_data's.
TEST(FeasibleParameterSet, AddStripBuildsTheSameSetAsFromData) {
  const Data d = make_data(3, 5000, 11);
  const auto bulk = FeasibleParameterSet::from_data(d.Phi, d.y, d.delta);
  FeasibleParameterSet grown(3);
  for (int t = 0; t < 5000; ++t) grown.add_strip(d.Phi.row(t).transpose(), d.y[t], d.delta[t]);
  ASSERT_EQ(grown.size(), bulk.size());
  ASSERT_EQ(grown.regressors().rows(), 5000);
  for (int t = 0; t < 5000; ++t) {
    for (int j = 0; j < 3; ++j) ASSERT_EQ(grown.regressors()(t, j).lower(), bulk.regressors()(t, j).lower());
    ASSERT_EQ(grown.outputs()[t].lower(), bulk.outputs()[t].lower());
    ASSERT_EQ(grown.outputs()[t].upper(), bulk.outputs()[t].upper());
  }
  const auto a = sets::pui(grown), b = sets::pui(bulk);
  for (int j = 0; j < 3; ++j) {
    EXPECT_EQ(a.box[j].lower(), b.box[j].lower());
    EXPECT_EQ(a.box[j].upper(), b.box[j].upper());
  }
  EXPECT_EQ(grown.contains(d.theta), bulk.contains(d.theta));
}

// Column scales are powers of 2 that bring each column's largest |entry| into [1, 2), exact for
// every entry (1 where not: a zero column, or entries spread beyond the normal exponent range),
// and they follow the strips as they are added (the same whether built in bulk or strip by strip).
TEST(FeasibleParameterSet, ColumnScalesArePowersOfTwoThatKeepEveryEntryExact) {
  const double tiny = std::ldexp(1.0, -1070);  // subnormal
  Eigen::MatrixXd Phi(4, 4);
  Phi << 3e-10, 0, 5e12, 4.0,
         -1e-11, 0, 1.0, tiny,
         2e-10, 0, -7e11, 0.5,
         1e-10, 0, 2.0, 1.0;
  const Eigen::Vector4d y(1, 2, 3, 4), delta = Eigen::Vector4d::Constant(0.1);
  const auto bulk = FeasibleParameterSet::from_data(Phi, y, delta);
  const Eigen::VectorXd d = bulk.column_scales();
  ASSERT_EQ(d.size(), 4);
  for (int j : {0, 2}) {
    const double big = Phi.col(j).cwiseAbs().maxCoeff();
    EXPECT_EQ(d[j], std::ldexp(1.0, -std::ilogb(big))) << j;
    EXPECT_GE(big * d[j], 1.0);
    EXPECT_LT(big * d[j], 2.0);
    for (int t = 0; t < 4; ++t) EXPECT_EQ(Phi(t, j) * d[j] / d[j], Phi(t, j));  // exact
  }
  EXPECT_EQ(d[1], 1.0);  // all zero
  EXPECT_EQ(d[3], 1.0);  // 1/4 would round the subnormal entry
  FeasibleParameterSet grown(4);
  for (int t = 0; t < 4; ++t) {
    grown.add_strip(Phi.row(t).transpose(), y[t], delta[t]);
    EXPECT_EQ(grown.column_scales()[2], std::ldexp(1.0, -std::ilogb(Phi.col(2).head(t + 1).cwiseAbs().maxCoeff())));
  }
  EXPECT_EQ(grown.column_scales(), d);
  // A column whose entries span more than the normal range keeps scale 1.
  Eigen::MatrixXd wide(2, 1);
  wide << 1e300, tiny;
  const auto w = FeasibleParameterSet::from_data(wide, Eigen::Vector2d(1, 1), Eigen::Vector2d(1, 1));
  EXPECT_EQ(w.column_scales()[0], 1.0);
  wide(1, 0) = 1e-5;  // 2^-996 * 1e-5 is still normal: scaled
  EXPECT_EQ(FeasibleParameterSet::from_data(wide, Eigen::Vector2d(1, 1), Eigen::Vector2d(1, 1)).column_scales()[0],
            std::ldexp(1.0, -std::ilogb(1e300)));
}

// The verdict alone (diagnosis windows use it): consistent data are proven consistent, an
// outlier is proven to falsify the model, and the verdict agrees with pui()'s.
TEST(Consistency, VerdictAgreesWithPui) {
  Data d = make_data(3, 40, 21);
  const auto good = FeasibleParameterSet::from_data(d.Phi, d.y, d.delta);
  EXPECT_EQ(sets::check_consistency(good).falsified, sets::Falsified::no);
  d.y[5] += 10;
  const auto bad = FeasibleParameterSet::from_data(d.Phi, d.y, d.delta);
  const auto v = sets::check_consistency(bad);
  EXPECT_EQ(v.falsified, sets::Falsified::yes);
  EXPECT_EQ(v.falsified, sets::pui(bad).consistency.falsified);
  EXPECT_NE(std::find(v.conflict.samples.begin(), v.conflict.samples.end(), 5), v.conflict.samples.end());
  EXPECT_NE(v.message().find("falsify"), std::string::npos);
}

namespace {

// Exact membership of theta in the set of one sample, in rationals: the range of phi^T theta
// over the regressor box meets the output interval.
bool exact_sample_member(const sets::IntervalVector& Phi, const sets::Interval& Y, const Eigen::VectorXd& theta) {
  CGAL::Gmpq lo(0), hi(0);
  for (Eigen::Index j = 0; j < theta.size(); ++j) {
    const CGAL::Gmpq a = CGAL::Gmpq(Phi[j].lower()) * CGAL::Gmpq(theta[j]);
    const CGAL::Gmpq b = CGAL::Gmpq(Phi[j].upper()) * CGAL::Gmpq(theta[j]);
    lo += a < b ? a : b;
    hi += a < b ? b : a;
  }
  return lo <= CGAL::Gmpq(Y.upper()) && hi >= CGAL::Gmpq(Y.lower());
}

}  // namespace

// contains() (one rounding-mode switch for the whole loop) never contradicts exact rational
// arithmetic, also for points placed exactly on a strip's boundary, where rounding decides.
RC_GTEST_PROP(FeasibleParameterSet, ContainsAgreesWithExactArithmetic, ()) {
  const int p = *rc::gen::inRange(1, 6);
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  std::uniform_real_distribution<double> U(-1, 1);
  const bool eiv = *rc::gen::arbitrary<bool>();
  const Eigen::VectorXd theta = Eigen::VectorXd::NullaryExpr(p, [&] { return 3 * U(rng) / 7; });
  const int N = 6;  // >= p
  IntervalMatrix Phi(N, p);
  IntervalVector Y(N);
  for (int t = 0; t < N; ++t) {
    double centre = 0;
    for (int j = 0; j < p; ++j) {
      const double c = U(rng) / 3, r = eiv ? std::abs(U(rng)) / 10 : 0.0;
      Phi(t, j) = sets::Interval(c - r, c + r);  // c - r, c + r are doubles: the box is what it says
      centre += c * theta[j];                    // round-to-nearest: a point near the boundary
    }
    // Output interval ending (almost) exactly where the sample's range starts or ends.
    const double w = *rc::gen::arbitrary<bool>() ? 0.0 : std::abs(U(rng));
    switch (*rc::gen::inRange(0, 3)) {
      case 0: Y[t] = sets::Interval(centre - 2 * w - 1, centre - w); break;
      case 1: Y[t] = sets::Interval(centre + w, centre + 2 * w + 1); break;
      default: Y[t] = sets::Interval(centre - w, centre + w); break;
    }
  }
  const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
  bool member = true;
  for (int t = 0; t < N; ++t) member = member && exact_sample_member(Phi.row(t).transpose(), Y[t], theta);
  const sets::BoolInterval v = fps.contains(theta);
  if (member) RC_ASSERT(v != sets::BoolInterval::no);
  if (!member) RC_ASSERT(v != sets::BoolInterval::yes);
  // The same verdict as Boost's interval operations row by row (contains() sums the same ends
  // column by column in one rounding scope): no undecided point where intervals decide.
  sets::BoolInterval reference = sets::BoolInterval::yes;
  for (int t = 0; t < N && reference != sets::BoolInterval::no; ++t) {
    sets::Interval lo(0.0), hi(0.0);
    for (int j = 0; j < p; ++j) {
      const sets::Interval a = Phi(t, j).lower() * sets::Interval(theta[j]), b = Phi(t, j).upper() * sets::Interval(theta[j]);
      lo += theta[j] >= 0 ? a : b;
      hi += theta[j] >= 0 ? b : a;
    }
    if (lo.lower() > Y[t].upper() || hi.upper() < Y[t].lower()) reference = sets::BoolInterval::no;
    else if (!(lo.upper() <= Y[t].upper() && hi.lower() >= Y[t].lower())) reference = sets::BoolInterval::unknown;
  }
  RC_ASSERT(static_cast<int>(v) == static_cast<int>(reference));
}

// ---------------------------------------------------------------- dense simplex versus GLPK
// pui() finds the LP optima with the dense simplex by default and with GLPK on request; both
// ends are Neumaier–Shcherbina bounds from the solver's multipliers, so on the same data they
// must agree to LP tolerance, both contain the true parameters, and the dense solver must
// answer most LPs itself (else the comparison would test GLPK against GLPK).
namespace {

sets::PuiOptions with_solver(sets::PuiLpSolver solver, sets::PuiOptions o = {}) {
  o.solver = solver;
  return o;
}

// The two boxes are the same to LP tolerance (relative to the box's size).
void require_same_box(const IntervalVector& a, const IntervalVector& b) {
  RC_ASSERT(a.size() == b.size());
  for (Eigen::Index j = 0; j < a.size(); ++j)
    for (const auto& [u, v] : {std::pair{a[j].lower(), b[j].lower()}, std::pair{a[j].upper(), b[j].upper()}}) {
      if (std::isinf(u) || std::isinf(v)) {
        RC_ASSERT(u == v);
        continue;
      }
      const double scale = 1 + std::abs(b[j].upper()) + std::abs(b[j].lower());
      RC_ASSERT(std::abs(u - v) <= 1e-7 * scale);
    }
}

void require_same_pui(const sets::PuiResult& dense, const sets::PuiResult& glpk) {
  RC_ASSERT(static_cast<int>(dense.consistency.falsified) == static_cast<int>(glpk.consistency.falsified));
  RC_ASSERT(dense.guaranteed == glpk.guaranteed);
  RC_ASSERT(dense.orthants.size() == glpk.orthants.size());
  for (std::size_t k = 0; k < dense.orthants.size(); ++k) {
    RC_ASSERT(dense.orthants[k].signs == glpk.orthants[k].signs);
    RC_ASSERT(static_cast<int>(dense.orthants[k].status) == static_cast<int>(glpk.orthants[k].status));
  }
  require_same_box(dense.box, glpk.box);
  RC_ASSERT(glpk.lp_fallbacks == 0);
  RC_ASSERT(dense.lp_fallbacks * 4 <= dense.lp_solves);
}

}  // namespace

RC_GTEST_PROP(PuiDenseSolver, SameCertifiedBoxAsGlpkExactRegressors, ()) {
  const int p = *rc::gen::inRange(1, 9);
  const int N = *rc::gen::inRange(p + 1, 400);  // beyond 10p + 10: row generation at work
  const Data d = make_data(p, N, *rc::gen::arbitrary<std::uint64_t>());
  const auto fps = FeasibleParameterSet::from_data(d.Phi, d.y, d.delta);
  const bool warm = *rc::gen::arbitrary<bool>();
  const auto dense = sets::pui(fps, with_solver(sets::PuiLpSolver::dense, {.warm_start = warm}));
  const auto glpk = sets::pui(fps, with_solver(sets::PuiLpSolver::glpk, {.warm_start = warm}));
  RC_ASSERT(dense.guaranteed);
  RC_ASSERT(sets::contains(dense.box, d.theta));
  require_same_pui(dense, glpk);
}

RC_GTEST_PROP(PuiDenseSolver, SameCertifiedBoxAsGlpkIntervalRegressors, ()) {
  const int p = *rc::gen::inRange(1, 6);
  const int N = *rc::gen::inRange(p + 2, 200);
  const auto seed = *rc::gen::arbitrary<std::uint64_t>();
  const Data d = make_data(p, N, seed);
  std::mt19937_64 rng(seed + 1);
  std::uniform_real_distribution<double> U(0, 1);
  IntervalMatrix Phi(N, p);
  IntervalVector Y(N);
  for (int t = 0; t < N; ++t) {
    for (int j = 0; j < p; ++j) {
      const double r = (j % 2 == 0 ? 0.02 : 0.0) * U(rng), off = r * (2 * U(rng) - 1);  // mixed point/interval columns
      Phi(t, j) = sets::interval_around(d.Phi(t, j) + off, r);
    }
    Y[t] = sets::interval_around(d.y[t], d.delta[t]);
  }
  const auto fps = FeasibleParameterSet::from_interval_data(Phi, Y);
  const bool every_orthant = *rc::gen::arbitrary<bool>();
  const auto orthants = every_orthant ? sets::OrthantSelection::all : sets::OrthantSelection::remark2;
  const auto dense = sets::pui(fps, with_solver(sets::PuiLpSolver::dense, {.orthants = orthants}));
  const auto glpk = sets::pui(fps, with_solver(sets::PuiLpSolver::glpk, {.orthants = orthants}));
  if (every_orthant) {
    RC_ASSERT(dense.guaranteed);
    RC_ASSERT(sets::contains(dense.box, d.theta));
  }
  require_same_pui(dense, glpk);
}

// Degenerate sets through both solvers: empty (two strips that cannot meet), a direction the
// data do not bound, every sample twice, samples with a zero regressor, and delta = 0 (a flat
// set: equality rows).
TEST(PuiDenseSolver, DegenerateSetsAgreeWithGlpk) {
  const auto both = [](const FeasibleParameterSet& fps) {
    return std::pair{sets::pui(fps, with_solver(sets::PuiLpSolver::dense)),
                     sets::pui(fps, with_solver(sets::PuiLpSolver::glpk))};
  };
  const auto same_box = [](const IntervalVector& a, const IntervalVector& b) {
    ASSERT_EQ(a.size(), b.size());
    for (Eigen::Index j = 0; j < a.size(); ++j)
      for (const auto& [u, v] : {std::pair{a[j].lower(), b[j].lower()}, std::pair{a[j].upper(), b[j].upper()}}) {
        if (std::isinf(v))
          EXPECT_EQ(u, v) << j;
        else
          EXPECT_NEAR(u, v, 1e-9 * (1 + std::abs(v))) << j;
      }
  };
  {  // empty: theta in [-0.1, 0.1] and in [0.9, 1.1]
    Eigen::MatrixXd Phi(3, 1);
    Phi << 1, 1, 1;
    const auto [dense, glpk] = both(FeasibleParameterSet::from_data(Phi, Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::Constant(0.1)));
    EXPECT_TRUE(dense.empty());
    EXPECT_TRUE(glpk.empty());
  }
  {  // theta_2 unconstrained: infinite ends, never a finite number
    Eigen::MatrixXd Phi(4, 2);
    Phi << 1, 0, 1, 0, 2, 0, 1, 0;
    const auto [dense, glpk] =
        both(FeasibleParameterSet::from_data(Phi, Eigen::Vector4d(1, 1, 2, 1), Eigen::Vector4d::Constant(0.1)));
    ASSERT_FALSE(dense.empty());
    EXPECT_EQ(dense.box[1].lower(), -sets::inf);
    EXPECT_EQ(dense.box[1].upper(), sets::inf);
    same_box(dense.box, glpk.box);
  }
  {  // duplicates, zero regressors, and delta = 0
    const Data d = make_data(3, 30, 5);
    Eigen::MatrixXd Phi(62, 3);
    Eigen::VectorXd y(62), delta(62);
    Phi << d.Phi, d.Phi, Eigen::RowVector3d::Zero(), Eigen::RowVector3d::Zero();
    y << d.y, d.y, 0.0, 0.01;
    delta << d.delta, d.delta, 0.0, 0.05;
    const auto [dense, glpk] = both(FeasibleParameterSet::from_data(Phi, y, delta));
    EXPECT_TRUE(dense.guaranteed);
    EXPECT_TRUE(sets::contains(dense.box, d.theta));
    same_box(dense.box, glpk.box);
    // delta = 0 for one sample: the set is flat in one direction; still both agree.
    Eigen::VectorXd flat = delta;
    flat[0] = 0;
    Eigen::VectorXd y_flat = y;
    y_flat[0] = d.Phi.row(0).dot(d.theta);
    const auto [fd, fg] = both(FeasibleParameterSet::from_data(Phi, y_flat, flat));
    EXPECT_EQ(static_cast<int>(fd.consistency.falsified), static_cast<int>(fg.consistency.falsified));
    same_box(fd.box, fg.box);
  }
}

TEST(Pui, BadlyScaledColumnsTheFiveMissesOfTheSoundnessCampaign) {
  // Columns scaled by 10^-10..10^10: GLPK's absolute tolerances took the 1e-10 columns for zero
  // (false "unbounded") and stopped the 1e10 columns' objectives at a wrong vertex, so the
  // floating-point extent had width-0 intervals that missed theta (seeds 752, 4112, 4502, 9087,
  // 9662 of the 10 000). The LP now runs on exactly column-scaled data, and a box whose ends
  // cannot be certified is never the floating-point extent.
  for (unsigned long seed : {752ul, 4112ul, 4502ul, 9087ul, 9662ul}) {
    const sets::BoundedErrorRegression problem = sets::bounded_error_regression(seed);
    ASSERT_TRUE(problem.kind == sets::RegressionKind::badly_scaled);
    const sets::PuiResult r = sets::pui(problem.fps, problem.options);
    const std::string where = "seed " + std::to_string(seed);
    EXPECT_EQ(r.consistency.falsified, sets::Falsified::no) << where;
    EXPECT_TRUE(sets::contains(r.box, problem.theta)) << where;
    EXPECT_TRUE(r.guaranteed) << where;
    EXPECT_TRUE(sets::lower(r.box).allFinite() && sets::upper(r.box).allFinite()) << where;
    for (Eigen::Index j = 0; j < r.box.size(); ++j)  // tight: a real interval, not a point
      EXPECT_LT(r.box[j].lower(), r.box[j].upper()) << where << ", theta_" << j;
  }
}

TEST(Pui, NearCollinearRegressorsGetFiniteProvenEndsWhereTheLpSaidUnbounded) {
  // Columns a_j c + eps_j z with eps_j down to 1e-10: the set is bounded (the regressors have
  // full column rank) but extremely long, and GLPK called it unbounded (seed 8) or found no
  // feasible point without a certificate of emptiness (seed 3, an undecided orthant): every end
  // was infinite. A box proven from p samples (verified inverse), tightened by safe bounds of
  // the LP over it, bounds every end; it must hold the truth.
  for (unsigned long seed : {3ul, 8ul}) {
    const sets::BoundedErrorRegression problem = sets::bounded_error_regression(seed);
    ASSERT_TRUE(problem.kind == sets::RegressionKind::near_collinear);
    const sets::PuiResult r = sets::pui(problem.fps, problem.options);
    const std::string where = "seed " + std::to_string(seed);
    EXPECT_NE(r.consistency.falsified, sets::Falsified::yes) << where;
    EXPECT_TRUE(sets::lower(r.box).allFinite() && sets::upper(r.box).allFinite()) << where;
    EXPECT_TRUE(sets::contains(r.box, problem.theta)) << where;
  }
}

TEST(Pui, AGenuinelyUnboundedDirectionKeepsItsInfiniteEnds) {
  // Two identical regressor columns: theta_0 - theta_1 is free (the ray (1, -1, 0) has
  // phi . d = 0 on every sample), so theta_0 and theta_1 are unbounded both ways, and no proven
  // box may make them finite.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd Phi(30, 3);
  Eigen::VectorXd y(30), delta = Eigen::VectorXd::Constant(30, 0.01);
  for (int t = 0; t < 30; ++t) {
    Phi(t, 0) = Phi(t, 1) = u(rng);
    Phi(t, 2) = u(rng);
    y[t] = 0.5 * Phi(t, 0) + 0.25 * Phi(t, 1) - Phi(t, 2);
  }
  const sets::PuiResult r = sets::pui(FeasibleParameterSet::from_data(Phi, y, delta));
  EXPECT_EQ(r.consistency.falsified, sets::Falsified::no);
  for (int j = 0; j < 2; ++j) {
    EXPECT_EQ(r.box[j].lower(), -sets::inf) << j;
    EXPECT_EQ(r.box[j].upper(), sets::inf) << j;
  }
  EXPECT_TRUE(sets::contains(r.box, Eigen::Vector3d(0.5, 0.25, -1)));
}
