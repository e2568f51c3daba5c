#include "sets/fps/feasible_parameter_set.hpp"

#include <Eigen/LU>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include "sets/core/error.hpp"
#include "sets/numeric/dense_lp.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/numeric/lp_certificate.hpp"
#include "numeric/certified_extent.hpp"
#include "numeric/verified_linear_algebra.hpp"

namespace sets {

// ---------------------------------------------------------------- the set

FeasibleParameterSet::FeasibleParameterSet(int dimension) : p_(dimension) {
  if (dimension <= 0) throw InputError("FeasibleParameterSet: dimension must be positive");
  Phi_.resize(0, dimension);
  col_largest_.setZero(dimension);
  col_smallest_.setConstant(dimension, inf);
}

void FeasibleParameterSet::track_magnitudes(Eigen::Index t) {
  for (Eigen::Index j = 0; j < p_; ++j)
    for (double a : {std::abs(Phi_(t, j).lower()), std::abs(Phi_(t, j).upper())}) {
      col_largest_[j] = std::max(col_largest_[j], a);
      if (a > 0) col_smallest_[j] = std::min(col_smallest_[j], a);
    }
}

Eigen::VectorXd FeasibleParameterSet::column_scales() const {
  Eigen::VectorXd d = Eigen::VectorXd::Ones(p_);
  for (int j = 0; j < p_; ++j) {
    if (!(col_largest_[j] > 0)) continue;
    const int k = -std::ilogb(col_largest_[j]);  // d_j = 2^k
    // a 2^k is exact while its exponent stays in the normal range; the largest entry lands in
    // [1, 2), so only the smallest can fall out (below it).
    if (k <= std::numeric_limits<double>::max_exponent - 1 &&
        std::ilogb(col_smallest_[j]) + k >= std::numeric_limits<double>::min_exponent - 1)
      d[j] = std::ldexp(1.0, k);
  }
  return d;
}

FeasibleParameterSet FeasibleParameterSet::from_data(const Eigen::Ref<const Eigen::MatrixXd>& Phi,
                                                     const Eigen::Ref<const Eigen::VectorXd>& y,
                                                     const Eigen::Ref<const Eigen::VectorXd>& delta) {
  if (Phi.rows() != y.size() || delta.size() != y.size())
    throw InputError("FeasibleParameterSet: " + std::to_string(Phi.rows()) + " regressor rows, " +
                     std::to_string(y.size()) + " outputs and " + std::to_string(delta.size()) +
                     " error bounds: the lengths must match");
  if (Phi.rows() < Phi.cols())
    throw InputError("FeasibleParameterSet: " + std::to_string(Phi.rows()) + " samples for " +
                     std::to_string(Phi.cols()) + " parameters: need at least as many samples as parameters");
  FeasibleParameterSet f(static_cast<int>(Phi.cols()));
  f.Phi_.resize(Phi.rows(), Phi.cols());
  f.Y_.resize(Phi.rows());
  f.n_ = Phi.rows();
  for (Eigen::Index t = 0; t < Phi.rows(); ++t) {
    for (Eigen::Index j = 0; j < Phi.cols(); ++j) {
      if (!std::isfinite(Phi(t, j)))
        throw InputError("FeasibleParameterSet: sample " + std::to_string(t) + ", regressor entry " +
                         std::to_string(j) + " is not finite");
      f.Phi_(t, j) = Interval(Phi(t, j));
    }
    if (!std::isfinite(y[t]))
      throw InputError("FeasibleParameterSet: sample " + std::to_string(t) + ", output y is not finite");
    if (!(delta[t] >= 0) || !std::isfinite(delta[t]))
      throw InputError("FeasibleParameterSet: sample " + std::to_string(t) +
                       ", error bound delta must be finite and >= 0 (got " + std::to_string(delta[t]) + ")");
    f.Y_[t] = interval_around(y[t], delta[t]);
    f.track_magnitudes(t);
  }
  return f;
}

FeasibleParameterSet FeasibleParameterSet::from_interval_data(const IntervalMatrix& Phi,
                                                              const IntervalVector& Y) {
  if (Phi.rows() != Y.size())
    throw InputError("FeasibleParameterSet: " + std::to_string(Phi.rows()) + " regressor rows but " +
                     std::to_string(Y.size()) + " outputs: the lengths must match");
  if (Phi.rows() < Phi.cols())
    throw InputError("FeasibleParameterSet: " + std::to_string(Phi.rows()) + " samples for " +
                     std::to_string(Phi.cols()) + " parameters: need at least as many samples as parameters");
  FeasibleParameterSet f(static_cast<int>(Phi.cols()));
  // Same checks as add_strip and the magnitudes track_magnitudes keeps, in one pass column by
  // column (Phi is column-major) with local accumulators; only when an entry is not finite is Phi
  // scanned again row by row, to name the first such sample.
  bool finite = true, eiv = false;
  for (Eigen::Index j = 0; j < Phi.cols(); ++j) {
    double largest = f.col_largest_[j], smallest = f.col_smallest_[j];
    for (Eigen::Index t = 0; t < Phi.rows(); ++t) {
      const double lo = Phi(t, j).lower(), hi = Phi(t, j).upper();
      finite = finite && std::isfinite(lo) && std::isfinite(hi);
      eiv = eiv || lo != hi;
      const double a = std::abs(lo), b = std::abs(hi);
      largest = std::max(largest, std::max(a, b));
      if (a > 0) smallest = std::min(smallest, a);
      if (b > 0) smallest = std::min(smallest, b);
    }
    f.col_largest_[j] = largest;
    f.col_smallest_[j] = smallest;
  }
  for (Eigen::Index t = 0; t < Y.size(); ++t) finite = finite && std::isfinite(Y[t].lower()) && std::isfinite(Y[t].upper());
  for (Eigen::Index t = 0; t < Phi.rows() && !finite; ++t) {
    const auto where = [t] { return "FeasibleParameterSet: sample " + std::to_string(t); };
    for (Eigen::Index j = 0; j < Phi.cols(); ++j)
      if (!std::isfinite(Phi(t, j).lower()) || !std::isfinite(Phi(t, j).upper()))
        throw InputError(where() + ", regressor entry " + std::to_string(j) + " is not finite");
    if (!std::isfinite(Y[t].lower()) || !std::isfinite(Y[t].upper()))
      throw InputError(where() + ", output bound is not finite");
  }
  f.eiv_ = eiv;
  f.Phi_ = Phi;
  f.Y_ = Y;
  f.n_ = Phi.rows();
  return f;
}

void FeasibleParameterSet::add_strip(const Eigen::Ref<const Eigen::VectorXd>& phi, double y, double delta) {
  const std::string where = "FeasibleParameterSet: sample " + std::to_string(size());
  if (!std::isfinite(y)) throw InputError(where + ", output y is not finite");
  if (!(delta >= 0) || !std::isfinite(delta))
    throw InputError(where + ", error bound delta must be finite and >= 0 (got " + std::to_string(delta) + ")");
  add_strip(to_interval(phi), interval_around(y, delta));
}

void FeasibleParameterSet::add_strip(const IntervalVector& Phi, const Interval& Y) {
  const std::string where = "FeasibleParameterSet: sample " + std::to_string(size());
  if (Phi.size() != p_)
    throw InputError(where + " has " + std::to_string(Phi.size()) + " regressor entries, expected " +
                     std::to_string(p_));
  for (Eigen::Index j = 0; j < Phi.size(); ++j) {
    if (!std::isfinite(Phi[j].lower()) || !std::isfinite(Phi[j].upper()))
      throw InputError(where + ", regressor entry " + std::to_string(j) + " is not finite");
    if (Phi[j].lower() != Phi[j].upper()) eiv_ = true;
  }
  if (!std::isfinite(Y.lower()) || !std::isfinite(Y.upper()))
    throw InputError(where + ", output bound is not finite");
  if (n_ == Phi_.rows()) {  // grow geometrically: a loop of add_strip stays linear in N
    const Eigen::Index capacity = std::max<Eigen::Index>(16, 2 * n_);
    Phi_.conservativeResize(capacity, p_);
    Y_.conservativeResize(capacity);
  }
  Phi_.row(n_) = Phi.transpose();
  Y_[n_] = Y;
  track_magnitudes(n_);
  ++n_;
}

BoolInterval FeasibleParameterSet::contains(const Eigen::Ref<const Eigen::VectorXd>& theta) const {
  if (theta.size() != p_) throw InputError("FeasibleParameterSet::contains: wrong dimension");
  // The range of phi_t^T theta over the regressor box is [lo_t, hi_t], lo_t = sum_j of the
  // smaller of the ends' products with theta_j, hi_t the larger. Enclosures [L_t, L'_t] of lo_t
  // and [U'_t, U_t] of hi_t are summed column by column (Phi_ is column-major; reading it row by
  // row missed the cache on every entry), all in one upward rounding scope: a product or sum
  // rounded up is x * y or x + y, rounded down -((-x) * y) or -((-x) - y). These are the ends
  // Boost's interval operations give (up to the sign of a zero), without their case analysis;
  // which end of Phi_tj gives the smaller product depends only on the sign of theta_j, so it is
  // chosen once per column.
  Eigen::ArrayXd lo_down = Eigen::ArrayXd::Zero(n_), lo_up = lo_down, hi_down = lo_down, hi_up = lo_down;
  {
    RoundingScope upward;
    for (int j = 0; j < p_; ++j) {
      const double th = theta[j];
      const bool pos = th >= 0;
      const Interval* column = Phi_.data() + static_cast<Eigen::Index>(j) * Phi_.rows();
      for (Eigen::Index t = 0; t < n_; ++t) {
        const double small = pos ? column[t].lower() : column[t].upper();  // the end giving the smaller product
        const double large = pos ? column[t].upper() : column[t].lower();
        lo_down[t] = -((-lo_down[t]) + (-small) * th);
        lo_up[t] = lo_up[t] + small * th;
        hi_down[t] = -((-hi_down[t]) + (-large) * th);
        hi_up[t] = hi_up[t] + large * th;
      }
    }
  }
  BoolInterval result = BoolInterval::yes;
  for (Eigen::Index t = 0; t < n_; ++t) {
    if (lo_down[t] > Y_[t].upper() || hi_up[t] < Y_[t].lower()) return BoolInterval::no;
    if (!(lo_up[t] <= Y_[t].upper() && hi_down[t] >= Y_[t].lower())) result = BoolInterval::unknown;
  }
  return result;
}

Eigen::VectorXd FeasibleParameterSet::least_squares() const {
  // A starting point, no guarantee: plain midpoints (the interval midpoint() switches the
  // rounding mode per entry; that was 40 % of a Cerone-Regruto PUI with the dense simplex).
  const auto mid = [](const Interval& v) { return 0.5 * v.lower() + 0.5 * v.upper(); };
  const Eigen::MatrixXd A = regressors().unaryExpr(mid);
  const Eigen::VectorXd y = outputs().unaryExpr(mid);
  return A.colPivHouseholderQr().solve(y);
}

namespace {

// Row coefficients of sample t in orthant s: the minimising (lower) and maximising (upper) ends.
void orthant_rows(const Eigen::Ref<const IntervalMatrix>& Phi, Eigen::Index t, const Orthant& s, Eigen::VectorXd& lo_row,
                  Eigen::VectorXd& hi_row) {
  const Eigen::Index p = Phi.cols();
  lo_row.resize(p);
  hi_row.resize(p);
  for (Eigen::Index j = 0; j < p; ++j) {
    const bool pos = s.empty() || s[static_cast<std::size_t>(j)] > 0;
    lo_row[j] = pos ? Phi(t, j).lower() : Phi(t, j).upper();
    hi_row[j] = pos ? Phi(t, j).upper() : Phi(t, j).lower();
  }
}

}  // namespace

HPolytope FeasibleParameterSet::orthant_polytope(const Orthant& s) const {
  if (!s.empty() && static_cast<int>(s.size()) != p_)
    throw InputError("orthant_polytope: orthant has the wrong dimension");
  if (s.empty() && eiv_)
    throw InputError("orthant_polytope: interval regressors need an orthant");
  const Eigen::Index N = n_;
  const Eigen::Index extra = s.empty() ? 0 : p_;
  Eigen::MatrixXd A(2 * N + extra, p_);
  Eigen::VectorXd b(2 * N + extra);
  Eigen::VectorXd lo_row, hi_row;
  for (Eigen::Index t = 0; t < N; ++t) {
    orthant_rows(Phi_, t, s, lo_row, hi_row);
    A.row(2 * t) = lo_row.transpose();
    b[2 * t] = Y_[t].upper();
    A.row(2 * t + 1) = -hi_row.transpose();
    b[2 * t + 1] = -Y_[t].lower();
  }
  for (Eigen::Index j = 0; j < extra; ++j) {
    A.row(2 * N + j).setZero();
    A(2 * N + j, j) = -s[static_cast<std::size_t>(j)];
    b[2 * N + j] = 0;
  }
  return HPolytope(std::move(A), std::move(b));
}

// ---------------------------------------------------------------- PUIs

namespace {

// The LP of one orthant piece. With many samples only a working set of them is in the LP
// (constraint generation): after each solve the optimum is checked against every sample and the
// most violated ones are added, until none is violated. A working set is a relaxation, so every
// emptiness verdict and every safe bound it gives holds for the full set; and once no sample is
// violated, the relaxation's optimum is the full optimum (tightness is not lost).
class OrthantLp {
 public:
  /// `scale`: the LP is in z = theta ./ scale (column j of every row times scale_j, exact: see
  /// FeasibleParameterSet::column_scales), so every column has entries of size ~1.
  OrthantLp(const FeasibleParameterSet& fps, const Eigen::VectorXd& scale, const Orthant& s, const PuiOptions& options)
      : lp_(fps.dimension()),
        in_(static_cast<std::size_t>(fps.size()), 0),
        warm_(options.warm_start),
        point_rows_(!fps.has_interval_regressors()) {
    if (options.solver == PuiLpSolver::dense) dense_.emplace(fps.dimension());
    const bool working_set = options.working_set;
    const int p = fps.dimension(), N = fps.size();
    for (int j = 0; j < p; ++j) {
      if (s.empty() || s[static_cast<std::size_t>(j)] == 0) continue;  // 0: a free parameter
      if (s[static_cast<std::size_t>(j)] > 0)
        lp_.set_variable_bounds(j, 0, inf);
      else
        lp_.set_variable_bounds(j, -inf, 0);
    }
    // Column by column (the regressors are stored by column): the end of each entry that
    // minimises (lo_) and maximises (hi_) phi_j theta_j in the orthant; one matrix for point
    // regressors, where both are the same.
    const auto Phi = fps.regressors();
    lo_.resize(N, p);
    if (!point_rows_) hi_.resize(N, p);
    for (int j = 0; j < p; ++j) {
      const bool pos = s.empty() || s[static_cast<std::size_t>(j)] > 0;
      const double f = scale[j];
      for (int t = 0; t < N; ++t) {
        const double a = Phi(t, j).lower() * f, b = Phi(t, j).upper() * f;
        lo_(t, j) = pos ? a : b;
        if (!point_rows_) hi_(t, j) = pos ? b : a;
      }
    }
    ylo_.resize(N);
    yhi_.resize(N);
    tol_.resize(N);
    for (int t = 0; t < N; ++t) {
      ylo_[t] = fps.outputs()[t].lower();
      yhi_[t] = fps.outputs()[t].upper();
      tol_[t] = 1e-9 * (1 + std::abs(yhi_[t]) + std::abs(ylo_[t]));
    }
    const int start = working_set ? std::min(N, 10 * p + 10) : N;
    if (start == N) {
      for (int t = 0; t < N; ++t) add_sample(t);
    } else {
      // An evenly spread starting set; the rest come in as they are violated.
      for (int k = 0; k < start; ++k) add_sample(static_cast<int>(static_cast<long>(k) * N / start));
    }
  }

  LinearProgram& lp() { return lp_; }
  bool complete() const { return added_ == static_cast<int>(in_.size()); }
  int fallbacks() const { return fallbacks_; }

  /// Every sample's rows (as add_sample would add them), for exact checks on the full set.
  LpRows all_rows() const {
    LpRows r;
    const auto row = [](const Eigen::VectorXd& a) {
      std::vector<std::pair<int, double>> e;
      for (Eigen::Index j = 0; j < a.size(); ++j)
        if (a[j] != 0) e.emplace_back(static_cast<int>(j), a[j]);
      return e;
    };
    for (Eigen::Index t = 0; t < lo_.rows(); ++t) {
      const Eigen::VectorXd lo_row = lo_.row(t).transpose();
      if (point_row(t)) {
        r.entries.push_back(row(lo_row));
        r.lo.push_back(ylo_[t]);
        r.hi.push_back(yhi_[t]);
      } else {
        r.entries.push_back(row(lo_row));
        r.lo.push_back(-inf);
        r.hi.push_back(yhi_[t]);
        r.entries.push_back(row(hi_.row(t).transpose()));
        r.lo.push_back(ylo_[t]);
        r.hi.push_back(inf);
      }
    }
    return r;
  }

  /// Solves the current objective over the full set: re-solves after adding violated samples.
  LpSolution solve(int& lps) {
    for (;;) {
      LpSolution sol = solve_working_set();
      ++lps;
      if (sol.status == LpStatus::infeasible || complete()) return sol;
      if (sol.status == LpStatus::unbounded) {
        // The relaxation may be unbounded where the full set is not: take every sample.
        for (int t = 0; t < static_cast<int>(in_.size()); ++t)
          if (!in_[static_cast<std::size_t>(t)]) add_sample(t);
        continue;
      }
      if (add_violated(sol.x) == 0) return sol;
    }
  }

 private:
  // The working set's LP with the objective and bounds the caller set on lp_. The dense solver's
  // answer is used only when optimal (its multipliers are then certified like GLPK's); GLPK
  // decides everything else: emptiness, unboundedness, and the LPs the dense solver gives up on.
  LpSolution solve_working_set() {
    if (dense_) {
      dense_->set_objective(lp_.objective(), lp_.sense());
      for (int j = 0; j < lp_.num_variables(); ++j)
        dense_->set_variable_bounds(j, lp_.variable_lower(j), lp_.variable_upper(j));
      if (!warm_) dense_->reset_basis();
      std::optional<LpSolution> sol = dense_->solve();
      if (sol && sol->status == LpStatus::optimal) return std::move(*sol);
      if (!sol) ++fallbacks_;
    }
    if (!warm_) lp_.reset_basis();
    return lp_.solve();
  }

  // Both solvers hold the same rows in the same order (the multipliers index lp_'s rows).
  void add_row(const Eigen::VectorXd& a, double lo, double hi) {
    lp_.add_row(a, lo, hi);
    if (dense_) dense_->add_row(a, lo, hi);
  }

  bool point_row(Eigen::Index t) const { return point_rows_ || lo_.row(t) == hi_.row(t); }

  void add_sample(int t) {
    in_[static_cast<std::size_t>(t)] = 1;
    ++added_;
    const Eigen::VectorXd lo_row = lo_.row(t).transpose();
    if (point_row(t)) {
      add_row(lo_row, ylo_[t], yhi_[t]);
    } else {
      add_row(lo_row, -inf, yhi_[t]);
      add_row(hi_.row(t).transpose(), ylo_[t], inf);
    }
  }

  // Adds the samples the point x violates most; returns how many were added. One N x p product
  // for point regressors, two for interval ones.
  int add_violated(const Eigen::VectorXd& x) {
    a_.noalias() = lo_ * x;
    if (!point_rows_) b_.noalias() = hi_ * x;
    const Eigen::VectorXd& b = point_rows_ ? a_ : b_;
    std::vector<std::pair<double, int>> violated;
    for (Eigen::Index t = 0; t < a_.size(); ++t) {
      const double v = std::max(a_[t] - yhi_[t], ylo_[t] - b[t]);
      if (v > tol_[t] && !in_[static_cast<std::size_t>(t)]) violated.emplace_back(v, static_cast<int>(t));
    }
    const std::size_t k = std::min<std::size_t>(violated.size(), 60 + 4 * static_cast<std::size_t>(x.size()));
    std::partial_sort(violated.begin(), violated.begin() + static_cast<std::ptrdiff_t>(k), violated.end(),
                      [](const auto& u, const auto& v) { return u.first > v.first; });
    for (std::size_t i = 0; i < k; ++i) add_sample(violated[i].second);
    return static_cast<int>(k);
  }

  LinearProgram lp_;
  std::optional<DenseLp> dense_;
  std::vector<char> in_;
  bool warm_;
  int added_ = 0;
  int fallbacks_ = 0;
  bool point_rows_;          // no interval regressors: hi_ is not built (it would equal lo_)
  Eigen::MatrixXd lo_, hi_;  // orthant rows of every sample (scaled)
  Eigen::VectorXd ylo_, yhi_, tol_;
  Eigen::VectorXd a_, b_;    // lo_ x and hi_ x of the last violation check
};

struct OrthantOutcome {
  OrthantStatus status = OrthantStatus::unknown;
  IntervalVector box;
  Eigen::VectorXd float_lo, float_hi;  // floating-point LP ends (for the Remark-2 zero test)
  Eigen::MatrixXd lower_points, upper_points;
  std::vector<double> maxima;          // bounds on max d^T theta over this orthant piece
  bool certified = false;
  bool witness = false;                // a point of the piece proven to satisfy every sample
  int lps = 0;
  int fallbacks = 0;                   // LPs the dense solver handed to GLPK
};

// The orthant itself as a box: an outer bound of whatever part of the set lies in it.
IntervalVector orthant_box(const Orthant& s, int p) {
  IntervalVector box(p);
  for (int j = 0; j < p; ++j) {
    const int sign = s.empty() ? 0 : s[static_cast<std::size_t>(j)];
    box[j] = sign > 0 ? Interval(0.0, inf) : sign < 0 ? Interval(-inf, 0.0) : Interval(-inf, inf);
  }
  return box;
}

// The centre of a large ball inside the orthant piece (floating-point LP, a search aid only: the
// caller proves membership). The radius is capped so that an unbounded piece still gives a point.
std::optional<Eigen::VectorXd> inscribed_centre(const FeasibleParameterSet& fps, const Orthant& s) {
  const HPolytope P = fps.orthant_polytope(s);
  const int n = P.dimension();
  LinearProgram lp(n);
  const int r = lp.add_variables(1, 0.0, 1.0);
  Eigen::VectorXd row(n + 1);
  for (int i = 0; i < P.num_constraints(); ++i) {
    row << P.A().row(i).transpose(), P.A().row(i).norm();
    lp.add_row(row, -inf, P.b()[i]);
  }
  lp.set_objective_coordinate(r, Sense::maximize);
  try {
    const LpSolution sol = lp.solve();
    if (sol.status == LpStatus::optimal && sol.x[r] > 0) return Eigen::VectorXd(sol.x.head(n));
  } catch (const NumericalError&) {
  }
  return std::nullopt;
}

// A rigorous box around a set of exact-regressor samples from p of them: with A the regressor
// rows of samples S (A invertible) and Y_S their output intervals, every theta of the set has
// A theta in Y_S, so theta = A^{-1} y for some y in Y_S. With a verified approximate inverse X
// (||A^{-1} - X||_2 <= dev), theta_l lies in (X Y_S)_l +- dev ||Y_S||_2. Finite whenever such
// rows exist, i.e. whenever the set is bounded; loose (about cond(A) times the noise bound),
// but a true bound, where the LP solver may call a bounded set unbounded (near-collinear
// regressors: the distinguishing entries fall under its pivot tolerance). S: the rows a
// column-pivoted QR of Phi^T picks first (the best-conditioned choice it sees).
std::optional<IntervalVector> strip_box(const FeasibleParameterSet& fps) {
  const int p = fps.dimension();
  if (fps.has_interval_regressors() || fps.size() < p) return std::nullopt;
  const Eigen::MatrixXd Phi = lower(IntervalMatrix(fps.regressors()));
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Phi.transpose());
  if (qr.rank() < p) return std::nullopt;
  Eigen::MatrixXd A(p, p);
  IntervalVector Y(p);
  for (int k = 0; k < p; ++k) {
    const Eigen::Index t = qr.colsPermutation().indices()[k];
    A.row(k) = Phi.row(t);
    Y[k] = fps.outputs()[t];
  }
  const Eigen::MatrixXd X = A.fullPivLu().inverse();
  if (!X.allFinite()) return std::nullopt;
  const std::optional<double> dev = detail::inverse_deviation_bound(A, X);
  if (!dev) return std::nullopt;
  const double e = (Interval(*dev) * Interval(detail::norm_upper(Y))).upper();
  IntervalVector box = multiply(X, Y);
  for (int l = 0; l < p; ++l) box[l] += Interval(-e, e);
  if (!lower(box).allFinite() || !upper(box).allFinite()) return std::nullopt;
  return box;
}

// strip_box in the scaled coordinates z = theta ./ scale (outward).
std::optional<IntervalVector> scaled_strip_box(const FeasibleParameterSet& fps, const Eigen::VectorXd& scale) {
  std::optional<IntervalVector> box = strip_box(fps);
  if (box)
    for (Eigen::Index j = 0; j < box->size(); ++j) (*box)[j] /= Interval(scale[j]);
  return box;
}

// A rigorous box around a set with interval regressors from p of its samples: every theta of
// the set has A' theta = y for some A' in the samples' interval rows A and y in their output
// intervals Y_S, so theta lies in the solution set of the interval system A theta = Y_S. With
// R ~ mid(A)^{-1}, x0 = R mid(Y_S), C = I - R A and Z = R (Y_S - A x0) (interval arithmetic):
// if every row sum of |C| is <= c < 1, each A' is invertible and x = A'^{-1} y satisfies
// x - x0 = R (y - A' x0) + (I - R A')(x - x0), so ||x - x0||_inf <= ||Z||_inf / (1 - c) = d and
// |x - x0| <= |Z| + |C| 1 d componentwise. Loose (about cond(A) times noise plus regressor
// widths) but a proof: an orthant it misses holds no part of the set. S: as in strip_box.
std::optional<IntervalVector> interval_system_box(const FeasibleParameterSet& fps) {
  const int p = fps.dimension();
  if (fps.size() < p) return std::nullopt;
  const IntervalMatrix Phi = fps.regressors();
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(midpoint(Phi).transpose());
  if (qr.rank() < p) return std::nullopt;
  IntervalMatrix A(p, p);
  IntervalVector Y(p);
  for (int k = 0; k < p; ++k) {
    const Eigen::Index t = qr.colsPermutation().indices()[k];
    A.row(k) = Phi.row(t);
    Y[k] = fps.outputs()[t];
  }
  const Eigen::MatrixXd R = midpoint(A).fullPivLu().inverse();
  if (!R.allFinite()) return std::nullopt;
  const Eigen::VectorXd x0 = R * midpoint(Y);
  if (!x0.allFinite()) return std::nullopt;
  const IntervalVector Z = multiply(R, IntervalVector(Y - multiply(A, to_interval(x0))));
  const IntervalMatrix C = IntervalMatrix(IntervalMatrix::Identity(p, p)) - detail::multiply(to_interval(R), A);
  const auto mag = [](const Interval& v) { return Interval(std::max(std::abs(v.lower()), std::abs(v.upper()))); };
  IntervalVector row_sum(p);  // |C| 1, rounded up
  Interval c(0.0), z(0.0);
  for (int i = 0; i < p; ++i) {
    row_sum[i] = Interval(0.0);
    for (int j = 0; j < p; ++j) row_sum[i] += mag(C(i, j));
    c = Interval(std::max(c.upper(), row_sum[i].upper()));
    z = Interval(std::max(z.upper(), mag(Z[i]).upper()));
  }
  if (!(c.upper() < 1)) return std::nullopt;
  const Interval d = z / (Interval(1.0) - c);
  IntervalVector box(p);
  for (int l = 0; l < p; ++l) {
    const double r = (mag(Z[l]) + row_sum[l] * Interval(d.upper())).upper();
    box[l] = Interval(x0[l]) + Interval(-r, r);
  }
  if (!lower(box).allFinite() || !upper(box).allFinite()) return std::nullopt;
  return box;
}

// True when the box proves that no point of orthant s lies in it.
bool box_misses_orthant(const IntervalVector& box, const Orthant& s) {
  for (std::size_t j = 0; j < s.size(); ++j)
    if ((s[j] > 0 && box[static_cast<Eigen::Index>(j)].upper() < 0) ||
        (s[j] < 0 && box[static_cast<Eigen::Index>(j)].lower() > 0))
      return true;
  return false;
}

// The orthants that split the same parameters as `start` (nonzero signs) and that `box`, when
// given, does not prove empty; nullopt when they are more than 2^16.
std::optional<std::vector<Orthant>> orthants_to_search(const Orthant& start, const std::optional<IntervalVector>& box) {
  std::vector<std::size_t> both;  // parameters whose sign the box leaves open
  Orthant base = start;
  for (std::size_t j = 0; j < start.size(); ++j) {
    if (start[j] == 0) continue;
    const Interval b = box ? (*box)[static_cast<Eigen::Index>(j)] : Interval(-inf, inf);
    if (b.lower() > 0) base[j] = 1;
    else if (b.upper() < 0) base[j] = -1;
    else both.push_back(j);
  }
  if (both.size() > 16) return std::nullopt;
  std::vector<Orthant> out;
  for (unsigned long mask = 0; mask < (1ul << both.size()); ++mask) {
    Orthant s = base;
    for (std::size_t k = 0; k < both.size(); ++k) s[both[k]] = (mask >> k) & 1 ? -1 : 1;
    out.push_back(std::move(s));
  }
  return out;
}

// Recovery for ends the LPs left infinite (GLPK's "unbounded" on a set that strip_box proves
// bounded, or an extent that could not be certified): per end, the tighter of the proven box
// and a safe bound of the LP over it. The box is a true bound of the set, so any multipliers
// give a valid bound over it (no artificial faces, no all-or-nothing certification); an LP that
// fails leaves the box's end. Directions get the box's support where they had none.
void bound_infinite_ends(const FeasibleParameterSet& fps, const Eigen::VectorXd& scale, const Orthant& s,
                         const PuiOptions& options, const std::vector<Eigen::VectorXd>& directions, detail::Extent& e,
                         int& lps) {
  if (lower(make_box(e.lo, e.hi)).allFinite() && upper(make_box(e.lo, e.hi)).allFinite()) return;
  const std::optional<IntervalVector> box = scaled_strip_box(fps, scale);
  if (!box) return;
  const int p = fps.dimension();
  OrthantLp o(fps, scale, s, options);
  for (int j = 0; j < p; ++j) {
    const double lo = std::max((*box)[j].lower(), o.lp().variable_lower(j));
    const double hi = std::min((*box)[j].upper(), o.lp().variable_upper(j));
    if (!(lo <= hi)) return;  // the set misses this orthant; leave it to the LPs' verdict
    o.lp().set_variable_bounds(j, lo, hi);
  }
  for (int l = 0; l < p; ++l) {
    for (Sense sense : {Sense::minimize, Sense::maximize}) {
      const bool lower_end = sense == Sense::minimize;
      double& end = lower_end ? e.lo[l] : e.hi[l];
      if (std::isfinite(end)) continue;  // certified already
      end = lower_end ? o.lp().variable_lower(l) : o.lp().variable_upper(l);
      o.lp().set_objective_coordinate(l, sense);
      try {
        const LpSolution sol = o.solve(lps);
        const double b = o.lp().safe_bound(sol);  // +-inf unless optimal
        end = lower_end ? std::max(end, b) : std::min(end, b);
      } catch (const NumericalError&) {
      }
    }
  }
  for (std::size_t k = 0; k < directions.size() && k < e.maxima.size(); ++k)
    if (e.maxima[k] == inf) e.maxima[k] = detail::dot(to_interval(directions[k]), *box).upper();
  e.certified = true;  // every end is now a safe bound or an end of the proven box
}

// One orthant piece, in the scaled coordinates z = theta ./ scale (boxes, points and maxima; the
// directions are already scaled).
OrthantOutcome solve_orthant(const FeasibleParameterSet& fps, const Eigen::VectorXd& scale, const Orthant& s,
                             const PuiOptions& options, const std::vector<Eigen::VectorXd>& directions) {
  OrthantLp o(fps, scale, s, options);
  // The orthant's sign constraints are variable bounds of the LP, so ends on a coordinate face
  // are exact and need no artificial face there.
  detail::Extent e =
      detail::certified_extent(o.lp(), [&](int& lps) { return o.solve(lps); }, directions, options.safe);
  int lps = e.lps;
  if (options.safe && e.status == detail::ExtentStatus::feasible) bound_infinite_ends(fps, scale, s, options, directions, e, lps);
  OrthantOutcome out;
  out.lps = lps;
  out.fallbacks = o.fallbacks();
  out.status = e.status == detail::ExtentStatus::feasible ? OrthantStatus::feasible
               : e.status == detail::ExtentStatus::empty  ? OrthantStatus::empty
                                                          : OrthantStatus::unknown;
  if (out.status == OrthantStatus::unknown && options.safe) {
    // Undecided, but a proven box still bounds whatever of the set there is.
    if (const std::optional<IntervalVector> box = scaled_strip_box(fps, scale)) out.box = *box;
  }
  if (out.status != OrthantStatus::feasible) return out;
  out.float_lo = e.float_lo;
  out.float_hi = e.float_hi;
  out.lower_points = e.lower_points;
  out.upper_points = e.upper_points;
  out.maxima = e.maxima;
  out.certified = e.certified;
  out.box = make_box(e.lo, e.hi);
  // A witness of consistency: the mean of the 2p extreme points lies in the (convex) orthant
  // piece if they do, and is usually interior, so outward rounding can prove it. (A flat set, e.g. delta = 0, has no interior: then no witness, and the verdict is
  // unknown unless another orthant has one.)
  // The centre of the orthant's PUI box is a second candidate (inside when the piece is not
  // too skewed).
  const Eigen::VectorXd mean = 0.5 * (e.lower_points.rowwise().mean() + e.upper_points.rowwise().mean());
  const Eigen::VectorXd centre = 0.5 * (e.float_lo + e.float_hi);
  // theta = D z need not be exactly D times the LP's point: any point proven inside will do.
  for (const Eigen::VectorXd& x : {mean, centre})
    if (!out.witness && x.allFinite()) out.witness = fps.contains(scale.cwiseProduct(x)) == BoolInterval::yes;
  if (!out.witness) {  // skewed piece, or ends not computed (support only): its inscribed ball's centre
    const std::optional<Eigen::VectorXd> x = inscribed_centre(fps, s);  // unscaled
    out.witness = x && fps.contains(*x) == BoolInterval::yes;
  }
  if (!out.witness) {
    // Thin or flat pieces: the vertex an LP ended on, solved exactly from its active samples,
    // is a point of the piece when the LP's active set is right.
    const LpRows rows = o.all_rows();
    Eigen::VectorXd col_lo(fps.dimension()), col_hi(fps.dimension());
    for (int j = 0; j < fps.dimension(); ++j) {
      col_lo[j] = s.empty() || s[static_cast<std::size_t>(j)] > 0 ? (s.empty() ? -inf : 0.0) : -inf;
      col_hi[j] = s.empty() || s[static_cast<std::size_t>(j)] < 0 ? (s.empty() ? inf : 0.0) : inf;
    }
    for (const Eigen::VectorXd& x : {Eigen::VectorXd(e.lower_points.col(0)), Eigen::VectorXd(e.upper_points.col(0))})
      if (!out.witness && x.allFinite()) out.witness = verify_feasible_point(rows, col_lo, col_hi, x);
  }
  return out;
}

// The orthant of theta in the parameters whose regressors are intervals somewhere; 0 (free) for
// the others: with point regressors the set is the same polyhedron on both sides of theta_j = 0,
// so splitting there would only repeat LPs (2^k pieces for k such parameters).
Orthant sign_orthant(const FeasibleParameterSet& fps, const Eigen::VectorXd& theta) {
  Orthant s(static_cast<std::size_t>(theta.size()), 0);
  const auto Phi = fps.regressors();
  for (Eigen::Index j = 0; j < theta.size(); ++j)
    for (Eigen::Index t = 0; t < Phi.rows(); ++t)
      if (Phi(t, j).lower() != Phi(t, j).upper()) {
        s[static_cast<std::size_t>(j)] = theta[j] < 0 ? -1 : 1;
        break;
      }
  return s;
}

}  // namespace

std::vector<Orthant> all_orthants(int p) {
  if (p > 20) throw UnsupportedError("all_orthants: 2^" + std::to_string(p) + " orthants is too many");
  std::vector<Orthant> out;
  for (unsigned long mask = 0; mask < (1ul << p); ++mask) {
    Orthant s(static_cast<std::size_t>(p));
    for (int j = 0; j < p; ++j) s[static_cast<std::size_t>(j)] = (mask >> j) & 1 ? -1 : 1;
    out.push_back(std::move(s));
  }
  return out;
}

namespace {

// PUIs and, from the same LPs, bounds on max d^T theta for each direction (`maxima`): the
// maximum over the orthant pieces that pui() visits. Everything it returns is in the scaled
// coordinates z = theta ./ scale, and so are `directions` (see explore()).
// The orthants' outcomes gathered into one PUI: the hull of their boxes (certified with `safe`),
// the floating-point estimate beside it, the points attaining each end, the support maxima.
class OrthantHull {
 public:
  OrthantHull(int p, const PuiOptions& options, const std::vector<Eigen::VectorXd>& directions,
              std::vector<double>& maxima)
      : p_(p), options_(options), directions_(directions), maxima_(maxima) {
    maxima_.assign(directions.size(), -inf);
    result_.lower_points.setConstant(p, p, std::numeric_limits<double>::quiet_NaN());
    result_.upper_points.setConstant(p, p, std::numeric_limits<double>::quiet_NaN());
  }

  void absorb(const Orthant& s, OrthantOutcome oc) {
    result_.lp_solves += oc.lps;
    result_.lp_fallbacks += oc.fallbacks;
    if (oc.status == OrthantStatus::unknown) {
      // Undecided: never counted as empty. The orthant itself bounds whatever lies in it.
      ++unknown_orthants_;
      if (oc.box.size() != p_) oc.box = orthant_box(s, p_);
      maxima_.assign(directions_.size(), inf);
    }
    result_.orthants.push_back({s, oc.status, oc.box, oc.witness});
    if (oc.status == OrthantStatus::empty) return;
    result_.box = have_box_ ? hull(result_.box, oc.box) : oc.box;
    have_box_ = true;
    const IntervalVector estimate = oc.status == OrthantStatus::feasible
                                        ? make_box(oc.float_lo.cwiseMin(oc.float_hi), oc.float_hi.cwiseMax(oc.float_lo))
                                        : oc.box;
    result_.unreliable_box = have_unreliable_ ? hull(result_.unreliable_box, estimate) : estimate;
    have_unreliable_ = true;
    if (oc.status != OrthantStatus::feasible) return;
    for (std::size_t k = 0; k < directions_.size(); ++k) maxima_[k] = std::max(maxima_[k], oc.maxima[k]);
    all_certified_ = all_certified_ && (oc.certified || !options_.safe);
    for (int l = 0; l < p_; ++l) {
      if (!any_feasible_ || oc.box[l].lower() <= result_.box[l].lower())
        result_.lower_points.col(l) = oc.lower_points.col(l);
      if (!any_feasible_ || oc.box[l].upper() >= result_.box[l].upper())
        result_.upper_points.col(l) = oc.upper_points.col(l);
    }
    any_feasible_ = true;
  }

  bool has_box() const { return have_box_; }
  PuiResult finish(const FeasibleParameterSet& fps, bool searched_everywhere);

 private:
  void decide_consistency(const FeasibleParameterSet& fps, bool searched_everywhere);

  const int p_;
  const PuiOptions& options_;
  const std::vector<Eigen::VectorXd>& directions_;
  std::vector<double>& maxima_;
  PuiResult result_;
  bool any_feasible_ = false;     // some orthant gave floating-point LP points
  bool have_box_ = false;         // some orthant contributed to result_.box
  bool have_unreliable_ = false;
  bool all_certified_ = true;
  int unknown_orthants_ = 0;
};

// A witness proves consistency; only a search of every orthant that found no box proves the
// data falsify the model; anything else is unknown, with the reason.
void OrthantHull::decide_consistency(const FeasibleParameterSet& fps, bool searched_everywhere) {
  const bool any_witness =
      std::any_of(result_.orthants.begin(), result_.orthants.end(), [](const OrthantReport& o) { return o.witness; });
  ConsistencyVerdict& verdict = result_.consistency;
  if (any_witness) {
    verdict.falsified = Falsified::no;
  } else if (!have_box_ && searched_everywhere) {
    verdict.falsified = Falsified::yes;
  } else {
    verdict.falsified = Falsified::unknown;
    if (unknown_orthants_ > 0)
      verdict.reason = std::to_string(unknown_orthants_) + (unknown_orthants_ == 1 ? " orthant" : " orthants") +
                       " of the parameter space had no feasible point in floating point, but no certificate of "
                       "emptiness could be verified";
    else if (!searched_everywhere)
      verdict.reason = "more than 2^16 orthants of the parameter space could hold part of the set and were "
                       "not searched";
    else
      verdict.reason = "the LPs found parameter values, but none could be proven to satisfy every sample "
                       "(the set may be flat, or empty within rounding)";
  }
  if (verdict.falsified != Falsified::no && (unknown_orthants_ > 0 || verdict.falsified == Falsified::yes)) {
    try {
      verdict.conflict = find_conflict(fps);  // a report; the verdict does not rest on it
    } catch (const NumericalError&) {
    }
  }
}

PuiResult OrthantHull::finish(const FeasibleParameterSet& fps, bool searched_everywhere) {
  decide_consistency(fps, searched_everywhere);
  if (result_.consistency.falsified == Falsified::yes) {
    result_.box = IntervalVector();
    result_.guaranteed = true;
    maxima_.assign(directions_.size(), -inf);
    return result_;
  }
  if (!have_box_) result_.box = orthant_box({}, p_);  // nothing searched could bound the rest
  if (!have_unreliable_) result_.unreliable_box = result_.box;
  result_.guaranteed = options_.safe && all_certified_ && searched_everywhere;
  result_.central = midpoint(result_.box);
  return result_;
}

// The orthants across the faces theta_j = 0 that the set may reach from orthant s.
std::vector<Orthant> neighbours_to_visit(const Orthant& s, const OrthantOutcome& oc, const PuiOptions& options,
                                         const std::optional<IntervalVector>& proven) {
  std::vector<Orthant> out;
  if (oc.status == OrthantStatus::empty) return out;
  const auto p = static_cast<int>(s.size());
  double magnitude = 1;  // of the orthant's extents: the zero tolerance is relative to it
  if (oc.status == OrthantStatus::feasible) {
    for (int j = 0; j < p; ++j) {
      if (std::isfinite(oc.float_lo[j])) magnitude = std::max(magnitude, std::abs(oc.float_lo[j]));
      if (std::isfinite(oc.float_hi[j])) magnitude = std::max(magnitude, std::abs(oc.float_hi[j]));
    }
  }
  const double tol = options.zero_tolerance * magnitude;
  for (int j = 0; j < p; ++j) {
    const int sign = s[static_cast<std::size_t>(j)];
    if (sign == 0) continue;  // free: no face at theta_j = 0
    // An uncertified extent is an estimate: its box reaches the face, so may the set.
    // oc.box is the certified box with `safe` (the floating-point extent without).
    const bool off_face = oc.status == OrthantStatus::feasible && (!options.safe || oc.certified) &&
                          (sign > 0 ? oc.box[j].lower() > 0 && oc.float_lo[j] > tol
                                    : oc.box[j].upper() < 0 && oc.float_hi[j] < -tol);
    if (off_face) continue;
    Orthant next = s;
    next[static_cast<std::size_t>(j)] = -next[static_cast<std::size_t>(j)];
    if (proven && box_misses_orthant(*proven, next)) continue;  // proven empty
    out.push_back(next);
  }
  return out;
}

// Remark 2: start in the least-squares orthant; whenever a bound lands on a coordinate face
// (theta_l = 0), the set may continue into the orthant across that face. An undecided orthant
// may touch every face; a decided one stays off a face only if its certified end proves it (with
// `safe`) — the floating-point end is an estimate, its tolerance only adds visits.
// The set need not be connected across faces (one sample with phi in [-1, 1] and phi theta in
// [1, 2] keeps theta away from 0 on both sides), so with `safe` every orthant the search did not
// reach is then searched too, unless a box proven from p samples (interval_system_box) misses it:
// an orthant is skipped only when proven empty. Returns whether every orthant that may hold part
// of the set was visited.
bool search_remark2(const FeasibleParameterSet& fps, const Eigen::VectorXd& scale, const PuiOptions& options,
                    const std::vector<Eigen::VectorXd>& directions, OrthantHull& hull_of) {
  const std::optional<IntervalVector> proven = interval_system_box(fps);
  std::deque<Orthant> queue{sign_orthant(fps, fps.least_squares())};
  const Orthant start = queue.front();
  std::set<Orthant> seen{start};
  while (!queue.empty()) {
    Orthant s = queue.front();
    queue.pop_front();
    const OrthantOutcome oc = solve_orthant(fps, scale, s, options, directions);
    hull_of.absorb(s, oc);
    for (const Orthant& next : neighbours_to_visit(s, oc, options, proven))
      if (seen.insert(next).second) queue.push_back(next);
  }
  // A certified-empty starting orthant says nothing about the others, and with `safe` no orthant
  // is left out unproven: search the rest (the floating-point answer, !safe, keeps the paper's
  // shortcut).
  if (hull_of.has_box() && !options.safe) return true;
  const std::optional<std::vector<Orthant>> rest = orthants_to_search(start, proven);
  if (!rest) return false;
  for (const Orthant& s : *rest)
    if (!seen.count(s)) hull_of.absorb(s, solve_orthant(fps, scale, s, options, directions));
  return true;
}

PuiResult explore_scaled(const FeasibleParameterSet& fps, const Eigen::VectorXd& scale, const PuiOptions& options,
                         const std::vector<Eigen::VectorXd>& directions, std::vector<double>& maxima) {
  const int p = fps.dimension();
  OrthantHull hull_of(p, options, directions, maxima);
  bool searched_everywhere = true;
  if (!fps.has_interval_regressors()) {
    hull_of.absorb({}, solve_orthant(fps, scale, {}, options, directions));
  } else if (options.orthants == OrthantSelection::all) {
    for (const Orthant& s : all_orthants(p)) hull_of.absorb(s, solve_orthant(fps, scale, s, options, directions));
  } else {
    searched_everywhere = search_remark2(fps, scale, options, directions, hull_of);
  }
  return hull_of.finish(fps, searched_everywhere);
}

// Column scaling by powers of 2 (exact): theta_j = d_j z_j with d_j = 2^-e_j, 2^e_j about the
// largest |regressor| of column j, so every column of the LP has entries of size ~1. GLPK's
// tolerances are absolute: on a column with entries ~1e-10 it took pivots for zero and
// reported the set unbounded, and on one with entries ~1e10 its objective's duals fell below
// the reduced-cost tolerance and it stopped at a wrong vertex (PUI intervals of width 0 that
// missed the truth, soundness campaign seeds 752, 4112, 4502, 9087, 9662). The scaled problem
// is the same set exactly: a_tj d_j and the scaled directions' dir_j d_j are exact unless they
// leave the normal range, and then that column keeps d_j = 1. The set keeps its columns'
// magnitudes up to date, so this costs O(p) and nothing is copied: the orthant LPs scale their
// rows as they build them.
Eigen::VectorXd column_scales(const FeasibleParameterSet& fps, const std::vector<Eigen::VectorXd>& directions) {
  Eigen::VectorXd d = fps.column_scales();
  for (Eigen::Index j = 0; j < d.size(); ++j) {
    const int k = std::ilogb(d[j]);  // d_j = 2^k
    for (const auto& dir : directions)  // d^T theta = (D d)^T z
      if (dir[j] != 0 && (std::ilogb(dir[j]) + k < std::numeric_limits<double>::min_exponent - 1 ||
                          std::ilogb(dir[j]) + k > std::numeric_limits<double>::max_exponent - 1))
        d[j] = 1;
  }
  return d;
}

// theta = D z for a box in z (outward: the products are exact unless they overflow or
// underflow, and then interval multiplication rounds outward).
IntervalVector unscale(const IntervalVector& z, const Eigen::VectorXd& d) {
  IntervalVector x(z.size());
  for (Eigen::Index j = 0; j < z.size(); ++j) x[j] = z[j] * Interval(d[j]);
  return x;
}

PuiResult explore(const FeasibleParameterSet& fps, const PuiOptions& options,
                  const std::vector<Eigen::VectorXd>& directions, std::vector<double>& maxima, const char* what) {
  const int p = fps.dimension();
  if (fps.size() < p)
    throw InputError(std::string(what) + ": " + std::to_string(fps.size()) + " samples for " + std::to_string(p) +
                     " parameters: need at least as many samples as parameters");
  for (const auto& d : directions)
    if (d.size() != p)
      throw InputError(std::string(what) + ": a direction has " + std::to_string(d.size()) + " entries, expected " +
                       std::to_string(p));
  const Eigen::VectorXd d = column_scales(fps, directions);
  std::vector<Eigen::VectorXd> scaled_directions;  // d^T theta = (D d)^T z
  for (const auto& dir : directions) scaled_directions.push_back(dir.cwiseProduct(d));
  PuiResult r = explore_scaled(fps, d, options, scaled_directions, maxima);
  if ((d.array() == 1).all()) return r;
  if (r.empty()) return r;
  r.box = unscale(r.box, d);
  r.unreliable_box = unscale(r.unreliable_box, d);
  r.central = midpoint(r.box);
  for (OrthantReport& o : r.orthants)
    if (o.box.size() == p) o.box = unscale(o.box, d);
  r.lower_points = d.asDiagonal() * r.lower_points;
  r.upper_points = d.asDiagonal() * r.upper_points;
  return r;
}

}  // namespace

PuiResult pui(const FeasibleParameterSet& fps, const PuiOptions& options) {
  std::vector<double> none;
  return explore(fps, options, {}, none, "pui");
}

FpsSupport support(const FeasibleParameterSet& fps, const std::vector<Eigen::VectorXd>& directions,
                   const PuiOptions& options) {
  FpsSupport out;
  PuiResult r = explore(fps, options, directions, out.maxima, "support");
  out.consistency = std::move(r.consistency);
  out.guaranteed = r.guaranteed;
  out.box = std::move(r.box);
  out.lp_solves = r.lp_solves;
  return out;
}

ConsistencyVerdict check_consistency(const FeasibleParameterSet& fps, const PuiOptions& options) {
  PuiOptions o = options;
  o.safe = false;  // the verdict does not need certified bounds
  return pui(fps, o).consistency;
}

Falsification find_conflict(const FeasibleParameterSet& fps) {
  // min t  s.t.  Y_lo - t <= phi_c^T theta <= Y_hi + t  (central regressors): the rows that
  // carry the optimal multipliers are a set of samples that cannot hold together.
  const int p = fps.dimension();
  const Eigen::MatrixXd A = midpoint(IntervalMatrix(fps.regressors()));
  LinearProgram lp(p + 1);
  lp.set_variable_bounds(p, 0, inf);
  Eigen::VectorXd row(p + 1);
  for (int t = 0; t < fps.size(); ++t) {
    row.head(p) = A.row(t).transpose();
    row[p] = 1;
    lp.add_row(row, fps.outputs()[t].lower(), inf);
    row[p] = -1;
    lp.add_row(row, -inf, fps.outputs()[t].upper());
  }
  Eigen::VectorXd c = Eigen::VectorXd::Zero(p + 1);
  c[p] = 1;
  lp.set_objective(c, Sense::minimize);
  const LpSolution sol = lp.solve();
  Falsification f;
  if (sol.status != LpStatus::optimal || sol.objective <= 0) return f;
  const Eigen::VectorXd theta = sol.x.head(p);
  std::vector<std::pair<double, int>> support;
  for (int t = 0; t < fps.size(); ++t) {
    const double v = A.row(t).dot(theta);
    const double viol = std::max({fps.outputs()[t].lower() - v, v - fps.outputs()[t].upper(), 0.0});
    const bool active = std::abs(sol.row_dual[2 * t]) > 1e-12 || std::abs(sol.row_dual[2 * t + 1]) > 1e-12;
    if (active) support.emplace_back(viol, t);
  }
  if (support.empty()) {
    for (int t = 0; t < fps.size(); ++t) {
      const double v = A.row(t).dot(theta);
      support.emplace_back(std::max({fps.outputs()[t].lower() - v, v - fps.outputs()[t].upper(), 0.0}), t);
    }
    std::sort(support.rbegin(), support.rend());
    support.resize(std::min<std::size_t>(support.size(), static_cast<std::size_t>(p + 1)));
  }
  std::sort(support.rbegin(), support.rend());
  for (const auto& [v, t] : support) {
    f.samples.push_back(t);
    f.violation.push_back(v);
  }
  return f;
}

const char* to_string(OrthantStatus s) {
  switch (s) {
    case OrthantStatus::feasible: return "feasible";
    case OrthantStatus::empty: return "empty";
    default: return "unknown";
  }
}

}  // namespace sets
