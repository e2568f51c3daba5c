// V-polytopes (src/domains/vpolytope.cpp): containment agrees with CGAL's exact 2-D hull, points on
// the boundary included.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/convex_hull_2.h>

#include <cmath>
#include <cstdint>
#include <iterator>
#include <vector>

#include "sets/domains/vpolytope.hpp"
#include "support/random_matrices.hpp"

namespace {

using sets::BoolInterval;
using sets::VPolytope;
using sets::test::Rng;
using K = CGAL::Exact_predicates_exact_constructions_kernel;

}  // namespace

RC_GTEST_PROP(Polytope, VContainmentAgreesWithCgal2D, ()) {
  Rng r(*rc::gen::arbitrary<std::uint64_t>());
  // Integer points, so edge midpoints are exact and land exactly on the boundary.
  Eigen::MatrixXd P(2, 8);
  for (int k = 0; k < 8; ++k) P.col(k) << std::round(10 * r.u()), std::round(10 * r.u());
  const VPolytope V(P);
  std::vector<K::Point_2> pts, hull;
  for (int k = 0; k < 8; ++k) pts.emplace_back(P(0, k), P(1, k));
  CGAL::convex_hull_2(pts.begin(), pts.end(), std::back_inserter(hull));
  for (int s = 0; s < 20; ++s) {
    Eigen::Vector2d x(std::round(10 * r.u()) / 2, std::round(10 * r.u()) / 2);
    if (s < 4) x = 0.5 * (P.col(s) + P.col(s + 1));
    const auto side = CGAL::bounded_side_2(hull.begin(), hull.end(), K::Point_2(x[0], x[1]));
    const bool inside = hull.size() >= 3 ? side != CGAL::ON_UNBOUNDED_SIDE
                                         : sets::contains(V, x) == BoolInterval::yes;
    RC_ASSERT(sets::contains(V, x) == (inside ? BoolInterval::yes : BoolInterval::no));
  }
}
