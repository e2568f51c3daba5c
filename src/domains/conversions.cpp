#include "sets/domains/conversions.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "sets/core/error.hpp"
#include "sets/numeric/interval.hpp"

namespace sets {

// ------------------------------------------------------------------------------- boxes

HPolytope to_hpolytope(const IntervalVector& box) {
  const auto n = box.size();
  Eigen::MatrixXd A(2 * n, n);
  Eigen::VectorXd b(2 * n);
  A.setZero();
  for (Eigen::Index i = 0; i < n; ++i) {
    A(2 * i, i) = 1;
    b[2 * i] = box[i].upper();
    A(2 * i + 1, i) = -1;
    b[2 * i + 1] = -box[i].lower();
  }
  return HPolytope(A, b);
}

VPolytope to_vpolytope(const IntervalVector& box) {
  const auto n = box.size();
  if (n > 20) throw UnsupportedError("to_vpolytope(box): 2^" + std::to_string(n) + " corners is too many");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isfinite(box[i].lower()) || !std::isfinite(box[i].upper()))
      throw UnsupportedError("to_vpolytope(box): coordinate " + std::to_string(i) + " is unbounded");
  Eigen::MatrixXd V(n, 1L << n);
  for (long k = 0; k < (1L << n); ++k)
    for (Eigen::Index i = 0; i < n; ++i) V(i, k) = (k >> i) & 1 ? box[i].upper() : box[i].lower();
  return VPolytope(V);
}

// ------------------------------------------------------------------------------- zonotopes

namespace {

long binomial(long n, long k) {
  if (k < 0 || k > n) return 0;
  long r = 1;
  for (long i = 1; i <= k; ++i) {
    r = r * (n - k + i) / i;
    if (r > (1L << 40)) return r;
  }
  return r;
}

// Unit vector orthogonal to the r-1 columns of H (r x (r-1)), or empty if they are dependent.
Eigen::VectorXd normal_of(const Eigen::MatrixXd& H) {
  const auto r = H.rows();
  Eigen::VectorXd nrm(r);
  if (r == 2) {
    nrm << -H(1, 0), H(0, 0);  // exact
  } else if (r == 3) {
    nrm = Eigen::Vector3d(H.col(0)).cross(Eigen::Vector3d(H.col(1)));
  } else {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(H.transpose(), Eigen::ComputeFullV);
    const auto& s = svd.singularValues();
    if (s.size() < r - 1 || s[s.size() - 1] <= 1e-12 * s[0]) return {};
    nrm = svd.matrixV().col(r - 1);
  }
  double scale = 1;
  for (Eigen::Index j = 0; j < H.cols(); ++j) scale *= std::max(H.col(j).norm(), 1e-300);
  if (nrm.norm() <= 1e-12 * scale) return {};
  return nrm / nrm.norm();
}

}  // namespace

HPolytope to_hpolytope(const Zonotope& Zin, long max_facets) {
  const Zonotope Z = compact(Zin);
  const int n = Z.dimension(), m = Z.num_generators();
  const Eigen::MatrixXd& G = Z.generators();
  std::vector<Eigen::VectorXd> normals;
  int r = 0;
  Eigen::MatrixXd U;  // basis of span(G) (identity when full-dimensional)
  if (m > 0) {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeFullU);
    const auto& s = svd.singularValues();
    for (Eigen::Index i = 0; i < s.size(); ++i) r += s[i] > 1e-12 * s[0] * std::max(n, m);
    if (r == n) {
      U = Eigen::MatrixXd::Identity(n, n);
    } else {
      U = svd.matrixU().leftCols(r);
      for (int i = r; i < n; ++i) normals.push_back(svd.matrixU().col(i));
    }
  } else {
    for (int i = 0; i < n; ++i) normals.push_back(Eigen::VectorXd::Unit(n, i));
  }
  if (r == 1) {
    normals.push_back(U.col(0));
  } else if (r >= 2) {
    if (binomial(m, r - 1) > max_facets)
      throw UnsupportedError("to_hpolytope: " + std::to_string(m) + " generators in dimension " +
                             std::to_string(r) + " give more than " + std::to_string(max_facets) +
                             " facet candidates; reduce the order first");
    const Eigen::MatrixXd H = r == n ? G : Eigen::MatrixXd(U.transpose() * G);
    std::vector<int> comb(r - 1);
    std::iota(comb.begin(), comb.end(), 0);
    Eigen::MatrixXd S(r, r - 1);
    while (true) {
      for (int k = 0; k < r - 1; ++k) S.col(k) = H.col(comb[k]);
      const Eigen::VectorXd nr = normal_of(S);
      if (nr.size()) normals.push_back(r == n ? nr : Eigen::VectorXd(U * nr));
      int k = r - 2;
      while (k >= 0 && comb[k] == m - (r - 1) + k) --k;
      if (k < 0) break;
      ++comb[k];
      for (int l = k + 1; l < r - 1; ++l) comb[l] = comb[l - 1] + 1;
    }
  }
  // Orient each normal canonically and drop duplicates (parallel generators give the same facet).
  for (auto& d : normals) {
    Eigen::Index i = 0;
    d.cwiseAbs().maxCoeff(&i);
    if (d[i] < 0) d = -d;
  }
  std::sort(normals.begin(), normals.end(), [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return std::lexicographical_compare(a.data(), a.data() + a.size(), b.data(), b.data() + b.size());
  });
  std::vector<Eigen::VectorXd> unique;
  for (const auto& d : normals) {
    bool dup = false;
    for (auto it = unique.rbegin(); it != unique.rend() && it - unique.rbegin() < 8; ++it)
      if ((*it - d).cwiseAbs().maxCoeff() <= 1e-13) dup = true;
    if (!dup) unique.push_back(d);
  }
  Eigen::MatrixXd A(2 * unique.size(), n);
  Eigen::VectorXd b(2 * unique.size());
  for (std::size_t k = 0; k < unique.size(); ++k) {
    A.row(2 * k) = unique[k].transpose();
    b[2 * k] = support(Z, unique[k]);
    A.row(2 * k + 1) = -unique[k].transpose();
    b[2 * k + 1] = support(Z, -unique[k]);
  }
  return HPolytope(A, b);
}

VPolytope to_vpolytope(const Zonotope& Z) {
  if (Z.dimension() == 2) return VPolytope(polygon_vertices(Z));
  if (Z.dimension() == 1) {
    const auto b = outer_box(Z);
    Eigen::MatrixXd V(1, 2);
    V << b[0].lower(), b[0].upper();
    return VPolytope(V);
  }
  if (Z.dimension() != 3) throw UnsupportedError("to_vpolytope(Zonotope): only 1-3 dimensions");
  // Small generator sets: all 2^m sums, then the exact hull; otherwise through the facets.
  const Zonotope C = compact(Z);
  const int m = C.num_generators();
  if (m <= 12) {
    Eigen::MatrixXd P(3, 1 << m);
    for (int mask = 0; mask < (1 << m); ++mask) {
      Eigen::VectorXd xi(m);
      for (int j = 0; j < m; ++j) xi[j] = (mask >> j) & 1 ? 1.0 : -1.0;
      P.col(mask) = C.center() + C.generators() * xi;
    }
    return convex_hull(VPolytope(P));
  }
  return to_vpolytope(to_hpolytope(Z));
}

// ------------------------------------------------------------------------------- 2-D polygons

Eigen::MatrixXd polygon_vertices(const Zonotope& Zin) {
  if (Zin.dimension() != 2) throw InputError("polygon_vertices: the zonotope is not 2-D");
  const Zonotope Z = compact(Zin);
  const int m = Z.num_generators();
  if (m == 0) return Eigen::MatrixXd(Z.center());
  std::vector<std::pair<double, double>> g(m);
  for (int j = 0; j < m; ++j) {
    double gx = Z.generators()(0, j), gy = Z.generators()(1, j);
    if (gy < 0 || (gy == 0 && gx < 0)) gx = -gx, gy = -gy;  // upper half-plane
    g[j] = {gx, gy};
  }
  std::sort(g.begin(), g.end(), [](const auto& a, const auto& b) {
    return std::atan2(a.second, a.first) < std::atan2(b.second, b.first);
  });
  // Lowest vertex: c - sum g; walk counter-clockwise by +2 g_j, then back by -2 g_j.
  double px = Z.center()[0], py = Z.center()[1];
  for (const auto& [gx, gy] : g) px -= gx, py -= gy;
  Eigen::MatrixXd V(2, 2 * m);
  for (int j = 0; j < 2 * m; ++j) {
    V(0, j) = px;
    V(1, j) = py;
    const double sgn = j < m ? 2.0 : -2.0;
    px += sgn * g[j % m].first;
    py += sgn * g[j % m].second;
  }
  return V;
}

Eigen::MatrixXd polygon_vertices(const VPolytope& V) {
  if (V.dimension() != 2) throw InputError("polygon_vertices: the polytope is not 2-D");
  return convex_hull(V).points();
}

Eigen::MatrixXd polygon_vertices(const HPolytope& P) {
  if (P.dimension() != 2) throw InputError("polygon_vertices: the polytope is not 2-D");
  return polygon_vertices(to_vpolytope(P));
}

namespace {

// The edge p -> q of V as an interval vector, scaled by a power of 2 (exact) to entries of size
// ~1, so that products of edges and the shape neither underflow nor overflow on tiny or huge
// ellipsoids. Empty (size 0) for an edge of length 0.
IntervalVector scaled_edge(const Eigen::MatrixXd& V, Eigen::Index k) {
  const Eigen::Index k1 = (k + 1) % V.cols();
  IntervalVector e(2);
  for (int i = 0; i < 2; ++i) e[i] = Interval(V(i, k1)) - V(i, k);
  const double m = std::max(norm(e[0]), norm(e[1]));
  if (!(m > 0) || !std::isfinite(m)) return IntervalVector();
  int exponent = 0;
  std::frexp(m, &exponent);
  for (int i = 0; i < 2; ++i) e[i] = Interval(std::ldexp(e[i].lower(), -exponent), std::ldexp(e[i].upper(), -exponent));
  return e;
}

// True when the polygon V (2 x n) is proven, in interval arithmetic on its exact vertices, to be
// convex, counter-clockwise and to contain E: every turn is strictly to the left, and for every
// edge p -> q with outward normal n = (q - p) rotated clockwise, E's support function
// n^T c + sqrt(n^T P n) is at most n^T p. (With strict left turns, the intersection of the edges'
// half-planes lies in the polygon.)
bool polygon_contains(const Eigen::MatrixXd& V, const Ellipsoid& E) {
  if (!V.allFinite()) return false;
  const auto n = V.cols();
  const IntervalMatrix P = to_interval(E.shape());
  const Interval cx(E.center()[0]), cy(E.center()[1]);
  for (Eigen::Index k = 0; k < n; ++k) {
    const IntervalVector e = scaled_edge(V, k), next = scaled_edge(V, (k + 1) % n);
    if (e.size() == 0 || next.size() == 0) return false;
    const Interval turn = e[0] * next[1] - e[1] * next[0];
    if (!(turn.lower() > 0)) return false;
    const Interval nx = e[1], ny = -e[0];  // outward for a counter-clockwise polygon
    const Interval reach = nx * (Interval(V(0, k)) - cx) + ny * (Interval(V(1, k)) - cy);
    const Interval q = nx * (P(0, 0) * nx + P(0, 1) * ny) + ny * (P(1, 0) * nx + P(1, 1) * ny);
    if (!(sqrt(Interval(std::max(q.upper(), 0.0))).upper() <= reach.lower())) return false;
  }
  return true;
}

}  // namespace

Eigen::MatrixXd outer_polygon(const Ellipsoid& E, int n) {
  if (E.dimension() != 2) throw InputError("outer_polygon: the ellipsoid is not 2-D");
  if (n < 3) throw InputError("outer_polygon: need at least 3 vertices");
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(E.shape());
  const Eigen::Vector2d l = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  Eigen::Matrix2d Q = es.eigenvectors();
  if (Q.determinant() < 0) Q.col(1) *= -1;  // keep the vertices counter-clockwise
  // A regular n-gon with inradius 1 (circumradius 1/cos(pi/n)) contains the unit disc; its image
  // under Q diag(l) contains E, up to rounding: of the eigen-decomposition (an absolute error of
  // about eps l_max^2 in the small eigenvalue, so the minor axis can be off by sqrt(eps) l_max),
  // of the vertices (half an ulp of the centre) and of the trigonometry. So the axes grow by a
  // relative delta, delta l_max and a few ulps of the centre, and the result is accepted only
  // when polygon_contains proves it; else the margins grow 32-fold and it is tried again.
  const double R = 1.0 / std::cos(std::numbers::pi / n);
  const double lmax = l.maxCoeff();
  const double ulps = 8 * std::numeric_limits<double>::epsilon() * E.center().cwiseAbs().maxCoeff() +
                      std::numeric_limits<double>::min();
  double delta = 0x1p-40, absolute = ulps;
  for (int attempt = 0; attempt < 12; ++attempt, delta *= 32, absolute *= 32) {
    const Eigen::Vector2d axes = l * (1 + delta) + Eigen::Vector2d::Constant(delta * lmax + absolute);
    const Eigen::Matrix2d L = Q * axes.asDiagonal();
    Eigen::MatrixXd V(2, n);
    for (int k = 0; k < n; ++k) {
      const double t = 2.0 * std::numbers::pi * (k + 0.5) / n;
      V.col(k) = E.center() + L * Eigen::Vector2d(R * std::cos(t), R * std::sin(t));
    }
    if (polygon_contains(V, E)) return V;
  }
  throw NumericalError("outer_polygon: no polygon could be proven to contain the ellipsoid (overflow?)");
}

}  // namespace sets
