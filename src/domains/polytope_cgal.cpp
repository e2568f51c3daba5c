// H <-> V conversions and convex hulls in 1-3 dimensions with CGAL's exact kernel.
// The only translation unit that includes CGAL's hull code (slow to compile).

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/domains/conversions.hpp"

namespace sets {

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = K::FT;
using P2 = K::Point_2;
using P3 = K::Point_3;
using V3 = K::Vector_3;
using Mesh = CGAL::Surface_mesh<P3>;

double dbl(const FT& x) { return CGAL::to_double(x); }

void check_dim(int n, const char* what) {
  if (n < 1 || n > 3)
    throw UnsupportedError(std::string(what) + ": exact conversion is implemented in 1-3 dimensions, not " +
                           std::to_string(n));
}

std::vector<P2> points2(const Eigen::MatrixXd& V) {
  std::vector<P2> p;
  for (Eigen::Index k = 0; k < V.cols(); ++k) p.emplace_back(V(0, k), V(1, k));
  return p;
}
std::vector<P3> points3(const Eigen::MatrixXd& V) {
  std::vector<P3> p;
  for (Eigen::Index k = 0; k < V.cols(); ++k) p.emplace_back(V(0, k), V(1, k), V(2, k));
  return p;
}

// Affine structure of a 3-D point set: indices of up to 4 affinely independent points.
std::vector<std::size_t> affine_basis(const std::vector<P3>& p) {
  std::vector<std::size_t> b{0};
  for (std::size_t k = 1; k < p.size() && b.size() < 2; ++k)
    if (p[k] != p[0]) b.push_back(k);
  if (b.size() < 2) return b;
  for (std::size_t k = 1; k < p.size() && b.size() < 3; ++k)
    if (!CGAL::collinear(p[b[0]], p[b[1]], p[k])) b.push_back(k);
  if (b.size() < 3) return b;
  for (std::size_t k = 1; k < p.size() && b.size() < 4; ++k)
    if (!CGAL::coplanar(p[b[0]], p[b[1]], p[b[2]], p[k])) b.push_back(k);
  return b;
}

// Axis to drop when projecting a plane with normal N to 2-D (largest |N_k|, so it is a bijection).
int drop_axis(const V3& N) {
  const double a[3] = {std::abs(dbl(N.x())), std::abs(dbl(N.y())), std::abs(dbl(N.z()))};
  int k = 0;
  if (a[1] > a[k]) k = 1;
  if (a[2] > a[k]) k = 2;
  // Doubles may tie or vanish by underflow; make sure the exact component is nonzero.
  const FT c[3] = {N.x(), N.y(), N.z()};
  if (c[k] == 0) k = c[0] != 0 ? 0 : (c[1] != 0 ? 1 : 2);
  return k;
}
P2 project_drop(const P3& p, int k) {
  return k == 0 ? P2(p.y(), p.z()) : (k == 1 ? P2(p.x(), p.z()) : P2(p.x(), p.y()));
}

// Indices (into p) of the 2-D hull of coplanar 3-D points, counter-clockwise in the projection.
std::vector<std::size_t> planar_hull(const std::vector<P3>& p, int k) {
  std::vector<P2> q;
  for (const auto& x : p) q.push_back(project_drop(x, k));
  std::vector<std::size_t> idx(q.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::vector<std::size_t> out;
  // Hull on indices via a property map would need more boilerplate; use points and look back.
  std::vector<P2> h;
  CGAL::convex_hull_2(q.begin(), q.end(), std::back_inserter(h));
  for (const auto& v : h)
    for (std::size_t i = 0; i < q.size(); ++i)
      if (q[i] == v) {
        out.push_back(i);
        break;
      }
  return out;
}

Eigen::VectorXd to_eigen(const V3& v) {
  Eigen::VectorXd r(3);
  r << dbl(v.x()), dbl(v.y()), dbl(v.z());
  return r;
}

}  // namespace

VPolytope convex_hull(const VPolytope& V) {
  const int n = V.dimension();
  check_dim(n, "convex_hull");
  const Eigen::MatrixXd& X = V.points();
  if (n == 1) {
    Eigen::Index lo = 0, hi = 0;
    X.row(0).minCoeff(&lo);
    X.row(0).maxCoeff(&hi);
    if (X(0, lo) == X(0, hi)) return VPolytope(X.col(lo));
    Eigen::MatrixXd out(1, 2);
    out << X(0, lo), X(0, hi);
    return VPolytope(out);
  }
  if (n == 2) {
    const auto p = points2(X);
    std::vector<P2> h;
    CGAL::convex_hull_2(p.begin(), p.end(), std::back_inserter(h));
    Eigen::MatrixXd out(2, h.size());
    for (std::size_t k = 0; k < h.size(); ++k) out.col(k) << dbl(h[k].x()), dbl(h[k].y());
    return VPolytope(out);
  }
  const auto p = points3(X);
  const auto b = affine_basis(p);
  std::vector<std::size_t> keep;
  if (b.size() == 1) {
    keep = {0};
  } else if (b.size() == 2) {
    const V3 u = p[b[1]] - p[b[0]];
    std::size_t lo = 0, hi = 0;
    for (std::size_t k = 1; k < p.size(); ++k) {
      if ((p[k] - p[lo]) * u < 0) lo = k;
      if ((p[k] - p[hi]) * u > 0) hi = k;
    }
    keep = {lo, hi};
  } else if (b.size() == 3) {
    keep = planar_hull(p, drop_axis(CGAL::cross_product(p[b[1]] - p[b[0]], p[b[2]] - p[b[0]])));
  } else {
    Mesh sm;
    CGAL::convex_hull_3(p.begin(), p.end(), sm);
    Eigen::MatrixXd out(3, sm.number_of_vertices());
    int k = 0;
    for (auto v : sm.vertices()) {
      const P3& q = sm.point(v);
      out.col(k++) << dbl(q.x()), dbl(q.y()), dbl(q.z());
    }
    return VPolytope(out);
  }
  Eigen::MatrixXd out(3, keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) out.col(k) = X.col(keep[k]);
  return VPolytope(out);
}

HPolytope to_hpolytope(const VPolytope& V) {
  const int n = V.dimension();
  check_dim(n, "to_hpolytope(VPolytope)");
  std::vector<Eigen::VectorXd> normals;
  auto axis_pairs = [&] {
    for (int i = 0; i < n; ++i) {
      normals.push_back(Eigen::VectorXd::Unit(n, i));
      normals.push_back(-Eigen::VectorXd::Unit(n, i));
    }
  };
  if (n == 1) {
    axis_pairs();
  } else if (n == 2) {
    const auto p = points2(V.points());
    std::vector<P2> h;
    CGAL::convex_hull_2(p.begin(), p.end(), std::back_inserter(h));
    if (h.size() == 1) {
      axis_pairs();
    } else if (h.size() == 2) {
      const auto u = h[1] - h[0];
      for (double s : {1.0, -1.0}) {
        normals.push_back(s * Eigen::Vector2d(dbl(-u.y()), dbl(u.x())));
        normals.push_back(s * Eigen::Vector2d(dbl(u.x()), dbl(u.y())));
      }
    } else {
      for (std::size_t k = 0; k < h.size(); ++k) {
        const auto e = h[(k + 1) % h.size()] - h[k];  // counter-clockwise: outward normal (e_y, -e_x)
        normals.push_back(Eigen::Vector2d(dbl(e.y()), dbl(-e.x())));
      }
    }
  } else {
    const auto p = points3(V.points());
    const auto b = affine_basis(p);
    if (b.size() == 1) {
      axis_pairs();
    } else if (b.size() == 2) {
      const V3 u = p[b[1]] - p[b[0]];
      const V3 e[3] = {V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1)};
      V3 w1 = CGAL::cross_product(u, e[0]);
      if (w1 == CGAL::NULL_VECTOR) w1 = CGAL::cross_product(u, e[1]);
      const V3 w2 = CGAL::cross_product(u, w1);
      for (const V3& w : {u, w1, w2}) {
        normals.push_back(to_eigen(w));
        normals.push_back(-to_eigen(w));
      }
    } else if (b.size() == 3) {
      const V3 N = CGAL::cross_product(p[b[1]] - p[b[0]], p[b[2]] - p[b[0]]);
      normals.push_back(to_eigen(N));
      normals.push_back(-to_eigen(N));
      const auto h = planar_hull(p, drop_axis(N));
      for (std::size_t k = 0; k < h.size(); ++k) {
        const P3& a = p[h[k]];
        const P3& c = p[h[(k + 1) % h.size()]];
        V3 w = CGAL::cross_product(c - a, N);
        // Outward: the other hull vertices are on the non-positive side.
        for (std::size_t l = 0; l < h.size(); ++l)
          if ((p[h[l]] - a) * w > 0) {
            w = -w;
            break;
          }
        normals.push_back(to_eigen(w));
      }
    } else {
      Mesh sm;
      CGAL::convex_hull_3(p.begin(), p.end(), sm);
      for (auto f : sm.faces()) {
        std::vector<P3> q;
        for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) q.push_back(sm.point(v));
        // convex_hull_3 orients faces counter-clockwise seen from outside: outward normal.
        normals.push_back(to_eigen(CGAL::cross_product(q[1] - q[0], q[2] - q[0])));
      }
    }
  }
  // Normalise, drop near-duplicates (coplanar triangles of one facet), certify offsets.
  std::vector<Eigen::VectorXd> unique;
  for (auto w : normals) {
    const double s = w.norm();
    if (!(s > 0) || !std::isfinite(s)) continue;
    w /= s;
    bool dup = false;
    for (const auto& u : unique) dup = dup || (u - w).cwiseAbs().maxCoeff() <= 1e-14;
    if (!dup) unique.push_back(w);
  }
  Eigen::MatrixXd A(unique.size(), n);
  Eigen::VectorXd bb(unique.size());
  for (std::size_t k = 0; k < unique.size(); ++k) {
    A.row(k) = unique[k].transpose();
    bb[k] = support(V, unique[k]);
  }
  return HPolytope(A, bb);
}

VPolytope to_vpolytope(const HPolytope& P) {
  const int n = P.dimension();
  check_dim(n, "to_vpolytope(HPolytope)");
  if (is_empty(P) == BoolInterval::yes) throw EmptySetError("to_vpolytope: the polytope is empty");
  const ChebyshevBall ball = chebyshev_ball(P);
  if (ball.radius == inf) throw UnsupportedError("to_vpolytope: the polytope is unbounded (no vertex representation)");
  const double scale = 1 + ball.center.cwiseAbs().maxCoeff();
  if (!(ball.radius > 1e-12 * scale))
    throw UnsupportedError("to_vpolytope: the polytope is not full-dimensional (Chebyshev radius " +
                           std::to_string(ball.radius) + "); only full-dimensional polytopes are converted");
  const Eigen::VectorXd& c = ball.center;
  // Polar duality around the interior point c: with b'_i = b_i - a_i^T c > 0, the vertices of P
  // are c + v for the facets {d : v^T d = 1} of the hull of the points a_i / b'_i.
  std::vector<std::vector<FT>> dual;
  for (int i = 0; i < P.num_constraints(); ++i) {
    if (P.b()[i] == inf || P.A().row(i).isZero(0)) continue;
    FT bi(P.b()[i]);
    for (int j = 0; j < n; ++j) bi -= FT(P.A()(i, j)) * FT(c[j]);
    if (!(bi > 0))
      throw NumericalError("to_vpolytope: the Chebyshev centre is not strictly inside row " + std::to_string(i));
    std::vector<FT> d(n);
    for (int j = 0; j < n; ++j) d[j] = FT(P.A()(i, j)) / bi;
    dual.push_back(std::move(d));
  }
  const char* unbounded = "to_vpolytope: the polytope is unbounded (no vertex representation)";
  std::vector<std::vector<FT>> verts;
  if (n == 1) {
    bool has_hi = false, has_lo = false;
    FT hi = 0, lo = 0;  // max positive and min negative dual coordinate
    for (const auto& d : dual) {
      if (d[0] > 0 && (!has_hi || d[0] > hi)) hi = d[0], has_hi = true;
      if (d[0] < 0 && (!has_lo || d[0] < lo)) lo = d[0], has_lo = true;
    }
    if (!has_hi || !has_lo) throw UnsupportedError(unbounded);
    verts = {{FT(1) / lo}, {FT(1) / hi}};
  } else if (n == 2) {
    std::vector<P2> q;
    for (const auto& d : dual) q.emplace_back(d[0], d[1]);
    std::vector<P2> h;
    CGAL::convex_hull_2(q.begin(), q.end(), std::back_inserter(h));
    if (h.size() < 3) throw UnsupportedError(unbounded);
    for (std::size_t k = 0; k < h.size(); ++k) {
      const P2& a = h[k];
      const P2& b = h[(k + 1) % h.size()];
      if (CGAL::orientation(a, b, P2(0, 0)) != CGAL::LEFT_TURN) throw UnsupportedError(unbounded);
      const FT det = a.x() * b.y() - a.y() * b.x();
      verts.push_back({(b.y() - a.y()) / det, (a.x() - b.x()) / det});
    }
  } else {
    std::vector<P3> q;
    for (const auto& d : dual) q.emplace_back(d[0], d[1], d[2]);
    const auto b = affine_basis(q);
    if (b.size() < 4) throw UnsupportedError(unbounded);
    const P3 inside = CGAL::centroid(q[b[0]], q[b[1]], q[b[2]], q[b[3]]);
    Mesh sm;
    CGAL::convex_hull_3(q.begin(), q.end(), sm);
    std::set<P3> seen;
    for (auto f : sm.faces()) {
      std::vector<P3> t;
      for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t.push_back(sm.point(v));
      const K::Plane_3 pl(t[0], t[1], t[2]);
      const auto side = pl.oriented_side(P3(0, 0, 0));
      if (side == CGAL::ON_ORIENTED_BOUNDARY || side != pl.oriented_side(inside))
        throw UnsupportedError(unbounded);
      const P3 v(-pl.a() / pl.d(), -pl.b() / pl.d(), -pl.c() / pl.d());
      if (seen.insert(v).second) verts.push_back({v.x(), v.y(), v.z()});
    }
  }
  Eigen::MatrixXd out(n, verts.size());
  for (std::size_t k = 0; k < verts.size(); ++k)
    for (int j = 0; j < n; ++j) out(j, k) = dbl(FT(c[j]) + verts[k][j]);
  if (n == 2) return VPolytope(out);  // already counter-clockwise
  return VPolytope(out);
}

}  // namespace sets
