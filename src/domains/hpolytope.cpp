#include "sets/domains/hpolytope.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "sets/core/error.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/numeric/lp_certificate.hpp"
#include "numeric/certified_extent.hpp"
#include "numeric/verified_linear_algebra.hpp"

namespace sets {

HPolytope::HPolytope(Eigen::MatrixXd A, Eigen::VectorXd b) : A_(std::move(A)), b_(std::move(b)) {
  if (A_.rows() != b_.size())
    throw InputError("HPolytope: A has " + std::to_string(A_.rows()) + " rows but b has " +
                     std::to_string(b_.size()) + " entries");
  if (A_.hasNaN() || b_.hasNaN()) throw InputError("HPolytope: A or b contains NaN");
  if (!A_.allFinite()) throw InputError("HPolytope: A has an infinite entry");
  for (Eigen::Index i = 0; i < b_.size(); ++i)
    if (b_[i] == -inf) throw InputError("HPolytope: b(" + std::to_string(i) + ") is -inf");
}

BoolInterval contains(const HPolytope& P, const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (x.size() != P.dimension())
    throw InputError("contains: point has " + std::to_string(x.size()) + " entries, polytope dimension " +
                     std::to_string(P.dimension()));
  const IntervalVector Ax = multiply(P.A(), detail::iv(x));
  BoolInterval r = BoolInterval::yes;
  for (int i = 0; i < P.num_constraints(); ++i) {
    if (P.b()[i] == inf) continue;
    const Interval s = Ax[i] - Interval(P.b()[i]);
    if (s.lower() > 0) return BoolInterval::no;
    if (s.upper() > 0) r = BoolInterval::unknown;
  }
  return r;
}

namespace {

LinearProgram make_lp(const HPolytope& P) {
  LinearProgram lp(P.dimension());
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(P.num_constraints(), -inf);
  if (P.num_constraints() > 0) lp.add_rows(P.A(), lo, P.b());
  return lp;
}

[[noreturn]] void throw_empty(const char* what) {
  throw EmptySetError(std::string(what) + ": the polytope is empty");
}

// A certified bound on max d^T x over P from an optimal vertex, needing no box (so it works for
// unbounded P): n rows S active at the LP optimum with A_S invertible give the multipliers
// y_S = A_S^{-T} d. If an enclosure of the exact y_S is >= 0, weak duality
// d^T x = y_S^T A_S x <= y_S^T b_S holds for every x in P, and the sup over the enclosure bounds
// it. +inf when no such vertex certificate exists (unbounded direction, degenerate or
// ill-conditioned vertex).
double vertex_dual_bound(const HPolytope& P, LinearProgram& lp, const Eigen::VectorXd& d) {
  const int n = P.dimension(), m = P.num_constraints();
  for (int j = 0; j < n; ++j) lp.set_variable_bounds(j, -inf, inf);
  lp.set_objective(d, Sense::maximize);
  const LpSolution sol = lp.solve();
  if (sol.status != LpStatus::optimal) return inf;
  // Rows carrying a multiplier first, then the tightest other active rows, until n rows.
  std::vector<std::pair<double, int>> order;
  const Eigen::VectorXd slack = P.b() - P.A() * sol.x;
  for (int i = 0; i < m; ++i) {
    if (!std::isfinite(P.b()[i])) continue;
    const double scale = 1 + std::abs(P.b()[i]) + P.A().row(i).cwiseAbs().sum() * sol.x.cwiseAbs().maxCoeff();
    const double key = sol.row_dual[i] != 0 ? -1.0 : std::abs(slack[i]) / scale;
    if (key <= 1e-7) order.emplace_back(key, i);
  }
  if (static_cast<int>(order.size()) < n) return inf;
  std::sort(order.begin(), order.end());
  Eigen::MatrixXd AtS(n, n);  // A_S^T
  Eigen::VectorXd bS(n);
  for (int k = 0; k < n; ++k) {
    AtS.col(k) = P.A().row(order[static_cast<std::size_t>(k)].second).transpose();
    bS[k] = P.b()[order[static_cast<std::size_t>(k)].second];
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(AtS);
  if (!lu.isInvertible()) return inf;
  const Eigen::MatrixXd X = lu.inverse();
  const auto dev = detail::inverse_deviation_bound(AtS, X);  // ||A_S^{-T} - X||_2
  if (!dev) return inf;
  // y = X d + (A_S^{-T} - X) d: each entry within ||A_S^{-T} - X||_2 ||d||_2 of (X d)_k.
  const IntervalVector Xd = multiply(X, detail::iv(d));
  const Interval err = Interval(*dev) * Interval(detail::norm_upper(detail::iv(d)));
  Interval total(0.0);
  for (int k = 0; k < n; ++k) {
    const Interval y = Xd[k] + Interval(-err.upper(), err.upper());
    if (y.lower() < 0) return inf;  // a multiplier that may be negative certifies nothing
    total += y * Interval(bS[k]);
  }
  return total.upper();
}

// Certified upper bounds of max d^T x over P for each direction (see the header for the method).
std::vector<double> safe_maxima(const HPolytope& P, const std::vector<Eigen::VectorXd>& dirs,
                                const char* what) {
  const int n = P.dimension();
  for (const auto& d : dirs)
    if (d.size() != n) throw InputError(std::string(what) + ": direction has the wrong dimension");
  if (n == 0) {
    if (is_empty(P) == BoolInterval::yes) throw_empty(what);
    return std::vector<double>(dirs.size(), 0.0);
  }
  LinearProgram lp = make_lp(P);
  const detail::Extent e = detail::certified_extent(
      lp,
      [&](int& lps) {
        ++lps;
        return lp.solve();
      },
      dirs, true);
  if (e.status == detail::ExtentStatus::empty) throw_empty(what);
  if (e.status == detail::ExtentStatus::unknown) return std::vector<double>(dirs.size(), inf);
  // Where the box argument certified nothing (P unbounded, or the direction is), a bounded
  // direction can still be certified by its optimal vertex.
  std::vector<double> out = e.maxima;
  for (std::size_t k = 0; k < dirs.size(); ++k)
    if (out[k] == inf) out[k] = vertex_dual_bound(P, lp, dirs[k]);
  return out;
}

}  // namespace

BoolInterval is_empty(const HPolytope& P) {
  if (P.num_constraints() == 0) return BoolInterval::no;
  LinearProgram lp = make_lp(P);
  return certified_is_empty(lp);  // exact certificates either way, else unknown
}

IntervalVector outer_box(const HPolytope& P) {
  const int n = P.dimension();
  std::vector<Eigen::VectorXd> dirs;
  for (int j = 0; j < n; ++j) {
    dirs.push_back(Eigen::VectorXd::Unit(n, j));
    dirs.push_back(-Eigen::VectorXd::Unit(n, j));
  }
  const auto v = safe_maxima(P, dirs, "outer_box");
  IntervalVector box(n);
  for (int j = 0; j < n; ++j) box[j] = Interval(-v[2 * j + 1], v[2 * j]);
  return box;
}

double support(const HPolytope& P, const Eigen::Ref<const Eigen::VectorXd>& d) {
  return safe_maxima(P, {d}, "support")[0];
}

std::vector<double> support(const HPolytope& P, const std::vector<Eigen::VectorXd>& directions) {
  return safe_maxima(P, directions, "support");
}

ChebyshevBall chebyshev_ball(const HPolytope& P) {
  const int n = P.dimension(), m = P.num_constraints();
  // max r  s.t.  a_i^T x + ||a_i|| r <= b_i, r >= 0.
  LinearProgram lp(n);
  const int r = lp.add_variables(1, 0.0, inf);
  for (int i = 0; i < m; ++i) {
    Eigen::VectorXd row(n + 1);
    row << P.A().row(i).transpose(), P.A().row(i).norm();
    lp.add_row(row, -inf, P.b()[i]);
  }
  lp.set_objective_coordinate(r, Sense::maximize);
  const LpSolution sol = lp.solve();
  if (sol.status == LpStatus::infeasible) {
    if (is_empty(P) == BoolInterval::yes) throw_empty("chebyshev_ball");
    throw NumericalError("chebyshev_ball: the LP solver found no feasible point");
  }
  ChebyshevBall ball;
  if (sol.status == LpStatus::unbounded) {
    ball.radius = inf;
    ball.center = Eigen::VectorXd::Zero(n);
    return ball;
  }
  ball.center = sol.x.head(n);
  ball.radius = sol.x[r];
  return ball;
}

HPolytope intersect(const HPolytope& P, const HPolytope& Q) {
  if (P.dimension() != Q.dimension())
    throw InputError("intersect: dimensions " + std::to_string(P.dimension()) + " and " +
                     std::to_string(Q.dimension()) + " differ");
  Eigen::MatrixXd A(P.num_constraints() + Q.num_constraints(), P.dimension());
  Eigen::VectorXd b(A.rows());
  A << P.A(), Q.A();
  b << P.b(), Q.b();
  return HPolytope(A, b);
}

HPolytope remove_redundant(const HPolytope& P) {
  const int n = P.dimension();
  // Trivial rows and exact duplicates first.
  std::vector<int> rows;
  for (int i = 0; i < P.num_constraints(); ++i) {
    if (P.b()[i] == inf) continue;
    if (P.A().row(i).isZero(0)) {
      if (P.b()[i] >= 0) continue;
      return HPolytope(P.A().row(i), P.b().segment(i, 1));  // 0 <= b < 0: empty, one row says so
    }
    bool dup = false;
    for (int& k : rows)
      if (P.A().row(k) == P.A().row(i)) {
        if (P.b()[i] < P.b()[k]) k = i;
        dup = true;
        break;
      }
    if (!dup) rows.push_back(i);
  }
  // LP test: row i is redundant if max a_i^T x over the other rows (and a_i^T x <= b_i + 1, to
  // keep the LP bounded) stays <= b_i.
  std::vector<bool> keep(rows.size(), true);
  LinearProgram lp(n);
  for (int i : rows) lp.add_row(P.A().row(i).transpose(), -inf, P.b()[i]);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const int i = rows[k];
    const double bi = P.b()[i];
    const double slack = 1.0 + std::abs(bi);
    lp.set_row_bounds(static_cast<int>(k), -inf, bi + slack);
    lp.set_objective(P.A().row(i).transpose(), Sense::maximize);
    const LpSolution sol = lp.solve();
    if (sol.status == LpStatus::infeasible) {
      lp.set_row_bounds(static_cast<int>(k), -inf, bi);
      continue;  // the others alone are empty: keep the row (emptiness is preserved either way)
    }
    if (sol.status == LpStatus::optimal && sol.objective <= bi) {  // no tolerance: keeping is safe
      keep[k] = false;
      lp.set_row_bounds(static_cast<int>(k), -inf, inf);  // dropped from later tests too
    } else {
      lp.set_row_bounds(static_cast<int>(k), -inf, bi);
    }
  }
  std::vector<int> out;
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (keep[k]) out.push_back(rows[k]);
  Eigen::MatrixXd A(out.size(), n);
  Eigen::VectorXd b(out.size());
  for (std::size_t k = 0; k < out.size(); ++k) {
    A.row(k) = P.A().row(out[k]);
    b[k] = P.b()[out[k]];
  }
  return HPolytope(A, b);
}

HPolytope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& M, const HPolytope& P) {
  const int n = P.dimension();
  if (M.rows() != n || M.cols() != n)
    throw UnsupportedError("linear_map(HPolytope): only square invertible maps are supported (got " +
                           std::to_string(M.rows()) + "x" + std::to_string(M.cols()) +
                           "); project through to_vpolytope in 2-D/3-D");
  Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
  if (!lu.isInvertible())
    throw UnsupportedError("linear_map(HPolytope): the map is singular (a projection); use "
                           "to_vpolytope in 2-D/3-D");
  const Eigen::MatrixXd Minv_T = lu.inverse().transpose();
  // y = M x: the row c_i = M^{-T} a_i (rounded) bounds y by max_{x in P} (M^T c_i)^T x.
  std::vector<Eigen::VectorXd> dirs;
  Eigen::MatrixXd C(P.num_constraints(), n);
  for (int i = 0; i < P.num_constraints(); ++i) {
    C.row(i) = (Minv_T * P.A().row(i).transpose()).transpose();
    dirs.push_back(M.transpose() * C.row(i).transpose());  // rounded direction: bound is still valid
  }
  // The bound must hold for the exact M^T c_i; evaluate it with a certified enclosure instead:
  // max (M^T c)^T x <= max d^T x + max |(M^T c - d)^T x| <= support(d) + ||M^T c - d||_1 * max|x|.
  const IntervalVector box = outer_box(P);
  double xmag = 0;
  for (int j = 0; j < n; ++j) xmag = std::max({xmag, std::abs(box[j].lower()), std::abs(box[j].upper())});
  if (!std::isfinite(xmag)) throw UnsupportedError("linear_map(HPolytope): the polytope is unbounded");
  const auto s = support(P, dirs);
  Eigen::VectorXd b(P.num_constraints());
  for (int i = 0; i < P.num_constraints(); ++i) {
    const IntervalVector exact = multiply(Eigen::MatrixXd(M.transpose()), detail::iv(C.row(i).transpose()));
    Interval err(0.0);
    for (int j = 0; j < n; ++j) {
      const Interval diff = exact[j] - Interval(dirs[i][j]);
      err += Interval(std::max(std::abs(diff.lower()), std::abs(diff.upper())));
    }
    b[i] = (Interval(s[i]) + err * Interval(xmag)).upper();
  }
  return HPolytope(C, b);
}

std::string to_string(const HPolytope& P) {
  std::ostringstream os;
  os.precision(17);
  os << "HPolytope(dim=" << P.dimension() << ", rows=[";
  for (int i = 0; i < P.num_constraints(); ++i) {
    os << (i ? ", " : "") << "[";
    for (int j = 0; j < P.dimension(); ++j) os << (j ? ", " : "") << P.A()(i, j);
    os << " | " << P.b()[i] << "]";
  }
  os << "])";
  return os.str();
}

}  // namespace sets
