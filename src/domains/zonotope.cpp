#include "sets/domains/zonotope.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"
#include "domains/interval_enclosure.hpp"
#include "numeric/verified_linear_algebra.hpp"

namespace sets {

// ------------------------------------------------------------------------------- construction

Zonotope::Zonotope(Eigen::VectorXd center, Eigen::MatrixXd generators)
    : c_(std::move(center)), G_(std::move(generators)) {
  if (G_.rows() != c_.size()) {
    if (G_.size() == 0) {
      G_.resize(c_.size(), 0);
    } else {
      throw InputError("Zonotope: centre has " + std::to_string(c_.size()) +
                       " entries but the generator matrix has " + std::to_string(G_.rows()) + " rows");
    }
  }
  if (!c_.allFinite() || !G_.allFinite())
    throw InputError("Zonotope: centre or generators contain a NaN or infinite entry");
}

namespace detail {

Zonotope outer_zonotope(const IntervalVector& c, const IntervalMatrix& G) {
  // The exact set lies within mid(c) + mid(G) xi + (errors bounded by rad(c) + sum_j rad(G_ij)
  // per coordinate), which the extra axis-aligned generators cover.
  const auto n = c.size();
  const Eigen::VectorXd cm = midpoint(c);
  const Eigen::MatrixXd Gm = midpoint(G);
  Eigen::VectorXd e(n);
  int extra = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    Interval s(radius(c[i]));
    for (Eigen::Index j = 0; j < G.cols(); ++j) s += Interval(radius(G(i, j)));
    e[i] = s.upper();
    extra += e[i] > 0;
  }
  Eigen::MatrixXd out(n, Gm.cols() + extra);
  out.leftCols(Gm.cols()) = Gm;
  int k = static_cast<int>(Gm.cols());
  for (Eigen::Index i = 0; i < n; ++i)
    if (e[i] > 0) {
      out.col(k).setZero();
      out(i, k++) = e[i];
    }
  return Zonotope(cm, out);
}

}  // namespace detail

Zonotope Zonotope::from_box(const IntervalVector& box) {
  const auto n = box.size();
  IntervalVector c(n);
  IntervalMatrix G = IntervalMatrix::Constant(n, n, Interval(0.0));
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(box[i].lower()) || !std::isfinite(box[i].upper()))
      throw InputError("Zonotope::from_box: coordinate " + std::to_string(i) + " is unbounded");
    const double m = midpoint(box[i]);
    c[i] = Interval(m);
    G(i, i) = Interval(radius(box[i]));  // [m - r, m + r] contains the box's coordinate
  }
  Zonotope Z = detail::outer_zonotope(c, G);
  return compact(Z);
}

// ------------------------------------------------------------------------------- operations

namespace {

// Rigorous bound on |fl(A B) - A B| for a floating-point product in any summation order
// (Higham, Accuracy and Stability, 3.5): gamma_k |A| |B| with gamma_k = k u / (1 - k u), plus an
// absolute term for underflow. u = 2^-52 also covers directed rounding. |A||B| is itself
// computed in floating point, so it is divided by (1 - gamma_k) once more.
Eigen::MatrixXd product_error(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const double k = static_cast<double>(A.cols());
  const Interval ku = Interval(k) * Interval(std::ldexp(1.0, -52));
  if (!(ku.upper() < 0.5)) throw NumericalError("linear_map: inner dimension too large for the error bound");
  const Interval gamma = ku / (Interval(1.0) - ku);
  const double factor = (gamma / ((Interval(1.0) - gamma) * (Interval(1.0) - gamma))).upper();
  const double tiny = (Interval(k + 1) * Interval(std::numeric_limits<double>::denorm_min())).upper();
  Eigen::MatrixXd E = A.cwiseAbs() * B.cwiseAbs();
  for (Eigen::Index j = 0; j < E.cols(); ++j)
    for (Eigen::Index i = 0; i < E.rows(); ++i) E(i, j) = (Interval(E(i, j)) * Interval(factor) + Interval(tiny)).upper();
  return E;
}

}  // namespace

Zonotope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const Zonotope& Z) {
  if (A.cols() != Z.dimension())
    throw InputError("linear_map: matrix has " + std::to_string(A.cols()) +
                     " columns but the zonotope has dimension " + std::to_string(Z.dimension()));
  if (!A.allFinite()) throw InputError("linear_map: matrix has a NaN or infinite entry");
  // Fast rigorous product: A G in floating point plus a per-row error bound, which joins the
  // centre's rounding error as one axis-aligned generator per row.
  const Eigen::MatrixXd AG = A * Z.generators();
  const Eigen::MatrixXd err = product_error(A, Z.generators());
  const IntervalVector c = multiply(Eigen::MatrixXd(A), detail::iv(Z.center()));
  const auto n = A.rows();
  IntervalMatrix box = IntervalMatrix::Constant(n, 1, Interval(0.0));
  for (Eigen::Index i = 0; i < n; ++i) {
    Interval s(0.0);
    for (Eigen::Index j = 0; j < err.cols(); ++j) s += Interval(err(i, j));
    box(i, 0) = Interval(-s.upper(), s.upper());
  }
  const Zonotope E = detail::outer_zonotope(c, box);  // centre rounding + product error, as a box
  Eigen::MatrixXd G(n, AG.cols() + E.num_generators());
  G << AG, E.generators();
  return compact(Zonotope(E.center(), G));
}

Zonotope translate(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& b) {
  if (b.size() != Z.dimension()) throw InputError("translate: dimensions differ");
  return detail::outer_zonotope(detail::iv(Z.center()) + detail::iv(b), detail::im(Z.generators()));
}

Zonotope minkowski_sum(const Zonotope& Z1, const Zonotope& Z2) {
  if (Z1.dimension() != Z2.dimension())
    throw InputError("minkowski_sum: dimensions " + std::to_string(Z1.dimension()) + " and " +
                     std::to_string(Z2.dimension()) + " differ");
  // Generators are copied exactly; only the centre sum rounds (covered by a box generator).
  const Zonotope C = detail::outer_zonotope(detail::iv(Z1.center()) + detail::iv(Z2.center()),
                                            IntervalMatrix(Z1.dimension(), 0));
  Eigen::MatrixXd G(Z1.dimension(), Z1.num_generators() + Z2.num_generators() + C.num_generators());
  G << Z1.generators(), Z2.generators(), C.generators();
  return Zonotope(C.center(), G);
}

IntervalVector outer_box(const Zonotope& Z) {
  const int n = Z.dimension();
  IntervalVector b(n);
  for (int i = 0; i < n; ++i) {
    Interval s(0.0);
    for (int j = 0; j < Z.num_generators(); ++j) s += Interval(std::abs(Z.generators()(i, j)));
    b[i] = Interval(Z.center()[i]) + Interval(-s.upper(), s.upper());
  }
  return b;
}

double support(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& d) {
  if (d.size() != Z.dimension()) throw InputError("support: direction has the wrong dimension");
  const IntervalVector di = detail::iv(d);
  Interval s = detail::dot(di, detail::iv(Z.center()));
  for (int j = 0; j < Z.num_generators(); ++j) {
    const Interval p = detail::dot(di, detail::iv(Z.generators().col(j)));
    s += Interval(std::max(std::abs(p.lower()), std::abs(p.upper())));
  }
  return s.upper();
}

namespace {

// d separates x from Z when d^T x > support(Z, d), proven in interval arithmetic.
bool separates(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::VectorXd& d) {
  if (!d.allFinite() || d.isZero(0)) return false;
  const Interval dx = detail::dot(detail::iv(d), detail::iv(x));
  return dx.lower() > support(Z, d);
}

}  // namespace

BoolInterval contains(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& x) {
  const int n = Z.dimension(), m = Z.num_generators();
  if (x.size() != n) throw InputError("contains: point has the wrong dimension");
  if (!x.allFinite()) throw InputError("contains: point has a NaN or infinite entry");
  if (!sets::contains(outer_box(Z), x)) return BoolInterval::no;
  const IntervalVector v = detail::iv(x) - detail::iv(Z.center());
  const Eigen::VectorXd vm = midpoint(v);
  const Eigen::MatrixXd& G = Z.generators();
  if (m == 0) {
    for (int i = 0; i < n; ++i)
      if (!(v[i].lower() == 0 && v[i].upper() == 0)) return BoolInterval::unknown;
    return BoolInterval::yes;
  }

  // min t  s.t.  G xi = v, -t <= xi_j <= t.
  LinearProgram lp;
  lp.add_variables(m);
  const int t = lp.add_variables(1, 0.0, inf);
  for (int i = 0; i < n; ++i) {
    std::vector<std::pair<int, double>> row;
    for (int j = 0; j < m; ++j)
      if (G(i, j) != 0) row.emplace_back(j, G(i, j));
    lp.add_row(row, vm[i], vm[i]);
  }
  for (int j = 0; j < m; ++j) {
    lp.add_row(std::vector<std::pair<int, double>>{{j, 1.0}, {t, -1.0}}, -inf, 0.0);
    lp.add_row(std::vector<std::pair<int, double>>{{j, -1.0}, {t, -1.0}}, -inf, 0.0);
  }
  lp.set_objective_coordinate(t, Sense::minimize);
  const LpSolution sol = lp.solve();

  if (sol.status != LpStatus::optimal || sol.x[t] > 1) {
    // Candidate separating directions: the LP's multipliers of G xi = v, and the part of v
    // outside range(G) (flat zonotopes).
    if (sol.row_dual.size() >= n) {
      const Eigen::VectorXd y = sol.row_dual.head(n);
      if (separates(Z, x, y) || separates(Z, x, -y)) return BoolInterval::no;
    }
    const Eigen::VectorXd ls = G.completeOrthogonalDecomposition().solve(vm);
    const Eigen::VectorXd res = vm - G * ls;
    if (separates(Z, x, res)) return BoolInterval::no;
    return BoolInterval::unknown;
  }

  // Feasible with t <= 1: absorb the residual r = v - G xi with n independent generators B:
  // xi + B^{-1} r solves exactly, and |B^{-1} r| <= ||B^{-1}|| ||r||.
  const Eigen::VectorXd xi = sol.x.head(m);
  const IntervalVector r = v - multiply(G, detail::iv(xi));
  const double rn = detail::norm_upper(r);
  const double xmax = xi.cwiseAbs().maxCoeff();
  if (rn == 0) return xmax <= 1 ? BoolInterval::yes : BoolInterval::unknown;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(G);
  if (qr.rank() < n) return BoolInterval::unknown;  // flat: rounding cannot prove membership
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i) B.col(i) = G.col(qr.colsPermutation().indices()[i]);
  const Eigen::MatrixXd X = B.inverse();
  const auto inv = detail::inverse_norm_bound(B, X);
  if (!inv) return BoolInterval::unknown;
  const double eta = (Interval(*inv) * Interval(rn)).upper();
  if ((Interval(xmax) + Interval(eta)).upper() <= 1) return BoolInterval::yes;
  return BoolInterval::unknown;
}

// ------------------------------------------------------------------------------- reduction

Zonotope compact(const Zonotope& Z) {
  std::vector<int> keep;
  for (int j = 0; j < Z.num_generators(); ++j)
    if (!Z.generators().col(j).isZero(0)) keep.push_back(j);
  Eigen::MatrixXd G(Z.dimension(), keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) G.col(k) = Z.generators().col(keep[k]);
  return Zonotope(Z.center(), G);
}

namespace {

// Axis-aligned box around sum_j R_j [-1, 1].
Eigen::MatrixXd boxed_generators(const Eigen::MatrixXd& R) {
  const auto n = R.rows();
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    Interval s(0.0);
    for (Eigen::Index j = 0; j < R.cols(); ++j) s += Interval(std::abs(R(i, j)));
    D(i, i) = s.upper();
  }
  return D;
}

// Sum over the columns of R of |(X R)_ij| + dev ||R_j||: an upper bound on the row sums of
// |T^{-1} R| when ||T^{-1} - X||_2 <= dev. X R in floating point plus Higham's product bound.
Eigen::VectorXd frame_half_widths(const Eigen::MatrixXd& X, double dev, const Eigen::MatrixXd& R) {
  const Eigen::MatrixXd XR = X * R;
  const Eigen::MatrixXd err = product_error(X, R);
  Eigen::VectorXd col(R.cols());
  for (Eigen::Index j = 0; j < R.cols(); ++j)
    col[j] = (Interval(dev) * Interval(detail::norm_upper(detail::iv(R.col(j))))).upper();
  Eigen::VectorXd s(R.rows());
  for (Eigen::Index i = 0; i < R.rows(); ++i) {
    Interval acc(0.0);
    for (Eigen::Index j = 0; j < R.cols(); ++j) acc += Interval(std::abs(XR(i, j))) + Interval(err(i, j)) + Interval(col[j]);
    s[i] = acc.upper();
  }
  return s;
}

// The discarded generators R boxed in their principal axes T: R xi = T (T^{-1} R) xi, so a box of
// half-widths s in T's frame contains them. The stored generators are F = T diag(s') (rounded);
// a second verified pass checks that R's part fits in F's unit box, so no rounding generators
// are needed. Falls back to the axis-aligned box if verification fails.
Eigen::MatrixXd pca_generators(const Eigen::MatrixXd& R) {
  // Principal axes of the discarded generators: eigenvectors of R R^T (n x n, cheap).
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(R * R.transpose());
  const Eigen::MatrixXd T = es.eigenvectors();
  const auto dev = detail::inverse_deviation_bound(T, T.transpose());
  if (!dev) return boxed_generators(R);
  const Eigen::VectorXd s = frame_half_widths(T.transpose(), *dev, R) * (1 + 1e-9);
  if (!(s.minCoeff() > 0)) return boxed_generators(R);
  const Eigen::MatrixXd F = T * s.asDiagonal();
  const Eigen::MatrixXd Xf = s.cwiseInverse().asDiagonal() * T.transpose();
  const auto devf = detail::inverse_deviation_bound(F, Xf);
  if (!devf || !(frame_half_widths(Xf, *devf, R).maxCoeff() <= 1)) return boxed_generators(R);
  return F;
}

}  // namespace

Zonotope reduce_order(const Zonotope& Zin, double order, ReductionMethod method) {
  if (!(order >= 1)) throw InputError("reduce_order: order must be >= 1");
  const Zonotope Z = compact(Zin);
  const int n = Z.dimension(), m = Z.num_generators();
  const int target = std::max(n, static_cast<int>(std::floor(order * n)));
  if (m <= target) return Z;
  const int keep = target - n;  // the reduced part becomes n generators
  const Eigen::MatrixXd& G = Z.generators();
  std::vector<double> score(m);
  for (int j = 0; j < m; ++j)
    score[j] = method == ReductionMethod::girard ? G.col(j).lpNorm<1>() - G.col(j).lpNorm<Eigen::Infinity>()
                                                 : G.col(j).norm();
  std::vector<int> idx(m);
  std::iota(idx.begin(), idx.end(), 0);
  std::nth_element(idx.begin(), idx.begin() + keep, idx.end(),
                   [&](int a, int b) { return score[a] > score[b]; });
  Eigen::MatrixXd K(n, keep), R(n, m - keep);
  for (int k = 0; k < keep; ++k) K.col(k) = G.col(idx[k]);
  for (int k = keep; k < m; ++k) R.col(k - keep) = G.col(idx[k]);
  const Eigen::MatrixXd B = method == ReductionMethod::pca ? pca_generators(R) : boxed_generators(R);
  Eigen::MatrixXd out(n, keep + B.cols());
  out << K, B;
  return compact(Zonotope(Z.center(), out));
}

// ------------------------------------------------------------------------------- strips and FPS

std::optional<Zonotope> try_intersect_strip(const Zonotope& Z, const Eigen::Ref<const Eigen::VectorXd>& a, double y,
                                            double delta) {
  const int n = Z.dimension();
  if (a.size() != n) throw InputError("intersect_strip: regressor has the wrong dimension");
  if (!a.allFinite() || !std::isfinite(y) || !std::isfinite(delta) || delta < 0)
    throw InputError("intersect_strip: regressor, output and error bound must be finite, bound >= 0");
  const double hi_Z = support(Z, a), lo_Z = -support(Z, -a);
  const double lo_S = (Interval(y) - Interval(delta)).lower(), hi_S = (Interval(y) + Interval(delta)).upper();
  if (lo_S > hi_Z || hi_S < lo_Z) return std::nullopt;
  const double lo = std::max(lo_S, lo_Z), hi = std::min(hi_S, hi_Z);
  if (lo <= lo_Z && hi >= hi_Z) return Z;  // the strip does not cut Z
  const double ym = 0.5 * (lo + hi);
  const double dl = std::max((Interval(ym) - Interval(lo)).upper(), (Interval(hi) - Interval(ym)).upper());
  const Eigen::MatrixXd& G = Z.generators();
  const Eigen::VectorXd Gta = G.transpose() * a;
  const double den = Gta.squaredNorm() + dl * dl;
  if (!(den > 0)) return Z;
  const Eigen::VectorXd lambda = G * Gta / den;  // any lambda is valid; this one is F-optimal
  const IntervalVector li = detail::iv(lambda), ai = detail::iv(a);
  const Interval e = Interval(ym) - detail::dot(ai, detail::iv(Z.center()));
  IntervalVector c = detail::iv(Z.center());
  for (int i = 0; i < n; ++i) c[i] += li[i] * e;
  const int m = Z.num_generators();
  IntervalMatrix Gn(n, m + 1);
  const IntervalMatrix Gi = detail::im(G);
  for (int j = 0; j < m; ++j) {
    const Interval ag = detail::dot(ai, Gi.col(j));
    for (int i = 0; i < n; ++i) Gn(i, j) = Gi(i, j) - li[i] * ag;
  }
  for (int i = 0; i < n; ++i) Gn(i, m) = Interval(dl) * li[i];
  return detail::outer_zonotope(c, Gn);
}

std::string to_string(const Zonotope& Z) {
  std::ostringstream os;
  os.precision(17);
  os << "Zonotope(dim=" << Z.dimension() << ", center=[";
  for (int i = 0; i < Z.dimension(); ++i) os << (i ? ", " : "") << Z.center()[i];
  os << "], generators=[";
  for (int j = 0; j < Z.num_generators(); ++j) {
    os << (j ? ", [" : "[");
    for (int i = 0; i < Z.dimension(); ++i) os << (i ? ", " : "") << Z.generators()(i, j);
    os << "]";
  }
  os << "])";
  return os.str();
}

}  // namespace sets
