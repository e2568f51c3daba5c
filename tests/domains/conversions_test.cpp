// The conversions of conversions.hpp agree with each other: a set reached by different routes
// (zonotope -> H, zonotope -> V, H -> V -> H, polygon vertices of each) has the same support
// function up to rounding, exact conversions of a box are exact, and outer approximations
// contain what they approximate. (Each conversion's own properties against CGAL are tested in
// zonotope_test, polytope_cgal_test and ellipsoid_test.)

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "sets/domains/conversions.hpp"
#include "support/random_matrices.hpp"

namespace {

using sets::BoolInterval;
using sets::test::Rng;

// max over the columns of V of d^T v (plain floating point).
double vertex_support(const Eigen::MatrixXd& V, const Eigen::VectorXd& d) { return (d.transpose() * V).maxCoeff(); }

}  // namespace

TEST(Conversions, BoxToPolytopesIsExact) {
  const sets::IntervalVector box = sets::make_box(Eigen::Vector3d(-1, 0.25, 2), Eigen::Vector3d(0.5, 0.75, 3));
  const auto V = sets::to_vpolytope(box);
  ASSERT_EQ(V.num_points(), 8);
  const auto H = sets::to_hpolytope(box);
  ASSERT_EQ(H.num_constraints(), 6);
  const auto vbox = sets::outer_box(V);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(vbox[i].lower(), box[i].lower());
    EXPECT_EQ(vbox[i].upper(), box[i].upper());
  }
  for (int k = 0; k < V.num_points(); ++k) {
    const Eigen::VectorXd corner = V.points().col(k);
    EXPECT_EQ(sets::contains(H, corner), BoolInterval::yes) << k;  // on the boundary, exactly
    Eigen::VectorXd out = corner;
    out[k % 3] = std::nextafter(out[k % 3], out[k % 3] > box[k % 3].lower() ? 10.0 : -10.0);
    EXPECT_EQ(sets::contains(H, out), BoolInterval::no) << k;  // one ulp outside
  }
}

TEST(Conversions, ZonotopeRoutesAgreeOnTheSupportFunction) {
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    Rng rng(seed);
    const int n = 2 + static_cast<int>(seed % 2);
    const sets::Zonotope Z(rng.mat(n, 1).col(0), rng.mat(n, n + 2));
    const auto H = sets::to_hpolytope(Z);
    const auto V = sets::to_vpolytope(Z);
    const auto HV = sets::to_hpolytope(sets::to_vpolytope(H));
    for (int k = 0; k < 10; ++k) {
      const Eigen::VectorXd d = rng.mat(n, 1).col(0);
      const double h = sets::support(Z, d);
      const double tol = 1e-9 * (1 + std::abs(h));
      EXPECT_NEAR(sets::support(H, d), h, tol) << "seed " << seed;
      EXPECT_NEAR(sets::support(V, d), h, tol) << "seed " << seed;
      EXPECT_NEAR(sets::support(HV, d), h, tol) << "seed " << seed;
      // The outer conversions contain Z: their rigorous support is never below Z's exact one.
      EXPECT_GE(sets::support(H, d), vertex_support(V.points(), d) - tol) << "seed " << seed;
    }
    for (int k = 0; k < V.num_points(); ++k)
      EXPECT_NE(sets::contains(H, Eigen::VectorXd(V.points().col(k))), BoolInterval::no) << "seed " << seed;
    if (n == 2) {  // the plotted polygons of Z, V and H coincide
      const Eigen::MatrixXd pz = sets::polygon_vertices(Z), pv = sets::polygon_vertices(V),
                            ph = sets::polygon_vertices(H);
      for (int k = 0; k < 10; ++k) {
        const Eigen::VectorXd d = rng.mat(2, 1).col(0);
        const double h = vertex_support(pz, d);
        EXPECT_NEAR(vertex_support(pv, d), h, 1e-9 * (1 + std::abs(h)));
        EXPECT_NEAR(vertex_support(ph, d), h, 1e-9 * (1 + std::abs(h)));
      }
    }
  }
}

TEST(Conversions, OuterPolygonOfAnEllipseContainsItAndIsTight) {
  Rng rng(5);
  const Eigen::MatrixXd L = rng.mat(2, 2);
  const sets::Ellipsoid E(rng.mat(2, 1).col(0), L * L.transpose() + 0.01 * Eigen::Matrix2d::Identity());
  for (int n : {3, 8, 64}) {
    const Eigen::MatrixXd poly = sets::outer_polygon(E, n);
    ASSERT_EQ(poly.cols(), n);
    for (int k = 0; k < 50; ++k) {
      const double t = 2 * std::numbers::pi * k / 50;
      const Eigen::Vector2d d(std::cos(t), std::sin(t));
      const double exact = d.dot(E.center()) + std::sqrt(d.dot(E.shape() * d));
      const double h = vertex_support(poly, d);
      EXPECT_GE(h, exact) << n << " vertices, direction " << k;
      // A circumscribed n-gon reaches at most 1/cos(pi/n) times E's extent from its centre.
      EXPECT_LE(h - d.dot(E.center()), (exact - d.dot(E.center())) / std::cos(std::numbers::pi / n) * (1 + 1e-6));
    }
  }
}
