// Conversions between H- and V-polytopes through CGAL (src/domains/polytope_cgal.cpp): agreement
// with CGAL's exact arithmetic in 2-D/3-D (vertex sets, hulls, facets), certified boxes, and the
// degenerate cases (empty, unbounded, flat, near-parallel constraints, above 3-D).

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>

#include "sets/core/error.hpp"
#include "sets/domains/conversions.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/domains/vpolytope.hpp"
#include "sets/domains/zonotope.hpp"
#include "support/random_matrices.hpp"

namespace {

using sets::BoolInterval;
using sets::HPolytope;
using sets::VPolytope;
using sets::test::Rng;

HPolytope unit_box(int n) {
  return sets::to_hpolytope(sets::make_box(-Eigen::VectorXd::Ones(n), Eigen::VectorXd::Ones(n)));
}

// Every point of A is within tol of a point of B and vice versa. (Rounded facet normals can split
// a vertex where more than n facets meet into several points a rounding error apart.)
bool same_point_sets(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double tol) {
  auto covered = [tol](const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
    for (int k = 0; k < X.cols(); ++k) {
      bool found = false;
      for (int l = 0; l < Y.cols() && !found; ++l) found = (X.col(k) - Y.col(l)).cwiseAbs().maxCoeff() <= tol;
      if (!found) return false;
    }
    return true;
  };
  return covered(A, B) && covered(B, A);
}

}  // namespace

TEST(Polytope, EmptyUnboundedAndFlatPolytopes) {
  // Empty: x <= 0 and x >= 1.
  Eigen::MatrixXd A(2, 1);
  A << 1, -1;
  const HPolytope E(A, Eigen::Vector2d(0, -1));
  EXPECT_EQ(sets::is_empty(E), BoolInterval::yes);
  EXPECT_THROW(sets::outer_box(E), sets::EmptySetError);
  EXPECT_THROW(sets::to_vpolytope(E), sets::EmptySetError);
  // Unbounded: the half-plane y <= 1.
  Eigen::MatrixXd Hh(1, 2);
  Hh << 0, 1;
  const HPolytope U(Hh, Eigen::VectorXd::Constant(1, 1.0));
  EXPECT_EQ(sets::is_empty(U), BoolInterval::no);
  const auto box = sets::outer_box(U);
  EXPECT_EQ(box[0].lower(), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(box[0].upper(), std::numeric_limits<double>::infinity());
  EXPECT_GE(box[1].upper(), 1.0);
  EXPECT_THROW(sets::to_vpolytope(U), sets::UnsupportedError);
  // Flat: the segment x = 0, |y| <= 1 (a thin polytope; emptiness still decided exactly).
  Eigen::MatrixXd F(4, 2);
  F << 1, 0, -1, 0, 0, 1, 0, -1;
  const HPolytope S(F, Eigen::Vector4d(0, 0, 1, 1));
  EXPECT_EQ(sets::is_empty(S), BoolInterval::no);
  const auto sb = sets::outer_box(S);
  EXPECT_LE(sb[0].lower(), 0.0);
  EXPECT_GE(sb[0].upper(), 0.0);
  EXPECT_LE(sb[1].lower(), -1.0);
  EXPECT_GE(sb[1].upper(), 1.0);
  EXPECT_THROW(sets::to_vpolytope(S), sets::UnsupportedError);
  // A thin but empty slab: x <= 1e-300 and x >= 2e-300.
  const HPolytope T(A, Eigen::Vector2d(1e-300, -2e-300));
  EXPECT_EQ(sets::is_empty(T), BoolInterval::yes);
  // Above 3-D: a clear error, not a wrong answer.
  EXPECT_THROW(sets::to_vpolytope(unit_box(4)), sets::UnsupportedError);
  EXPECT_THROW(sets::to_hpolytope(VPolytope(Eigen::MatrixXd::Identity(4, 4))), sets::UnsupportedError);
}

RC_GTEST_PROP(Polytope, VertexEnumerationAgreesWithExactHull, ()) {
  // Random points -> CGAL exact hull -> H (certified) -> V (exact duality): same vertices.
  const int n = *rc::gen::inRange(2, 4);
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const VPolytope V(r.mat(n, *rc::gen::inRange(n + 1, 25)));
  const VPolytope hull = sets::convex_hull(V);
  const HPolytope H = sets::to_hpolytope(V);
  for (int k = 0; k < V.num_points(); ++k) RC_ASSERT(sets::contains(H, V.points().col(k)) != BoolInterval::no);
  const VPolytope back = sets::to_vpolytope(H);
  RC_ASSERT(same_point_sets(hull.points(), back.points(), 1e-9));
  // Box by LPs is certified and tight.
  const auto box = sets::outer_box(H);
  const auto vbox = sets::outer_box(V);
  for (int i = 0; i < n; ++i) {
    RC_ASSERT(box[i].lower() <= vbox[i].lower());
    RC_ASSERT(box[i].upper() >= vbox[i].upper());
    RC_ASSERT(vbox[i].lower() - box[i].lower() <= 1e-9);
  }
}

TEST(Polytope, NearParallelConstraints) {
  // x <= 1 and x + 1e-13 y <= 1 meet at an angle of 1e-13: with x >= -1 they pin y <= 2e13,
  // a vertex far away but well defined, which the exact duality finds.
  Eigen::MatrixXd A(4, 2);
  A << 1, 0, 1, 1e-13, -1, 0, 0, -1;
  const HPolytope P(A, Eigen::Vector4d(1, 1, 1, 1));
  const VPolytope V = sets::to_vpolytope(P);
  ASSERT_EQ(V.num_points(), 4);
  EXPECT_NEAR(V.points().row(1).maxCoeff(), 2e13, 1.0);
  // Vertices are the exact ones rounded to nearest: within rounding of every facet.
  for (int k = 0; k < V.num_points(); ++k) {
    const Eigen::VectorXd v = V.points().col(k);
    EXPECT_TRUE(((A * v - P.b()).array() <= 1e-15 * (1 + v.cwiseAbs().maxCoeff())).all()) << k;
  }
  // Dropping x >= -1 leaves an unbounded set: a clear error, not a wrong vertex list.
  const HPolytope U(Eigen::MatrixXd(A.topRows(2)), Eigen::Vector2d(1, 1));
  EXPECT_THROW(sets::to_vpolytope(U), sets::UnsupportedError);
  // A nearly parallel but redundant copy is removed; the box is certified.
  Eigen::MatrixXd B(5, 2);
  B << A, 1, -1e-13;
  Eigen::VectorXd bb(5);
  bb << 1, 1, 1, 1, 1 + 1e-9;
  const HPolytope R = sets::remove_redundant(HPolytope(B, bb));
  EXPECT_EQ(R.num_constraints(), 4);
  const auto box = sets::outer_box(P);
  EXPECT_GE(box[1].upper(), 2e13);
}

RC_GTEST_PROP(Polytope, ZonotopeFacetsAgreeWithExactHull3D, ()) {
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  const int m = *rc::gen::inRange(3, 7);
  // Dyadic entries (k/1024, |k| <= 1024) so that the 2^m vertex sums are exact doubles: with
  // arbitrary doubles the rounded sums can split a facet of the exact hull in two.
  auto dyadic = [&r] { return std::round(r.u() * 1024) / 1024; };
  const Eigen::MatrixXd G = Eigen::MatrixXd::NullaryExpr(3, m, dyadic);
  for (int a = 0; a < m; ++a)  // generic position: no three generators linearly dependent
    for (int b = a + 1; b < m; ++b)
      for (int c = b + 1; c < m; ++c) {
        Eigen::Matrix3d M;
        M << G.col(a), G.col(b), G.col(c);
        RC_PRE(std::abs(M.determinant()) > 1e-6);
      }
  const sets::Zonotope Z(Eigen::Vector3d(dyadic(), dyadic(), dyadic()), G);
  const HPolytope H = sets::to_hpolytope(Z);
  const VPolytope V = sets::to_vpolytope(Z);        // 2^m sums through CGAL's exact hull
  const HPolytope Hc = sets::to_hpolytope(V);       // facets of the exact hull
  RC_ASSERT(H.num_constraints() == Hc.num_constraints());  // generic position: m(m-1) facets
  RC_ASSERT(H.num_constraints() == m * (m - 1));
  for (int k = 0; k < V.num_points(); ++k) RC_ASSERT(sets::contains(H, V.points().col(k)) != BoolInterval::no);
}

TEST(Polytope, PolygonVerticesAreCounterClockwise) {
  Rng r(4);
  const VPolytope V(r.mat(2, 30));
  for (const Eigen::MatrixXd& P : {sets::polygon_vertices(V), sets::polygon_vertices(sets::to_hpolytope(V))}) {
    ASSERT_GE(P.cols(), 3);
    for (int k = 0; k < P.cols(); ++k) {
      const Eigen::Vector2d a = P.col(k), b = P.col((k + 1) % P.cols()), c = P.col((k + 2) % P.cols());
      EXPECT_GT((b - a).x() * (c - b).y() - (b - a).y() * (c - b).x(), 0);
    }
  }
}

TEST(Polytope, FlatVPolytopesGetEqualityPairs) {
  // Coplanar points in 3-D and collinear points in 2-D.
  Eigen::MatrixXd P(3, 5);
  P << 0, 1, 0, 1, 0.5, 0, 0, 1, 1, 0.5, 1, 1, 1, 1, 1;
  const HPolytope H = sets::to_hpolytope(VPolytope(P));
  EXPECT_NE(sets::contains(H, Eigen::Vector3d(0.5, 0.5, 1)), BoolInterval::no);
  EXPECT_EQ(sets::contains(H, Eigen::Vector3d(0.5, 0.5, 1.01)), BoolInterval::no);
  EXPECT_EQ(sets::contains(H, Eigen::Vector3d(1.5, 0.5, 1)), BoolInterval::no);
  EXPECT_EQ(sets::convex_hull(VPolytope(P)).num_points(), 4);
  Eigen::MatrixXd L(2, 3);
  L << 0, 1, 2, 0, 1, 2;
  const HPolytope HL = sets::to_hpolytope(VPolytope(L));
  EXPECT_NE(sets::contains(HL, Eigen::Vector2d(1.5, 1.5)), BoolInterval::no);
  EXPECT_EQ(sets::contains(HL, Eigen::Vector2d(1.5, 1.6)), BoolInterval::no);
  EXPECT_EQ(sets::contains(HL, Eigen::Vector2d(2.5, 2.5)), BoolInterval::no);
}
