#include "sets/methods/ss_uncertainty/state_enclosure.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "sets/core/error.hpp"
#include "numeric/verified_linear_algebra.hpp"

namespace sets {
namespace {

using I = UnprotectedInterval;  // only inside a RoundingScope

constexpr double unit_roundoff = std::numeric_limits<double>::epsilon() / 2;

// gamma_n = n u / (1 - n u): |fl(x^T y) - x^T y| <= gamma_n |x|^T |y| for a product of length n
// summed in any order, fused multiply-adds included (Higham, Accuracy and Stability, 3.1). The
// same bound holds entrywise for a matrix product computed in round-to-nearest. Rounded up.
double gamma_n(Eigen::Index n) {
  const Interval nu = Interval(static_cast<double>(n)) * Interval(unit_roundoff);
  return (nu / (Interval(1.0) - nu)).upper();
}

// Rigorous facts about the Gram matrix R = Z^T Z of step 1, from a floating-point Cholesky
// factor L of fl(Z^T Z) and X ~ L^{-1}:
//   ||L^{-1} a|| <= ||fl(X a)|| + kappa_a ||a||     and     a^T R^{-1} a <= kappa_q ||L^{-1} a||^2
// for every a (an upper bound on the quadratic form, used for every functional of g^ below).
struct VerifiedGram {
  Eigen::MatrixXd X;     // ~ L^{-1}, lower triangular
  double kappa_a = 0;    // gamma_c ||X||_F + ||I - X L||_F ||L^{-1}||
  double kappa_q = 0;    // 1 / (1 - mu ||L^{-1}||^2), mu >= ||R - L L^T||_2
  double inv_norm = 0;   // >= ||R^{-1}||_2
  double gamma_cols = 0; // gamma_n for products of length cols
};

VerifiedGram verify_gram(const Eigen::MatrixXd& Z) {
  const Eigen::Index M = Z.rows(), c = Z.cols();
  // Only the lower triangle of fl(Z^T Z) is read (LLT, D below): a symmetric rank update computes
  // half the products. The error bound below holds for any order of summation.
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(c, c);
  R.selfadjointView<Eigen::Lower>().rankUpdate(Z.transpose());
  const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(R);
  if (llt.info() != Eigen::Success)
    throw InputError("guaranteed set: the step-1 regressor Z^T Z is not positive definite (inputs not exciting)");
  const Eigen::MatrixXd L = llt.matrixL();
  VerifiedGram g;
  g.X = L.triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(c, c));
  g.gamma_cols = gamma_n(c);
  // |R_exact - fl(R)|_ij <= gamma_M (|Z|^T |Z|)_ij <= gamma_M max_i R_ii (Cauchy-Schwarz on the
  // columns), and R_ii <= fl(R_ii) / (1 - gamma_M); plus M underflows of at most the smallest
  // subnormal per entry. ||.||_2 <= c max |entry|.
  IntervalMatrix E(c, c), D(c, c);  // I - X L and L L^T - fl(R), lower triangles (both symmetric or triangular)
  double mu = 0;
  {
    RoundingScope upward;
    const I gM(gamma_n(M));
    const I entry = gM * I(R.diagonal().maxCoeff()) / (I(1.0) - gM) +
                    I(static_cast<double>(M)) * I(std::numeric_limits<double>::denorm_min());
    const I eta1 = I(static_cast<double>(c)) * entry;
    // Sums of products of doubles as [lo, hi] in upward rounding: x y rounded up is x * y,
    // rounded down -((-x) * y); a - b rounded down is -(b - a). These are the ends Boost's
    // interval operations give on degenerate intervals (up to the sign of a zero), without
    // their case analysis on signs: about c^3 / 3 products, the bulk of this function.
    for (Eigen::Index j = 0; j < c; ++j)
      for (Eigen::Index i = 0; i < c; ++i) {
        if (j > i) {  // E is lower triangular; D is filled from the symmetric entry below
          E(i, j) = Interval(0.0);
          continue;
        }
        double elo = i == j ? 1.0 : 0.0, ehi = elo, dlo = 0.0, dhi = 0.0;
        for (Eigen::Index k = j; k <= i; ++k) {
          const double x = g.X(i, k), l = L(k, j);
          elo = -(x * l - elo);   // e - [down(x l), up(x l)]: lower end down(elo - up(x l))
          ehi = ehi + (-x) * l;   // upper end up(ehi - down(x l)) = up(ehi + up(-x l))
        }
        for (Eigen::Index k = 0; k <= j; ++k) {
          const double a = L(i, k), b = L(j, k);
          dlo = -((-dlo) + (-a) * b);  // down(dlo + down(a b)) = -up(-dlo + up(-a b))
          dhi = dhi + a * b;
        }
        dlo = -(R(i, j) - dlo);
        dhi = dhi - R(i, j);
        E(i, j) = Interval(elo, ehi);
        D(i, j) = Interval(dlo, dhi);
      }
    for (Eigen::Index i = 0; i < c; ++i)
      for (Eigen::Index j = i + 1; j < c; ++j) D(i, j) = D(j, i);
    mu = eta1.upper();
  }
  const double e = detail::frobenius_upper(E);
  if (!(e < 1)) throw NumericalError("guaranteed set: the inverse Cholesky factor of Z^T Z cannot be verified");
  const double xf = detail::frobenius_upper(to_interval(g.X));
  RoundingScope upward;
  const I lambda = I(xf) / (I(1.0) - I(e));  // >= ||L^{-1}||_2
  const I mu_total = I(mu) + I(detail::frobenius_upper(D));  // >= ||R - L L^T||_2
  const I shrink = I(1.0) - mu_total * lambda * lambda;
  if (!(shrink.lower() > 0)) throw NumericalError("guaranteed set: Z^T Z is too ill-conditioned to verify");
  g.kappa_q = (I(1.0) / shrink).upper();
  g.kappa_a = (I(g.gamma_cols) * I(xf) + I(e) * lambda).upper();
  g.inv_norm = (I(g.kappa_q) * lambda * lambda).upper();
  return g;
}

// Upper bounds on sqrt(a_t^T R^{-1} a_t) and ||a_t|| for the rows a_t of a matrix W of
// functionals, from s2_t = fl(||fl(X a_t)||^2) and w2_t = fl(||a_t||^2), each a computed sum of at
// most `terms` squares.
struct QuadraticBounds {
  Eigen::VectorXd root_q, norm;
};

QuadraticBounds quadratic_bounds(const VerifiedGram& g, const Eigen::VectorXd& s2, const Eigen::VectorXd& w2,
                                 Eigen::Index terms) {
  const Eigen::Index rows = s2.size();
  QuadraticBounds b{Eigen::VectorXd(rows), Eigen::VectorXd(rows)};
  RoundingScope upward;
  // A computed sum of n squares is at least (1 - gamma_n) times the exact one.
  const I inflate = I(1.0) / (I(1.0) - I(gamma_n(std::max<Eigen::Index>(terms, 1))));
  const I kq = boost::numeric::sqrt(I(g.kappa_q));
  for (Eigen::Index t = 0; t < rows; ++t) {
    // std::sqrt is correctly rounded in the current (upward) mode: an upper bound, no mode switch
    // (Boost's interval sqrt switches to downward for the lower end we do not need).
    const double norm_a = std::sqrt((I(w2[t]) * inflate).upper());
    const double norm_s = std::sqrt((I(s2[t]) * inflate).upper());
    b.norm[t] = norm_a;
    b.root_q[t] = (kq * (I(norm_s) + I(g.kappa_a) * I(norm_a))).upper();
  }
  return b;
}

// Functionals whose nonzero entries are the columns first .. first + Wu.cols() - 1 (Wu holds
// them): X is lower triangular, so only its rows from `first` on enter fl(X a_t).
QuadraticBounds column_range_bounds(const VerifiedGram& g, const Eigen::Ref<const Eigen::MatrixXd>& Wu,
                                    Eigen::Index first) {
  const Eigen::Index c = g.X.rows(), m = Wu.cols();
  const Eigen::MatrixXd S = Wu * g.X.block(first, first, c - first, m).transpose();
  return quadratic_bounds(g, S.rowwise().squaredNorm(), Wu.rowwise().squaredNorm(), c);
}

// The propagator functionals of every lag at once. The functional of lag l at column c is the
// window u_p(c + l) without its last l blocks: the first m_l = nu (p - l) entries of row c + l of
// the window matrix Zx (rows r: u(r), ..., u(r + p - 1), zeros past the data). As X is lower
// triangular, the first m_l entries of fl(X a) are those of row c + l of fl(Zx X^T), computed once
// for all lags (each lag's own product was a third of a Monte Carlo run); only the entries from
// m_l on, sums over the first m_l entries of a, are lag-specific. Gamma_c covers any order of
// summation, and zeros add exactly, so the bounds are those of the separate products.
class WindowFunctionals {
 public:
  WindowFunctionals(const VerifiedGram& g, const Eigen::Ref<const Eigen::MatrixXd>& u, int past, Eigen::Index cols,
                    int K, int max_lag)
      : g_(g), K_(K), nu_(u.cols()), Zx_(Eigen::MatrixXd::Zero(K + max_lag, cols)), Sx_(K + max_lag, cols) {
    const Eigen::Index N = u.rows();
    for (int b = 0; b < past; ++b) {  // block column by block column (contiguous)
      const Eigen::Index rows = std::min<Eigen::Index>(K + max_lag, N - b);
      Zx_.block(0, b * nu_, rows, nu_) = u.middleRows(b, rows);
    }
    Sx_.noalias() = Zx_ * g_.X.transpose().triangularView<Eigen::Upper>();
  }

  // Bounds for the functionals of lag l at columns 0 .. K-1.
  QuadraticBounds bounds(int lag, int past) const {
    const Eigen::Index c = g_.X.rows(), m = nu_ * (past - lag);
    const auto Wu = Zx_.block(lag, 0, K_, m);
    Eigen::VectorXd s2 = Sx_.block(lag, 0, K_, m).rowwise().squaredNorm();
    if (c > m) s2 += (Wu * g_.X.bottomLeftCorner(c - m, m).transpose()).rowwise().squaredNorm();
    return quadratic_bounds(g_, s2, Wu.rowwise().squaredNorm(), c);
  }

 private:
  const VerifiedGram& g_;
  Eigen::Index K_, nu_;
  Eigen::MatrixXd Zx_, Sx_;  // windows and fl(Zx X^T)
};

// The Markov-parameter ellipsoid of one output: the true g satisfies
// (g - g^)^T R (g - g^) <= level for the exact least-squares g^, and ||g^ - g_c|| <= offset for
// the computed g_c. Then |a^T (g - g_c)| <= sqrt(level) sqrt(a^T R^{-1} a) + offset ||a||.
struct MarkovEllipsoid {
  double level = 0, root_level = 0, offset = 0, g_norm = 0;
};

MarkovEllipsoid markov_ellipsoid(const VerifiedGram& g, const Eigen::MatrixXd& Z, const Eigen::VectorXd& Y,
                                 const Eigen::VectorXd& gc, double wbar, int output,
                                 std::vector<std::string>& contradictions) {
  const Eigen::Index M = Z.rows(), c = Z.cols();
  MarkovEllipsoid m;
  double j_low = 0, level_upper = 0;
  // Residuals of the computed estimate, eps = Y - Z g_c, and h = Z^T eps (J = ||eps||^2 - h^T R^{-1} h),
  // in floating point with a-priori error bounds (Higham 3.1) instead of interval dot products:
  //   |fl(Y - Z g_c) - eps|_t  <= gamma_{c+1} (|Y_t| + (|Z| |g_c|)_t) =: delta_t
  //   |fl(Z^T e) - Z^T eps|_j  <= (|Z|^T delta)_j + gamma_M (|Z|^T |e|)_j
  // plus one smallest subnormal per product for underflow. The bounds are products of
  // nonnegative numbers, computed (Eigen included) in upward rounding, hence upper bounds.
  const Eigen::VectorXd e = Y - Z * gc;
  const Eigen::VectorXd h_fl = Z.transpose() * e;
  const Eigen::MatrixXd Za = Z.cwiseAbs();
  {
    RoundingScope upward;
    const double tiny = std::numeric_limits<double>::denorm_min();
    const Eigen::VectorXd ga = gc.cwiseAbs(), ea = e.cwiseAbs();
    const Eigen::VectorXd w = Za * ga;  // >= |Z| |g_c| (upward)
    const double gc1 = gamma_n(c + 1), gM = gamma_n(M);
    Eigen::VectorXd delta(M);
    I sum_sq(0.0);
    for (Eigen::Index t = 0; t < M; ++t) {
      delta[t] = gc1 * (std::abs(Y[t]) + w[t]) + static_cast<double>(c + 1) * tiny;
      sum_sq += boost::numeric::square(I(e[t]) + I(-delta[t], delta[t]));
    }
    const Eigen::VectorXd r = Za.transpose() * (delta + gM * ea);  // upward, nonnegative
    I h_sq(0.0);
    for (Eigen::Index j = 0; j < c; ++j) {
      const double rj = r[j] + static_cast<double>(M) * tiny;
      h_sq += boost::numeric::square(I(h_fl[j]) + I(-rj, rj));
    }
    const I h_norm = boost::numeric::sqrt(h_sq);
    j_low = std::max(0.0, (sum_sq - I(g.inv_norm) * h_sq).lower());
    // ||Y - Z g||^2 = ||w||^2 <= M wbar^2 for the true g, and = J + (g - g^)^T R (g - g^).
    const I level = I(static_cast<double>(M)) * boost::numeric::square(I(wbar)) - I(j_low);
    level_upper = level.upper();
    m.level = std::max(0.0, level.upper());
    m.root_level = boost::numeric::sqrt(I(m.level)).upper();
    m.offset = (I(g.inv_norm) * h_norm).upper();
    I gn(0.0);
    for (Eigen::Index j = 0; j < c; ++j) gn += boost::numeric::square(I(gc[j]));
    m.g_norm = boost::numeric::sqrt(gn).upper();
  }
  if (level_upper < 0) {  // written out in the default rounding mode
    std::ostringstream os;
    os << "output " << output + 1 << ": the step-1 residuals (sum of squares >= " << j_low << " over " << M
       << " samples) exceed what noise + tail <= " << wbar << " allows (" << M << " x " << wbar << "^2)";
    contradictions.push_back(os.str());
  }
  return m;
}

// Radii sqrt(level) sqrt(a^T R^{-1} a) + offset ||a|| + extra ||a|| for the functionals a of q.
Eigen::VectorXd functional_radii(const MarkovEllipsoid& m, const QuadraticBounds& q, double extra_per_norm) {
  Eigen::VectorXd r(q.norm.size());
  RoundingScope upward;
  for (Eigen::Index t = 0; t < r.size(); ++t)
    r[t] = (I(m.root_level) * I(q.root_q[t]) + (I(m.offset) + I(extra_per_norm)) * I(q.norm[t])).upper();
  return r;
}

I meet(const I& a, const I& b, bool& empty) {
  const double lo = std::max(a.lower(), b.lower()), hi = std::min(a.upper(), b.upper());
  empty = lo > hi;
  return empty ? a : I(lo, hi);
}

void check_bounds(const Eigen::VectorXd& v, Eigen::Index size, const char* what, const char* per) {
  if (v.size() != size)
    throw InputError(std::string("guaranteed set: ") + what + " needs one value per " + per + " (" +
                     std::to_string(size) + "), got " + std::to_string(v.size()));
  for (Eigen::Index k = 0; k < v.size(); ++k)
    if (!(v[k] >= 0) || !std::isfinite(v[k]))
      throw InputError(std::string("guaranteed set: ") + what + " " + std::to_string(k + 1) +
                       " must be finite and >= 0");
}

// The enclosures of one run that do not meet, written out after the rounding scopes (printing in
// upward rounding would change the digits).
class Clashes {
 public:
  void add(int state, int t, const I& one, const I& other) { clashes_.push_back({state, t, one, other}); }

  void write_to(const CanonicalStructure& st, std::vector<std::string>& out) const {
    for (const Clash& c : clashes_) {
      std::ostringstream os;
      os << "state " << c.state + 1 << " (" << to_string(st.rows()[static_cast<std::size_t>(c.state)]) << ") at sample "
         << c.t << ": the enclosures " << c.one << " and " << c.other << " do not meet";
      out.push_back(os.str());
    }
  }

 private:
  struct Clash {
    int state, t;
    Interval one, other;
  };
  std::vector<Clash> clashes_;
};

void check_assumptions(const PropagatorResult& id, const Eigen::Ref<const Eigen::MatrixXd>& u,
                       const Eigen::Ref<const Eigen::MatrixXd>& y, const GuaranteedSetAssumptions& a) {
  const CanonicalStructure& st = id.structure;
  const int n = st.nx(), nu = st.nu(), ny = st.ny(), p = id.first_state;
  const int N = static_cast<int>(u.rows()), K = static_cast<int>(id.states.cols());
  if (u.cols() != nu || y.cols() != ny || y.rows() != N || K != N - p)
    throw InputError("guaranteed set: u and y are not the data the model was identified from");
  check_bounds(a.noise_bound, ny, "noise_bound", "output");
  if (a.state_error_bound.size() > 0) check_bounds(a.state_error_bound, n, "state_error_bound", "state");
  else if (a.tail_bound.size() == 0)
    throw InputError("guaranteed set: give a tail bound (data-based state bound) or a state error bound");
  else check_bounds(a.tail_bound, ny, "tail_bound", "output");
}

// Lag-0 rows of an output with D known: x_c,k(t) = y_o(t) - v_o(t), whatever else is assumed.
bool row_is_an_output(const CanonicalStructure& st, int k, int t, int N) {
  return st.rows()[static_cast<std::size_t>(k)].lag == 0 && !st.estimate_d() && t < N;
}

// With a user bound on the state error: x^ +- bound, met with the output where a row is one.
void enclose_with_state_bound(const PropagatorResult& id, const Eigen::Ref<const Eigen::MatrixXd>& y,
                              const GuaranteedSetAssumptions& a, StateEnclosure& X, Clashes& clashes) {
  const CanonicalStructure& st = id.structure;
  const int n = st.nx(), p = id.first_state, K = static_cast<int>(id.states.cols());
  RoundingScope upward;
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < K; ++c) {
      I x = I(id.states(k, c)) + I(-a.state_error_bound[k], a.state_error_bound[k]);
      const int t = p + c, o = st.rows()[static_cast<std::size_t>(k)].output;
      if (row_is_an_output(st, k, t, static_cast<int>(y.rows()))) {
        bool empty = false;
        const I obs = I(y(t, o)) + I(-a.noise_bound[o], a.noise_bound[o]);
        const I m = meet(x, obs, empty);
        if (empty) clashes.add(k, t, x, obs);
        else x = m;
      }
      X.states(k, c) = x;
    }
  for (int i = 0; i < n; ++i)
    if (st.a_unit(i) >= 0)
      for (int c = 0; c + 1 < K; ++c) X.unit_steps(i, c) = I(X.states(i, c + 1)) - I(X.states(st.a_unit(i), c));
}

// ||a|| <= sqrt(p) max_t ||u(t)|| for every window a of p input samples.
double window_norm_bound(const Eigen::Ref<const Eigen::MatrixXd>& u, int p) {
  RoundingScope upward;
  I largest(0.0);
  for (Eigen::Index t = 0; t < u.rows(); ++t) {
    I s(0.0);
    for (Eigen::Index m = 0; m < u.cols(); ++m) s += boost::numeric::square(I(u(t, m)));
    largest = I(0.0, std::max(largest.upper(), s.upper()));
  }
  return boost::numeric::sqrt(I(static_cast<double>(p)) * largest).upper();
}

// Without a state bound: every state from the Markov-parameter ellipsoid of its output, through
// the propagator and, where the row allows, through the output; then the unit rows of A_c.
class DataBasedEnclosure {
 public:
  DataBasedEnclosure(const PropagatorResult& id, const Eigen::Ref<const Eigen::MatrixXd>& u,
                     const Eigen::Ref<const Eigen::MatrixXd>& y, const GuaranteedSetAssumptions& a)
      : id_(id), st_(id.structure), u_(u), y_(y), a_(a), p_(id.first_state), N_(static_cast<int>(u.rows())),
        K_(static_cast<int>(id.states.cols())), Z_(past_input_regressor(u, p_, st_.estimate_d())), gram_(verify_gram(Z_)) {}

  void enclose(StateEnclosure& X, Clashes& clashes) {
    output_ellipsoids(X);
    int max_lag = 0;
    for (const auto& r : st_.rows()) max_lag = std::max(max_lag, r.lag);
    const WindowFunctionals windows(gram_, u_, p_, Z_.cols(), K_, max_lag);
    for (int k = 0; k < st_.nx(); ++k) enclose_row(k, windows, X, clashes);
    const double window_norm = window_norm_bound(u_, p_);
    for (int i = 0; i < st_.nx(); ++i)
      if (st_.a_unit(i) >= 0) enclose_unit_steps(i, window_norm, X, clashes);
  }

 private:
  // Column of the Markov parameter C_o A^j B (input block) in g: block p-1-j.
  Eigen::Index block(int j) const { return static_cast<Eigen::Index>((p_ - 1 - j) * st_.nu()); }

  // The Markov-parameter ellipsoid of every output the rows use.
  void output_ellipsoids(StateEnclosure& X) {
    const int ny = st_.ny(), nu = st_.nu();
    ell_.resize(static_cast<std::size_t>(ny));
    g_.resize(static_cast<std::size_t>(ny));
    X.markov_level = Eigen::VectorXd::Constant(ny, std::numeric_limits<double>::quiet_NaN());
    for (int o = 0; o < ny; ++o) {
      bool used = false;
      for (const auto& r : st_.rows()) used = used || r.output == o;
      if (!used) continue;
      Eigen::VectorXd& g = g_[static_cast<std::size_t>(o)];
      g.resize(Z_.cols());
      g.head(nu * p_) = id_.markov.row(o).transpose();
      if (st_.estimate_d()) g.tail(nu) = id_.d.row(o).transpose();
      const double wbar = (Interval(a_.noise_bound[o]) + Interval(a_.tail_bound[o])).upper();
      ell_[static_cast<std::size_t>(o)] = markov_ellipsoid(gram_, Z_, y_.col(o).tail(N_ - p_), g, wbar, o, X.contradictions);
      X.markov_level[o] = ell_[static_cast<std::size_t>(o)].level;
    }
  }

  // Row k: the propagator's x^_k(t) = a^T g^ with a = u_p(t+l) without its last l blocks (the
  // stored x^ is a floating-point product, error <= gamma_cols ||a|| ||g_c||), met with the
  // output x_c,k(t) = y_o(t+l) - v - D_o u(t+l) - sum_{j<l} (C_o A^j B) u(t+l-1-j) for t+l < N.
  void enclose_row(int k, const WindowFunctionals& windows, StateEnclosure& X, Clashes& clashes) const {
    const int l = st_.rows()[static_cast<std::size_t>(k)].lag, o = st_.rows()[static_cast<std::size_t>(k)].output;
    const MarkovEllipsoid& m = ell_[static_cast<std::size_t>(o)];
    const Eigen::VectorXd& go = g_[static_cast<std::size_t>(o)];
    const double rounding = (Interval(gram_.gamma_cols) * Interval(m.g_norm)).upper();
    const Eigen::VectorXd rp = functional_radii(m, windows.bounds(l, p_), rounding);
    const Eigen::MatrixXd Wo = output_functionals(l);
    const Eigen::Index wo_first = st_.nu() * (p_ - l);
    const Eigen::VectorXd ro = Wo.cols() == 0 ? Eigen::VectorXd::Zero(K_)
                                              : functional_radii(m, column_range_bounds(gram_, Wo, wo_first), 0.0);
    RoundingScope upward;
    for (int c = 0; c < K_; ++c) {
      const int t = p_ + c;
      const double radius = (I(a_.tail_bound[o]) + I(rp[c])).upper();
      I x = I(id_.states(k, c)) + I(-radius, radius);
      if (c + l < K_) {
        I obs(y_(t + l, o));
        for (Eigen::Index q = 0; q < Wo.cols(); ++q)
          if (Wo(c, q) != 0) obs -= I(Wo(c, q)) * I(go[wo_first + q]);
        const double noise = (I(a_.noise_bound[o]) + I(ro[c])).upper();
        obs += I(-noise, noise);
        bool empty = false;
        const I both = meet(x, obs, empty);
        if (empty) clashes.add(k, t, x, obs);
        else x = both;
      }
      X.states(k, c) = x;
    }
  }

  // The output functionals of lag l use the columns from nu (p - l) on (blocks p-1-j, j < l; then
  // D): one row per c, written block column by block column (contiguous).
  Eigen::MatrixXd output_functionals(int l) const {
    const int nu = st_.nu();
    const Eigen::Index wo_first = nu * (p_ - l);
    Eigen::MatrixXd Wo = Eigen::MatrixXd::Zero(K_, Z_.cols() - wo_first);
    for (int j = 0; j < l; ++j) Wo.block(0, block(j) - wo_first, K_ - l, nu) = u_.middleRows(p_ + l - 1 - j, K_ - l);  // u(t+l-1-j)
    if (st_.estimate_d()) Wo.block(0, nu * p_ - wo_first, K_ - l, nu) = u_.middleRows(p_ + l, K_ - l);  // u(t+l)
    return Wo;
  }

  // Unit row i of A_c: x_c,i(t+1) - x_c,k(t) = (C_o A^l B) u(t) exactly (the tails cancel), which
  // the propagator estimates by x^_i(t+1) - x^_k(t) = c^T g^, c = u(t) in block p-1-l.
  void enclose_unit_steps(int i, double window_norm, StateEnclosure& X, Clashes& clashes) const {
    const int k = st_.a_unit(i);
    const int l = st_.rows()[static_cast<std::size_t>(i)].lag, o = st_.rows()[static_cast<std::size_t>(i)].output;
    const MarkovEllipsoid& m = ell_[static_cast<std::size_t>(o)];
    // Row c: u(p + c) in the columns of block p-1-l.
    const Eigen::VectorXd rc = functional_radii(m, column_range_bounds(gram_, u_.middleRows(p_, K_ - 1), block(l)), 0.0);
    RoundingScope upward;
    // Rounding of the two stored states: gamma_cols ||a|| ||g_c|| each (see enclose_row).
    const I stored = I(2.0) * I(gram_.gamma_cols) * I(m.g_norm) * I(window_norm);
    for (int c = 0; c + 1 < K_; ++c) {
      const double radius = (I(rc[c]) + stored).upper();
      const I direct = (I(id_.states(i, c + 1)) - I(id_.states(k, c))) + I(-radius, radius);
      const I through = I(X.states(i, c + 1)) - I(X.states(k, c));
      bool empty = false;
      const I both = meet(direct, through, empty);
      if (empty) clashes.add(i, p_ + c, direct, through);
      X.unit_steps(i, c) = empty ? direct : both;
    }
  }

  const PropagatorResult& id_;
  const CanonicalStructure& st_;
  const Eigen::Ref<const Eigen::MatrixXd> u_, y_;
  const GuaranteedSetAssumptions& a_;
  const int p_, N_, K_;
  const Eigen::MatrixXd Z_;
  const VerifiedGram gram_;
  std::vector<MarkovEllipsoid> ell_;
  std::vector<Eigen::VectorXd> g_;
};

}  // namespace

StateEnclosure enclose_states(const PropagatorResult& id, const Eigen::Ref<const Eigen::MatrixXd>& u,
                              const Eigen::Ref<const Eigen::MatrixXd>& y, const GuaranteedSetAssumptions& a) {
  check_assumptions(id, u, y, a);
  const int n = id.structure.nx(), K = static_cast<int>(id.states.cols());
  StateEnclosure X;
  X.first = id.first_state;
  X.states.resize(n, K);
  X.unit_steps = IntervalMatrix::Constant(n, K - 1, Interval(0.0));
  Clashes clashes;
  if (a.state_error_bound.size() > 0) enclose_with_state_bound(id, y, a, X, clashes);
  else DataBasedEnclosure(id, u, y, a).enclose(X, clashes);
  // The ellipsoids' contradictions (written while they were built) come before the clashes.
  clashes.write_to(id.structure, X.contradictions);
  return X;
}

CanonicalFps guaranteed_fps(const PropagatorResult& id, const Eigen::Ref<const Eigen::MatrixXd>& u,
                            const Eigen::Ref<const Eigen::MatrixXd>& y, const StateEnclosure& X,
                            const Eigen::Ref<const Eigen::VectorXd>& noise_bound) {
  const CanonicalStructure& st = id.structure;
  const int n = st.nx(), nu = st.nu(), ny = st.ny(), K = static_cast<int>(X.states.cols());
  if (X.states.rows() != n || X.unit_steps.cols() != K - 1 || K < 2 || X.first + K > u.rows() ||
      u.cols() != nu || y.cols() != ny || y.rows() != u.rows())
    throw InputError("guaranteed_fps: the state enclosure does not fit the model and the data");
  check_bounds(noise_bound, ny, "noise_bound", "output");
  const int eq = n + ny;
  IntervalMatrix Psi = IntervalMatrix::Constant((K - 1) * eq, st.parameter_count(), Interval(0.0));
  IntervalVector Y((K - 1) * eq);
  {
    RoundingScope upward;  // interval work only
    for (int k = 0; k + 1 < K; ++k) {
      const int t = X.first + k;
      for (int i = 0; i < n; ++i) {  // state rows
        const int row = k * eq + i;
        if (st.a_unit(i) >= 0) {
          Y[row] = X.unit_steps(i, k);
        } else {
          Y[row] = X.states(i, k + 1);
          for (int q = 0; q < n; ++q) Psi(row, st.a_offset(i) + q) = X.states(q, k);
        }
        for (int m = 0; m < nu; ++m) Psi(row, st.b_offset(i) + m) = Interval(u(t, m));
      }
      for (int j = 0; j < ny; ++j) {  // output rows
        const int row = k * eq + n + j;
        const I noise(-noise_bound[j], noise_bound[j]);
        if (st.c_unit(j) >= 0) {
          Y[row] = I(y(t, j)) - I(X.states(st.c_unit(j), k)) + noise;
        } else {
          Y[row] = I(y(t, j)) + noise;
          for (int q = 0; q < n; ++q) Psi(row, st.c_offset(j) + q) = X.states(q, k);
        }
        if (st.estimate_d())
          for (int m = 0; m < nu; ++m) Psi(row, st.d_offset(j) + m) = Interval(u(t, m));
      }
    }
  }
  return CanonicalFps(Psi, Y);
}

Eigen::VectorXd fir_tail_bound(const StateSpaceModel& s, int past, double input_bound) {
  if (past < 0 || !(input_bound >= 0)) throw InputError("fir_tail_bound: need past >= 0 and input_bound >= 0");
  const Eigen::Index ny = s.C.rows();
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(ny);
  Eigen::MatrixXd CA = s.C;
  for (int k = 0; k < past; ++k) CA = CA * s.A;
  // Sum until a term is below 1e-17 of the sum for 50 steps in a row, at most 100 000 terms.
  int quiet = 0;
  for (int k = 0; k < 100000 && quiet < 50; ++k) {
    const Eigen::VectorXd term = (CA * s.B).cwiseAbs().rowwise().sum();
    sum += term;
    quiet = (term.array() <= 1e-17 * sum.array().max(1e-300)).all() ? quiet + 1 : 0;
    CA = CA * s.A;
  }
  if (quiet < 50) throw InputError("fir_tail_bound: the impulse response does not decay (unstable system?)");
  // The neglected terms decay geometrically below 1e-17 of the sum; the rounding of the sum is
  // far below 1e-9 of it. A relative margin of 1e-6 covers both.
  return (sum * input_bound * (1 + 1e-6)).array() + 1e-300;
}

}  // namespace sets
