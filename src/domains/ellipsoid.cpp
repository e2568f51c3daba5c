#include "sets/domains/ellipsoid.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "sets/core/error.hpp"
#include "domains/interval_enclosure.hpp"
#include "numeric/verified_linear_algebra.hpp"

namespace sets {

namespace {

void check_finite(const Eigen::MatrixXd& M, const char* what) {
  if (!M.allFinite()) throw InputError(std::string("Ellipsoid: ") + what + " has a NaN or infinite entry");
}

}  // namespace

// ------------------------------------------------------------------------------- construction

Ellipsoid::Ellipsoid(Eigen::VectorXd center, Eigen::MatrixXd shape)
    : c_(std::move(center)), P_(std::move(shape)) {
  const auto n = c_.size();
  if (P_.rows() != n || P_.cols() != n)
    throw InputError("Ellipsoid: centre has " + std::to_string(n) + " entries but the shape matrix is " +
                     std::to_string(P_.rows()) + "x" + std::to_string(P_.cols()));
  check_finite(c_, "centre");
  check_finite(P_, "shape matrix");
  const double scale = n > 0 ? P_.cwiseAbs().maxCoeff() : 0.0;  // maxCoeff of an empty matrix reads past its end
  if (n > 0 && (P_ - P_.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
    throw InputError("Ellipsoid: shape matrix is not symmetric");
  P_ = (0.5 * (P_ + P_.transpose())).eval();
  if (n > 0 && scale > 0) {
    const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P_, Eigen::EigenvaluesOnly)
                            .eigenvalues()
                            .minCoeff();
    if (lmin < -1e-9 * scale)
      throw InputError("Ellipsoid: shape matrix is not positive semidefinite (eigenvalue " +
                       std::to_string(lmin) + ")");
  }
}

Ellipsoid Ellipsoid::ball(const Eigen::Ref<const Eigen::VectorXd>& c, double r) {
  if (!(r >= 0) || !std::isfinite(r)) throw InputError("Ellipsoid::ball: radius must be finite and >= 0");
  const Interval r2 = Interval(r) * Interval(r);
  return Ellipsoid(c, r2.upper() * Eigen::MatrixXd::Identity(c.size(), c.size()));
}

Ellipsoid Ellipsoid::from_level_set(const Eigen::Ref<const Eigen::VectorXd>& theta0,
                                    const Eigen::Ref<const Eigen::MatrixXd>& R, double gamma) {
  const auto n = theta0.size();
  if (R.rows() != n || R.cols() != n)
    throw InputError("Ellipsoid::from_level_set: theta0 has " + std::to_string(n) +
                     " entries but R is " + std::to_string(R.rows()) + "x" + std::to_string(R.cols()));
  check_finite(theta0, "theta0");
  check_finite(R, "R");
  if (!std::isfinite(gamma) || gamma < 0)
    throw InputError("Ellipsoid::from_level_set: gamma must be finite and >= 0 (got " +
                     std::to_string(gamma) + ")");
  const Eigen::MatrixXd Rs = 0.5 * (R + R.transpose());
  if ((R - Rs).cwiseAbs().maxCoeff() > 1e-9 * R.cwiseAbs().maxCoeff())
    throw InputError("Ellipsoid::from_level_set: R is not symmetric");
  Eigen::LLT<Eigen::MatrixXd> llt(Rs);
  if (llt.info() != Eigen::Success)
    throw InputError(
        "Ellipsoid::from_level_set: R is not positive definite (the level set is unbounded)");
  Eigen::MatrixXd X = llt.solve(Eigen::MatrixXd::Identity(n, n));
  X = (0.5 * (X + X.transpose())).eval();
  // ||R^{-1} - X||_2 <= ||X|| ||I - X R|| / (1 - ||I - X R||): enlarge X by that on the diagonal.
  const auto dev = detail::inverse_deviation_bound(Rs, X);
  if (!dev)
    throw NumericalError(
        "Ellipsoid::from_level_set: R is too ill-conditioned to invert with a guarantee");
  IntervalMatrix P(n, n);
  const Interval g(gamma);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      P(i, j) = g * (Interval(X(i, j)) + (i == j ? Interval(*dev) : Interval(0.0)));
  return detail::outer_ellipsoid(detail::iv(theta0), P);
}

// ------------------------------------------------------------------------------- helpers

namespace detail {

Ellipsoid outer_ellipsoid(const IntervalVector& c, const IntervalMatrix& P) {
  const auto n = c.size();
  Eigen::MatrixXd M = upper_symmetric_bound(P);
  const Eigen::VectorXd cm = midpoint(c);
  const double rho = norm_upper(c - detail::iv(cm));
  if (rho > 0) {
    // The centre is only known to a ball of radius rho: E(cm, M) + rho B is contained in
    // E(cm, (1 + 1/p) M + (1 + p) rho^2 I) for every p > 0; p = sqrt(tr M / (n rho^2)) is the
    // minimum-trace choice.
    Interval tr(0.0);
    for (Eigen::Index i = 0; i < n; ++i) tr += Interval(std::max(M(i, i), 0.0));
    const Interval r2 = Interval(rho) * Interval(rho);
    IntervalMatrix S(n, n);
    if (tr.upper() <= 0) {
      for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j) S(i, j) = i == j ? r2 : Interval(0.0);
    } else {
      const double p = std::sqrt(midpoint(tr) / (static_cast<double>(n) * midpoint(r2)));
      const Interval a = Interval(1.0) + Interval(1.0) / Interval(p);
      const Interval b = (Interval(1.0) + Interval(p)) * r2;
      for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j) S(i, j) = a * Interval(M(i, j)) + (i == j ? b : Interval(0.0));
    }
    M = upper_symmetric_bound(S);
  }
  // M is symmetric by construction and dominates a PSD matrix, so it is PSD up to rounding.
  return Ellipsoid(cm, M);
}

}  // namespace detail

// ------------------------------------------------------------------------------- queries

namespace {

void check_dim(const Ellipsoid& E, Eigen::Index n, const char* what) {
  if (n != E.dimension())
    throw InputError(std::string(what) + ": vector has " + std::to_string(n) +
                     " entries but the ellipsoid has dimension " + std::to_string(E.dimension()));
}

void check_coords(const Ellipsoid& E, const std::vector<int>& coords, const char* what) {
  for (int k : coords)
    if (k < 0 || k >= E.dimension())
      throw InputError(std::string(what) + ": coordinate " + std::to_string(k) +
                       " is out of range for an ellipsoid of dimension " + std::to_string(E.dimension()));
}

// Symmetric pseudo-inverse with a relative eigenvalue cut-off.
Eigen::MatrixXd pseudo_inverse(const Eigen::MatrixXd& A, double rel_tol = 1e-12) {
  if (A.size() == 0) return A;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  const Eigen::VectorXd& l = es.eigenvalues();
  const double cut = rel_tol * std::max(l.cwiseAbs().maxCoeff(), 0.0);
  Eigen::VectorXd li(l.size());
  for (Eigen::Index i = 0; i < l.size(); ++i) li[i] = l[i] > cut ? 1.0 / l[i] : 0.0;
  return es.eigenvectors() * li.asDiagonal() * es.eigenvectors().transpose();
}

}  // namespace

Ellipsoid project(const Ellipsoid& E, const std::vector<int>& coords) {
  check_coords(E, coords, "project");
  const auto k = static_cast<Eigen::Index>(coords.size());
  Eigen::VectorXd c(k);
  Eigen::MatrixXd P(k, k);
  for (Eigen::Index i = 0; i < k; ++i) {
    c[i] = E.center()[coords[i]];
    for (Eigen::Index j = 0; j < k; ++j) P(i, j) = E.shape()(coords[i], coords[j]);
  }
  return Ellipsoid(c, P);
}

std::optional<Ellipsoid> slice(const Ellipsoid& E, const std::vector<int>& coords,
                               const Eigen::Ref<const Eigen::VectorXd>& fixed) {
  check_coords(E, coords, "slice");
  const int n = E.dimension();
  std::vector<bool> kept(n, false);
  for (int k : coords) {
    if (kept[k]) throw InputError("slice: coordinate " + std::to_string(k) + " is listed twice");
    kept[k] = true;
  }
  std::vector<int> other;
  for (int i = 0; i < n; ++i)
    if (!kept[i]) other.push_back(i);
  if (static_cast<Eigen::Index>(other.size()) != fixed.size())
    throw InputError("slice: " + std::to_string(other.size()) + " coordinates are fixed but " +
                     std::to_string(fixed.size()) + " values were given");
  const auto k = static_cast<Eigen::Index>(coords.size());
  const auto f = static_cast<Eigen::Index>(other.size());
  Eigen::MatrixXd Pkk(k, k), Pkf(k, f), Pff(f, f);
  Eigen::VectorXd ck(k), w(f);
  for (Eigen::Index i = 0; i < k; ++i) {
    ck[i] = E.center()[coords[i]];
    for (Eigen::Index j = 0; j < k; ++j) Pkk(i, j) = E.shape()(coords[i], coords[j]);
    for (Eigen::Index j = 0; j < f; ++j) Pkf(i, j) = E.shape()(coords[i], other[j]);
  }
  for (Eigen::Index i = 0; i < f; ++i) {
    w[i] = fixed[i] - E.center()[other[i]];
    for (Eigen::Index j = 0; j < f; ++j) Pff(i, j) = E.shape()(other[i], other[j]);
  }
  // P_FF^+ w and P_FF^+ P_KF^T. By Cholesky when P_FF is safely positive definite: its estimated
  // reciprocal condition number above 1e-10, a margin of 100 over the cut-off of pseudo_inverse
  // (1e-12), which then cuts nothing and is the inverse; the eigen-decomposition was most of the
  // cost of a slice. Otherwise (flat or nearly flat) the pseudo-inverse.
  Eigen::VectorXd Pffi_w;
  Eigen::MatrixXd Pffi_Pfk;
  const Eigen::LLT<Eigen::MatrixXd> llt(Pff);
  if (f > 0 && llt.info() == Eigen::Success && llt.rcond() > 1e-10) {
    Pffi_w = llt.solve(w);
    Pffi_Pfk = llt.solve(Pkf.transpose());
  } else {
    const Eigen::MatrixXd Pffi = pseudo_inverse(Pff);
    Pffi_w = Pffi * w;
    Pffi_Pfk = Pffi * Pkf.transpose();
  }
  // Off range(P_FF): the fixed values leave the (flat) ellipsoid's affine hull.
  const double scale = std::max(1.0, w.norm());
  if (f > 0 && (Pff * Pffi_w - w).norm() > 1e-9 * scale) return std::nullopt;
  const double kappa = 1.0 - w.dot(Pffi_w);
  if (kappa < -1e-12) return std::nullopt;
  const Eigen::VectorXd c = ck + Pkf * Pffi_w;
  Eigen::MatrixXd S = Pkk - Pkf * Pffi_Pfk;
  S = (0.5 * (S + S.transpose())).eval();
  // Rounding can leave tiny negative eigenvalues in the Schur complement: clip them.
  if (k > 0) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
    Eigen::VectorXd l = es.eigenvalues().cwiseMax(0.0);
    S = es.eigenvectors() * l.asDiagonal() * es.eigenvectors().transpose();
    S = (0.5 * (S + S.transpose())).eval();
  }
  return Ellipsoid(c, std::max(kappa, 0.0) * S);
}

double support(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& d) {
  check_dim(E, d.size(), "support");
  const IntervalVector di = detail::iv(d);
  const Interval lin = detail::dot(di, detail::iv(E.center()));
  const Interval q = detail::dot(di, multiply(E.shape(), di));
  const double qu = std::max(q.upper(), 0.0);
  return (lin + sqrt(Interval(qu))).upper();
}

IntervalVector outer_box(const Ellipsoid& E) {
  const int n = E.dimension();
  IntervalVector b(n);
  for (int i = 0; i < n; ++i) {
    const double r = sqrt(Interval(std::max(E.shape()(i, i), 0.0))).upper();
    b[i] = Interval(E.center()[i]) + Interval(-r, r);
  }
  return b;
}

BoolInterval contains(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& x) {
  check_dim(E, x.size(), "contains");
  if (!x.allFinite()) throw InputError("contains: point has a NaN or infinite entry");
  const int n = E.dimension();
  if (n == 0) return BoolInterval::yes;
  const Eigen::MatrixXd& P = E.shape();
  const IntervalVector v = detail::iv(x) - detail::iv(E.center());
  const Eigen::VectorXd vm = midpoint(v);
  const IntervalMatrix Pi = detail::im(P);

  // "no": a direction d with d^T v > sqrt(d^T P d) separates x from E (support function).
  auto separates = [&](const Eigen::VectorXd& d) {
    if (!d.allFinite() || d.isZero(0)) return false;
    const IntervalVector di = detail::iv(d);
    Interval dv = detail::dot(di, v);
    if (dv.upper() < 0) dv = -dv;
    if (!(dv.lower() > 0)) return false;
    const Interval dpd = detail::dot(di, multiply(Pi, di));
    return (dv * dv).lower() > std::max(dpd.upper(), 0.0) && dv.lower() > 0;
  };

  Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() == Eigen::Success) {
    const Eigen::MatrixXd X = llt.solve(Eigen::MatrixXd::Identity(n, n));
    const Eigen::VectorXd z = X * vm;
    if (separates(z)) return BoolInterval::no;
    if (const auto inv = detail::inverse_norm_bound(P, X)) {
      // q = v^T P^{-1} v = v^T z + v^T P^{-1} r with r = v - P z (exact identity).
      const IntervalVector zi = detail::iv(z);
      const IntervalVector r = v - multiply(Pi, zi);
      const Interval err = Interval(*inv) * Interval(detail::norm_upper(v)) *
                           Interval(detail::norm_upper(r));
      const Interval q = detail::dot(v, zi) + Interval(-err.upper(), err.upper());
      if (q.upper() <= 1) return BoolInterval::yes;
      if (q.lower() > 1) return BoolInterval::no;
      return BoolInterval::unknown;
    }
  }
  // Singular (flat) or ill-conditioned P: x is in E iff v = P w with w^T P w <= 1.
  const Eigen::MatrixXd Pp = pseudo_inverse(P);
  const Eigen::VectorXd z = Pp * vm;
  if (separates(z)) return BoolInterval::no;
  const Eigen::VectorXd res = vm - P * z;
  if (separates(res)) return BoolInterval::no;
  if (separates(z + res / std::max(res.norm(), 1e-300) * z.norm())) return BoolInterval::no;
  // A "yes" needs P z = v to hold exactly, which rounding allows only in special cases.
  const IntervalVector zi = detail::iv(z);
  const IntervalVector r = v - multiply(Pi, zi);
  bool exact = true;
  for (int i = 0; i < n; ++i) exact = exact && r[i].lower() == 0 && r[i].upper() == 0;
  if (exact && detail::dot(zi, multiply(Pi, zi)).upper() <= 1) return BoolInterval::yes;
  return BoolInterval::unknown;
}

double volume(const Ellipsoid& E) {
  const int n = E.dimension();
  if (n == 0) return 1.0;
  const Eigen::VectorXd l = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(E.shape(), Eigen::EigenvaluesOnly)
                                .eigenvalues();
  double logdet = 0;
  for (int i = 0; i < n; ++i) {
    if (l[i] <= 0) return 0.0;
    logdet += std::log(l[i]);
  }
  const double log_ball = 0.5 * n * std::log(std::numbers::pi) - std::lgamma(0.5 * n + 1);
  return std::exp(log_ball + 0.5 * logdet);
}

double flatness(const Ellipsoid& E) {
  if (E.dimension() == 0) return 1.0;
  const Eigen::VectorXd l = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(E.shape(), Eigen::EigenvaluesOnly)
                                .eigenvalues();
  if (l.maxCoeff() <= 0) return 0.0;
  return std::max(l.minCoeff(), 0.0) / l.maxCoeff();
}

// ------------------------------------------------------------------------------- operations

Ellipsoid linear_map(const Eigen::Ref<const Eigen::MatrixXd>& A, const Ellipsoid& E) {
  if (A.cols() != E.dimension())
    throw InputError("linear_map: matrix has " + std::to_string(A.cols()) +
                     " columns but the ellipsoid has dimension " + std::to_string(E.dimension()));
  if (!A.allFinite()) throw InputError("linear_map: matrix has a NaN or infinite entry");
  const IntervalMatrix Ai = detail::im(A);
  const IntervalVector c = multiply(Eigen::MatrixXd(A), detail::iv(E.center()));
  const IntervalMatrix P = detail::multiply(detail::multiply(Ai, detail::im(E.shape())), Ai.transpose());
  return detail::outer_ellipsoid(c, P);
}

Ellipsoid translate(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& b) {
  check_dim(E, b.size(), "translate");
  const IntervalVector c = detail::iv(E.center()) + detail::iv(b);
  return detail::outer_ellipsoid(c, detail::im(E.shape()));
}

namespace {

double trace_or_logdet(const Eigen::MatrixXd& S, EllipsoidCriterion criterion) {
  if (criterion == EllipsoidCriterion::min_trace) return S.trace();
  Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
  return 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
}

// Golden-section minimisation of a unimodal function on [lo, hi].
template <class F>
double golden_min(F f, double lo, double hi, int iterations = 80) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = lo, b = hi;
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < iterations; ++i) {
    if (f1 <= f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - g * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + g * (b - a);
      f2 = f(x2);
    }
  }
  return 0.5 * (a + b);
}

}  // namespace

Ellipsoid minkowski_sum(const Ellipsoid& E1, const Ellipsoid& E2, EllipsoidCriterion criterion) {
  if (E1.dimension() != E2.dimension())
    throw InputError("minkowski_sum: dimensions " + std::to_string(E1.dimension()) + " and " +
                     std::to_string(E2.dimension()) + " differ");
  const int n = E1.dimension();
  const IntervalVector c = detail::iv(E1.center()) + detail::iv(E2.center());
  const double t1 = E1.shape().trace(), t2 = E2.shape().trace();
  if (t1 <= 0) return detail::outer_ellipsoid(c, detail::im(E2.shape()));
  if (t2 <= 0) return detail::outer_ellipsoid(c, detail::im(E1.shape()));
  double p = std::sqrt(t1 / t2);
  if (criterion == EllipsoidCriterion::min_volume) {
    auto f = [&](double lp) {
      const double pp = std::exp(lp);
      const double v = trace_or_logdet((1 + 1 / pp) * E1.shape() + (1 + pp) * E2.shape(), criterion);
      return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
    };
    const double lp0 = std::log(p);
    if (std::isfinite(f(lp0))) p = std::exp(golden_min(f, lp0 - 30, lp0 + 30));
  }
  const Interval a = Interval(1.0) + Interval(1.0) / Interval(p);
  const Interval b = Interval(1.0) + Interval(p);
  IntervalMatrix S(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) S(i, j) = a * Interval(E1.shape()(i, j)) + b * Interval(E2.shape()(i, j));
  return detail::outer_ellipsoid(c, S);
}

namespace {

// E and the strip a^T x in [lo, hi] (already clipped to E's extent along a), in intervals.
struct StripCut {
  IntervalVector ai, Pa;  // a, and P a
  IntervalMatrix Pi;      // P
  Interval g, e;          // a^T P a; the innovation ym - a^T c
  double lo = 0, hi = 0, ym = 0, dl = 0;  // the strip's ends, middle and half-width (rounded up)
};

// The intersection with the hyperplane a^T x = ym (dl = 0), exactly the ellipsoid with centre
// c + e P a / g and shape (1 - e^2/g) (P - P a a^T P / g) (conditioning formulas).
Ellipsoid cut_by_hyperplane(const Ellipsoid& E, const StripCut& s) {
  const auto n = E.dimension();
  const Interval beta = Interval(1.0) - s.e * s.e / s.g;
  IntervalVector c = detail::iv(E.center());
  for (int i = 0; i < n; ++i) c[i] += s.e / s.g * s.Pa[i];
  IntervalMatrix P(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      P(i, j) = Interval(std::max(beta.upper(), 0.0)) * (s.Pi(i, j) - s.Pa[i] * s.Pa[j] / s.g);
  return detail::outer_ellipsoid(c, P);
}

// 1-D: the intersection is an interval, which is itself the optimal ellipsoid.
Ellipsoid cut_in_one_dimension(const StripCut& s) {
  IntervalVector c(1);
  c[0] = (Interval(s.lo) + Interval(s.hi)) / Interval(2.0) / s.ai[0];
  const Interval r = (Interval(s.hi) - Interval(s.lo)) / Interval(2.0) / abs(s.ai[0]);
  IntervalMatrix P(1, 1);
  P(0, 0) = r * r;
  return detail::outer_ellipsoid(c, P);
}

// Schweppe's family with weight q: (x-c)^T P^{-1} (x-c) + q (ym - a^T x)^2 / dl^2 <= 1 + q.
// With s = dl^2 + q g: centre c + q e P a / s, shape beta (P - q P a a^T P / s),
// beta = 1 + q - q e^2 / s.
Ellipsoid schweppe_member(const Ellipsoid& E, const StripCut& s, const Interval& q) {
  const auto n = E.dimension();
  const Interval sq = Interval(s.dl) * Interval(s.dl) + q * s.g;
  const Interval beta = Interval(1.0) + q - q * s.e * s.e / sq;
  IntervalVector c = detail::iv(E.center());
  const Interval k = q * s.e / sq;
  for (int i = 0; i < n; ++i) c[i] += k * s.Pa[i];
  IntervalMatrix P(n, n);
  const Interval h = q / sq;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) P(i, j) = beta * (s.Pi(i, j) - h * s.Pa[i] * s.Pa[j]);
  return detail::outer_ellipsoid(c, P);
}

// Fogel & Huang's minimum-volume weight: s = d^2 + q g solves
// (n-1) s^2 - (g - d^2 - e^2) s - (n+1) e^2 d^2 = 0.
double minimum_volume_weight(int n, double gm, double d2, double em) {
  const double B = gm - d2 - em * em;
  const double s_vol = (B + std::sqrt(B * B + 4.0 * (n - 1.0) * (n + 1.0) * em * em * d2)) / (2.0 * (n - 1.0));
  return (s_vol - d2) / gm;
}

// Minimum-trace weight: 1-D search (grid in log q, then golden section); 0 when no q > 0 beats E.
double minimum_trace_weight(const Ellipsoid& E, const StripCut& s, double gm, double d2, double em) {
  const double trP = E.shape().trace();
  const double pa2 = midpoint(detail::dot(s.Pa, s.Pa));
  auto tr = [&](double qq) {
    const double sq = d2 + qq * gm;
    return (1 + qq - qq * em * em / sq) * (trP - qq * pa2 / sq);
  };
  double q_tr = 0, fbest = trP, best_lq = 0;
  for (double lq = -10; lq <= 10; lq += 0.25) {
    const double v = tr(std::pow(10.0, lq));
    if (v < fbest) fbest = v, best_lq = lq, q_tr = 1;
  }
  if (q_tr > 0)
    q_tr = std::pow(10.0, golden_min([&](double lq) { return tr(std::pow(10.0, lq)); }, best_lq - 0.25, best_lq + 0.25));
  return q_tr;
}

}  // namespace

std::optional<Ellipsoid> try_intersect_strip(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& a, double y,
                                             double delta, const StripOptions& options) {
  check_dim(E, a.size(), "intersect_strip");
  if (!a.allFinite() || !std::isfinite(y) || !std::isfinite(delta) || delta < 0)
    throw InputError("intersect_strip: regressor, output and error bound must be finite, bound >= 0");
  const int n = E.dimension();
  StripCut s;
  s.ai = detail::iv(a);
  s.Pi = detail::im(E.shape());
  s.Pa = multiply(s.Pi, s.ai);
  s.g = detail::dot(s.ai, s.Pa);
  const Interval ac = detail::dot(s.ai, detail::iv(E.center()));
  const Interval half_width = sqrt(Interval(std::max(s.g.upper(), 0.0)));
  // E's extent along a is inside [lo_E, hi_E]; the strip is [y - delta, y + delta].
  const double lo_E = (ac - half_width).lower(), hi_E = (ac + half_width).upper();
  const double lo_S = (Interval(y) - Interval(delta)).lower(), hi_S = (Interval(y) + Interval(delta)).upper();
  if (lo_S > hi_E || hi_S < lo_E) return std::nullopt;  // provably disjoint
  // Clip the strip to E's extent: the intersection is unchanged and the update is tighter.
  s.lo = std::max(lo_S, lo_E), s.hi = std::min(hi_S, hi_E);
  if (s.lo <= lo_E && s.hi >= hi_E) return E;  // the strip does not cut E
  s.ym = 0.5 * (s.lo + s.hi);
  s.dl = std::max((Interval(s.ym) - Interval(s.lo)).upper(), (Interval(s.hi) - Interval(s.ym)).upper());
  const double gm = s.g.upper();
  if (gm <= 0) return E;  // E is flat along a: nothing to cut
  s.e = Interval(s.ym) - ac;  // innovation
  if (s.dl == 0) return cut_by_hyperplane(E, s);
  if (n == 1) return cut_in_one_dimension(s);
  const double d2 = s.dl * s.dl, em = midpoint(s.e);
  // Rounding enlarges each candidate differently (large q means cancellation), so compare the
  // stored results, E itself included, by the requested measure.
  std::vector<Ellipsoid> cand{E};
  for (double q : {minimum_volume_weight(n, gm, d2, em), minimum_trace_weight(E, s, gm, d2, em)})
    if (q > 0 && std::isfinite(q)) cand.push_back(schweppe_member(E, s, Interval(q)));
  auto measure = [&](const Ellipsoid& F) {
    if (options.criterion == EllipsoidCriterion::min_trace) return std::pair{F.shape().trace(), 0.0};
    return std::pair{volume(F), F.shape().trace()};  // flat: volumes tie at 0, trace decides
  };
  std::size_t best = 0;
  for (std::size_t k = 1; k < cand.size(); ++k)
    if (measure(cand[k]) < measure(cand[best])) best = k;
  return cand[best];
}

Ellipsoid intersect_strip(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& a, double y, double delta,
                          const StripOptions& options) {
  auto r = try_intersect_strip(E, a, y, delta, options);
  if (!r)
    throw EmptySetError("intersect_strip: the ellipsoid and the strip |" + std::to_string(y) +
                        " - a^T x| <= " + std::to_string(delta) + " do not meet");
  return *r;
}

Ellipsoid intersect_strip(const Ellipsoid& E, const Eigen::Ref<const Eigen::VectorXd>& a, double y, double delta,
                          EllipsoidCriterion criterion) {
  return intersect_strip(E, a, y, delta, StripOptions{criterion});
}

// ------------------------------------------------------------------------------- output

std::string to_string(const Ellipsoid& E) {
  std::ostringstream os;
  os.precision(17);
  os << "Ellipsoid(dim=" << E.dimension() << ", center=[";
  for (int i = 0; i < E.dimension(); ++i) os << (i ? ", " : "") << E.center()[i];
  os << "], shape=[";
  for (int i = 0; i < E.dimension(); ++i) {
    os << (i ? ", [" : "[");
    for (int j = 0; j < E.dimension(); ++j) os << (j ? ", " : "") << E.shape()(i, j);
    os << "]";
  }
  os << "])";
  return os.str();
}

}  // namespace sets
