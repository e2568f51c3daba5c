// The generic operations of set_operations.hpp, checked the same way for every ConvexSet type:
// sample points of the true set, then every point must lie under support(S, d) for random d, in
// outer_box(S), not be refused by contains(S, x), and its image A x must lie in linear_map(A, S).

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "sets/domains/conversions.hpp"
#include "sets/domains/ellipsoid.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/domains/set_operations.hpp"
#include "sets/domains/vpolytope.hpp"
#include "sets/domains/zonotope.hpp"
#include "support/random_matrices.hpp"

namespace {

using sets::BoolInterval;
using sets::test::Rng;

// Points are pulled towards an interior point by this fraction, so that the rounding of the
// sample itself cannot put it outside the set (the sets are of size ~1).
constexpr double kShrink = 1e-9;

// A random set of dimension n and k points of it.
template <class S>
struct Sampled {
  S set;
  Eigen::MatrixXd points;  // n x k
};

// Convex combinations of the columns of V, each pulled towards their mean.
Eigen::MatrixXd hull_samples(const Eigen::MatrixXd& V, int k, Rng& rng) {
  const Eigen::VectorXd mean = V.rowwise().mean();
  Eigen::MatrixXd X(V.rows(), k);
  for (int s = 0; s < k; ++s) {
    Eigen::VectorXd w = Eigen::VectorXd::NullaryExpr(V.cols(), [&] { return std::pow(rng.u(0, 1), 4); });
    if (s < V.cols()) w = Eigen::VectorXd::Unit(V.cols(), s);  // the points themselves first
    w /= w.sum();
    X.col(s) = mean + (1 - kShrink) * (V * w - mean);
  }
  return X;
}

Sampled<sets::Zonotope> sample(std::type_identity<sets::Zonotope>, int n, Rng& rng) {
  const int m = n + 2;
  sets::Zonotope Z(rng.mat(n, 1).col(0), rng.mat(n, m));
  Eigen::MatrixXd X(n, 20);
  for (int s = 0; s < X.cols(); ++s) {
    Eigen::VectorXd xi = s < 4 ? Eigen::VectorXd(rng.mat(m, 1).col(0).cwiseSign()) : Eigen::VectorXd(rng.mat(m, 1).col(0));
    X.col(s) = Z.center() + Z.generators() * ((1 - kShrink) * xi);
  }
  return {Z, X};
}

Sampled<sets::Ellipsoid> sample(std::type_identity<sets::Ellipsoid>, int n, Rng& rng) {
  const Eigen::MatrixXd L = rng.mat(n, n);
  const sets::Ellipsoid E(rng.mat(n, 1).col(0), L * L.transpose());
  Eigen::MatrixXd X(n, 20);
  for (int s = 0; s < X.cols(); ++s) {
    Eigen::VectorXd v = rng.mat(n, 1).col(0);
    v /= v.norm();  // on the boundary of the unit ball, then pulled in
    if (s >= 4) v *= rng.u(0, 1);
    X.col(s) = E.center() + L * ((1 - kShrink) * v);
  }
  return {E, X};
}

Sampled<sets::VPolytope> sample(std::type_identity<sets::VPolytope>, int n, Rng& rng) {
  const sets::VPolytope V(rng.mat(n, n + 3));
  return {V, hull_samples(V.points(), 20, rng)};
}

// The H-polytope of a random hull (to_hpolytope(VPolytope) contains the hull).
Sampled<sets::HPolytope> sample(std::type_identity<sets::HPolytope>, int n, Rng& rng) {
  const Eigen::MatrixXd V = rng.mat(n, n + 3);
  return {sets::to_hpolytope(sets::VPolytope(V)), hull_samples(V, 20, rng)};
}

template <class S>
class SetOperations : public ::testing::Test {};
using SetTypes = ::testing::Types<sets::Zonotope, sets::Ellipsoid, sets::VPolytope, sets::HPolytope>;
TYPED_TEST_SUITE(SetOperations, SetTypes);

}  // namespace

TYPED_TEST(SetOperations, EverySampledPointIsInsideEveryOuterApproximation) {
  using S = TypeParam;
  static_assert(sets::ConvexSet<S>);
  int yes = 0, checked = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    Rng rng(seed);
    const int n = 2 + static_cast<int>(seed % 2);  // 2-D and 3-D (the H-polytopes need CGAL's hull)
    const Sampled<S> smp = sample(std::type_identity<S>{}, n, rng);
    const S& set = smp.set;
    ASSERT_EQ(set.dimension(), n);
    Eigen::MatrixXd A = rng.mat(n, n);
    A.diagonal().array() += 3;  // well-conditioned: linear_map of an H-polytope needs an inverse
    const S image = sets::linear_map(A, set);
    const sets::IntervalVector box = sets::outer_box(set);
    std::vector<Eigen::VectorXd> dirs;
    for (int k = 0; k < 8; ++k) dirs.push_back(rng.mat(n, 1).col(0));
    std::vector<double> h, h_image;
    for (const auto& d : dirs) {
      h.push_back(sets::support(set, d));
      h_image.push_back(sets::support(image, d));
    }
    for (Eigen::Index s = 0; s < smp.points.cols(); ++s) {
      const Eigen::VectorXd x = smp.points.col(s);
      const Eigen::VectorXd y = A * x;
      const std::string where = sets::to_string(set) + ", point " + std::to_string(s);
      for (std::size_t k = 0; k < dirs.size(); ++k) {
        ASSERT_LE(dirs[k].dot(x), h[k]) << where;
        ASSERT_LE(dirs[k].dot(y), h_image[k]) << where << " (image)";
      }
      ASSERT_TRUE(sets::contains(box, x)) << where;
      ASSERT_NE(sets::contains(set, x), BoolInterval::no) << where;
      ASSERT_NE(sets::contains(image, y), BoolInterval::no) << where << " (image)";
      yes += sets::contains(set, x) == BoolInterval::yes;
      ++checked;
    }
  }
  // Points pulled inside are mostly decided, not left unknown.
  EXPECT_GT(yes, checked / 2);
}

TYPED_TEST(SetOperations, ToStringNamesTheTypeAndDimension) {
  Rng rng(99);
  const auto smp = sample(std::type_identity<TypeParam>{}, 2, rng);
  const std::string text = sets::to_string(smp.set);
  EXPECT_NE(text.find("(dim=2"), std::string::npos) << text;
}
