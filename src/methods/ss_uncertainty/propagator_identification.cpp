#include "sets/methods/ss_uncertainty/propagator_identification.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <utility>
#include <sstream>

#include "sets/core/error.hpp"

namespace sets {

namespace {

int find_row(const std::vector<ObservabilityRow>& rows, ObservabilityRow r) {
  const auto it = std::find(rows.begin(), rows.end(), r);
  return it == rows.end() ? -1 : static_cast<int>(it - rows.begin());
}

double smallest_singular_value(const Eigen::MatrixXd& M) {
  if (M.rows() == 0) return std::numeric_limits<double>::infinity();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M);
  return svd.singularValues()(svd.singularValues().size() - 1);
}

// Greedy choice of n independent rows among candidates (lag, output) in the order of `selection`.
// A chain of one output stops at its first dependent lag (shift invariance of Gamma).
std::vector<ObservabilityRow> greedy_rows(const std::function<Eigen::RowVectorXd(int, int)>& row,
                                          int n, int ny, int max_lag, RowSelection selection,
                                          double abs_tol) {
  std::vector<ObservabilityRow> chosen;
  std::vector<bool> closed(ny, false);
  Eigen::MatrixXd M(0, row(0, 0).size());
  auto try_add = [&](int lag, int j) {
    if (closed[j] || static_cast<int>(chosen.size()) == n) return;
    Eigen::MatrixXd N(M.rows() + 1, M.cols());
    N << M, row(lag, j);
    if (N.rows() <= N.cols() && smallest_singular_value(N) > abs_tol) {
      M = std::move(N);
      chosen.push_back({lag, j});
    } else {
      closed[j] = true;
    }
  };
  if (selection == RowSelection::output_major) {
    for (int j = 0; j < ny; ++j)
      for (int l = 0; l <= max_lag && !closed[j]; ++l) try_add(l, j);
  } else {
    for (int l = 0; l <= max_lag; ++l)
      for (int j = 0; j < ny; ++j) try_add(l, j);
  }
  return chosen;
}

void check_finite(const Eigen::MatrixXd& X, const char* what) {
  for (int t = 0; t < X.rows(); ++t)
    for (int c = 0; c < X.cols(); ++c)
      if (!std::isfinite(X(t, c))) {
        std::ostringstream os;
        os << what << ": sample " << t << ", column " << c + 1 << " is not a finite number";
        throw InputError(os.str());
      }
}

// Concatenation through a stream: GCC 12 warns (-Wrestrict, a false positive) on "lit" + string.
template <class... T>
std::string cat(const T&... parts) {
  std::ostringstream os;
  (os << ... << parts);
  return os.str();
}

}  // namespace

std::string to_string(const ObservabilityRow& row) {
  return cat("y", row.output + 1, "[t+", row.lag, "]");
}

CanonicalStructure::CanonicalStructure(std::vector<ObservabilityRow> rows, int nu, int ny,
                                       bool estimate_d)
    : rows_(std::move(rows)), nu_(nu), ny_(ny), estimate_d_(estimate_d) {
  const int n = nx();
  if (n < 1) throw InputError("canonical structure: at least one state row is needed");
  if (nu < 1 || ny < 1) throw InputError("canonical structure: need at least one input and one output");
  for (int k = 0; k < n; ++k) {
    const auto& r = rows_[k];
    if (r.lag < 0 || r.output < 0 || r.output >= ny)
      throw InputError("canonical structure: row " + std::to_string(k) + " (" + to_string(r) +
                       ") is outside Gamma_p");
    if (find_row(rows_, r) != k)
      throw InputError("canonical structure: row " + to_string(r) + " is selected twice");
  }
  a_unit_.resize(n);
  a_offset_.assign(n, -1);
  c_unit_.resize(ny);
  c_offset_.assign(ny, -1);
  for (int i = 0; i < n; ++i) {
    a_unit_[i] = find_row(rows_, {rows_[i].lag + 1, rows_[i].output});
    if (a_unit_[i] < 0) a_offset_[i] = std::exchange(count_, count_ + n);
  }
  for (int j = 0; j < ny; ++j) {
    c_unit_[j] = find_row(rows_, {0, j});
    if (c_unit_[j] < 0) c_offset_[j] = std::exchange(count_, count_ + n);
  }
  b0_ = std::exchange(count_, count_ + n * nu);
  if (estimate_d_) d0_ = std::exchange(count_, count_ + ny * nu);
}

int CanonicalStructure::parameter_count() const { return count_; }

std::vector<std::string> CanonicalStructure::parameter_names() const {
  std::vector<std::string> names(count_);
  const int n = nx();
  const int free_a = static_cast<int>(std::count(a_unit_.begin(), a_unit_.end(), -1));
  for (int i = 0; i < n; ++i)
    if (a_offset_[i] >= 0)
      for (int k = 0; k < n; ++k)
        names[a_offset_[i] + k] = free_a == 1 ? cat("-a", k) : cat("A(", i + 1, ",", k + 1, ")");
  for (int j = 0; j < ny_; ++j)
    if (c_offset_[j] >= 0)
      for (int k = 0; k < n; ++k) names[c_offset_[j] + k] = cat("c", k, "^", j + 1);
  for (int i = 0; i < n; ++i)
    for (int m = 0; m < nu_; ++m) names[b_offset(i) + m] = cat("b", i, "^", m + 1);
  if (estimate_d_)
    for (int j = 0; j < ny_; ++j)
      for (int m = 0; m < nu_; ++m)
        names[d_offset(j) + m] = cat("D(", j + 1, ",", m + 1, ")");
  return names;
}

StateSpaceModel CanonicalStructure::to_model(const Eigen::Ref<const Eigen::VectorXd>& theta) const {
  if (theta.size() != count_) throw InputError("canonical structure: wrong number of parameters");
  const int n = nx();
  StateSpaceModel m{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, nu_),
                    Eigen::MatrixXd::Zero(ny_, n), Eigen::MatrixXd::Zero(ny_, nu_)};
  for (int i = 0; i < n; ++i) {
    if (a_unit_[i] >= 0) m.A(i, a_unit_[i]) = 1.0;
    else m.A.row(i) = theta.segment(a_offset_[i], n).transpose();
    m.B.row(i) = theta.segment(b_offset(i), nu_).transpose();
  }
  for (int j = 0; j < ny_; ++j) {
    if (c_unit_[j] >= 0) m.C(j, c_unit_[j]) = 1.0;
    else m.C.row(j) = theta.segment(c_offset_[j], n).transpose();
    if (estimate_d_) m.D.row(j) = theta.segment(d_offset(j), nu_).transpose();
  }
  return m;
}

Eigen::VectorXd CanonicalStructure::to_parameters(const StateSpaceModel& c) const {
  const int n = nx();
  if (c.A.rows() != n || c.A.cols() != n || c.B.rows() != n || c.B.cols() != nu_ || c.C.rows() != ny_ ||
      c.C.cols() != n)
    throw InputError("canonical structure: model dimensions do not match");
  Eigen::VectorXd theta(count_);
  for (int i = 0; i < n; ++i) {
    if (a_offset_[i] >= 0) theta.segment(a_offset_[i], n) = c.A.row(i).transpose();
    theta.segment(b_offset(i), nu_) = c.B.row(i).transpose();
  }
  for (int j = 0; j < ny_; ++j) {
    if (c_offset_[j] >= 0) theta.segment(c_offset_[j], n) = c.C.row(j).transpose();
    if (estimate_d_) theta.segment(d_offset(j), nu_) = c.D.row(j).transpose();
  }
  return theta;
}

int observability_rank(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& C,
                       double rel_tol) {
  const int n = static_cast<int>(A.rows());
  if (A.cols() != n || C.cols() != n) throw InputError("observability_rank: A must be n x n and C p x n");
  Eigen::MatrixXd O(C.rows() * n, n);
  Eigen::MatrixXd CA = C;
  for (int l = 0; l < n; ++l) {
    O.middleRows(l * C.rows(), C.rows()) = CA;
    CA = CA * A;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(O);
  const auto& s = svd.singularValues();
  if (s.size() == 0 || s(0) == 0.0) return 0;
  return static_cast<int>((s.array() > rel_tol * s(0)).count());
}

std::vector<ObservabilityRow> select_rows(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                          const Eigen::Ref<const Eigen::MatrixXd>& C, RowSelection selection) {
  const int n = static_cast<int>(A.rows());
  const int r = observability_rank(A, C);
  if (r < n)
    throw InputError("(A, C) is not observable: the observability matrix has rank " + std::to_string(r) +
                     " < n_x = " + std::to_string(n));
  auto row = [&](int lag, int j) -> Eigen::RowVectorXd {
    Eigen::RowVectorXd c = C.row(j);
    for (int l = 0; l < lag; ++l) c = c * A;
    return c;
  };
  double scale = 0;
  for (int l = 0; l < n; ++l)
    for (int j = 0; j < C.rows(); ++j) scale = std::max(scale, row(l, j).norm());
  auto rows = greedy_rows(row, n, static_cast<int>(C.rows()), n - 1, selection, 1e-10 * scale);
  if (static_cast<int>(rows.size()) < n)
    throw InputError("(A, C): the chosen row order finds only " + std::to_string(rows.size()) +
                     " independent rows of the observability matrix");
  return rows;
}

StateSpaceModel canonical_form(const StateSpaceModel& s, const std::vector<ObservabilityRow>& rows) {
  const int n = static_cast<int>(s.A.rows());
  if (static_cast<int>(rows.size()) != n)
    throw InputError("canonical_form: " + std::to_string(rows.size()) + " rows given for n_x = " + std::to_string(n));
  const int r = observability_rank(s.A, s.C);
  if (r < n)
    throw InputError("(A, C) is not observable: the observability matrix has rank " + std::to_string(r) +
                     " < n_x = " + std::to_string(n));
  Eigen::MatrixXd T(n, n);
  for (int k = 0; k < n; ++k) {
    if (rows[k].output < 0 || rows[k].output >= s.C.rows() || rows[k].lag < 0)
      throw InputError("canonical_form: row " + to_string(rows[k]) + " does not exist");
    Eigen::RowVectorXd c = s.C.row(rows[k].output);
    for (int l = 0; l < rows[k].lag; ++l) c = c * s.A;
    T.row(k) = c;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(T);
  if (svd.singularValues()(n - 1) <= 1e-12 * svd.singularValues()(0))
    throw InputError("canonical_form: the chosen rows of the observability matrix are dependent");
  const Eigen::MatrixXd Ti = T.inverse();
  StateSpaceModel c{T * s.A * Ti, T * s.B, s.C * Ti, s.D};
  // Unit rows are exact by construction; remove rounding noise so to_parameters reads clean values.
  const CanonicalStructure st(rows, static_cast<int>(s.B.cols()), static_cast<int>(s.C.rows()), false);
  for (int i = 0; i < n; ++i)
    if (st.a_unit(i) >= 0) c.A.row(i) = Eigen::RowVectorXd::Unit(n, st.a_unit(i));
  for (int j = 0; j < s.C.rows(); ++j)
    if (st.c_unit(j) >= 0) c.C.row(j) = Eigen::RowVectorXd::Unit(n, st.c_unit(j));
  return c;
}

CanonicalRegression canonical_regression(const CanonicalStructure& st, const Eigen::Ref<const Eigen::MatrixXd>& states,
                                         int first, const Eigen::Ref<const Eigen::MatrixXd>& u,
                                         const Eigen::Ref<const Eigen::MatrixXd>& y) {
  const int n = st.nx(), nu = st.nu(), ny = st.ny();
  const int K = static_cast<int>(states.cols());
  if (states.rows() != n || u.cols() != nu || y.cols() != ny || u.rows() != y.rows())
    throw InputError("canonical_regression: dimensions of states, u and y do not match the structure");
  if (K < 2 || first < 0 || first + K - 1 > u.rows() - 1)
    throw InputError("canonical_regression: the state sequence does not fit inside the data");
  const int eq = n + ny;
  CanonicalRegression r;
  r.equations = eq;
  r.state_equations = n;
  r.Psi = Eigen::MatrixXd::Zero((K - 1) * eq, st.parameter_count());
  r.y.resize((K - 1) * eq);
  r.equation.resize((K - 1) * eq);
  r.sample.resize((K - 1) * eq);
  for (int k = 0; k + 1 < K; ++k) {
    const int t = first + k;
    const auto x = states.col(k);
    for (int i = 0; i < n; ++i) {
      const int row = k * eq + i;
      r.equation[row] = i;
      r.sample[row] = t;
      if (st.a_unit(i) >= 0) {
        r.y[row] = states(i, k + 1) - x(st.a_unit(i));
      } else {
        r.y[row] = states(i, k + 1);
        r.Psi.row(row).segment(st.a_offset(i), n) = x.transpose();
      }
      r.Psi.row(row).segment(st.b_offset(i), nu) = u.row(t);
    }
    for (int j = 0; j < ny; ++j) {
      const int row = k * eq + n + j;
      r.equation[row] = n + j;
      r.sample[row] = t;
      if (st.c_unit(j) >= 0) {
        r.y[row] = y(t, j) - x(st.c_unit(j));
      } else {
        r.y[row] = y(t, j);
        r.Psi.row(row).segment(st.c_offset(j), n) = x.transpose();
      }
      if (st.estimate_d()) r.Psi.row(row).segment(st.d_offset(j), nu) = u.row(t);
    }
  }
  return r;
}

namespace {

// The equation of every column of Psi (the equation of its nonzero rows); nullopt when a column
// is zero or has nonzero rows in two equations (not a regression canonical_regression builds).
std::optional<std::vector<int>> column_equations(const CanonicalRegression& reg) {
  if (static_cast<Eigen::Index>(reg.equation.size()) != reg.Psi.rows() || reg.y.size() != reg.Psi.rows())
    return std::nullopt;
  for (const int e : reg.equation)
    if (e < 0 || e >= reg.equations) return std::nullopt;
  std::vector<int> eq_of(static_cast<std::size_t>(reg.Psi.cols()), -1);
  for (Eigen::Index j = 0; j < reg.Psi.cols(); ++j) {
    int& e = eq_of[static_cast<std::size_t>(j)];
    for (Eigen::Index row = 0; row < reg.Psi.rows(); ++row) {
      if (reg.Psi(row, j) == 0) continue;
      const int here = reg.equation[static_cast<std::size_t>(row)];
      if (e >= 0 && e != here) return std::nullopt;
      e = here;
    }
    if (e < 0) return std::nullopt;
  }
  return eq_of;
}

}  // namespace

RegressionLeastSquares regression_least_squares(const CanonicalRegression& reg) {
  RegressionLeastSquares out;
  const Eigen::Index m = reg.Psi.cols();
  const std::optional<std::vector<int>> eq_of = column_equations(reg);
  if (!eq_of) {  // one QR of the whole Psi
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(reg.Psi);
    qr.setThreshold(least_squares_rank_threshold);
    out.rank = static_cast<int>(qr.rank());
    if (out.rank == m) out.theta = qr.solve(reg.y);
    return out;
  }
  out.theta = Eigen::VectorXd::Zero(m);
  std::vector<double> pivots;
  double max_pivot = 0;
  for (int e = 0; e < reg.equations; ++e) {
    std::vector<Eigen::Index> cols, rows;
    for (Eigen::Index j = 0; j < m; ++j)
      if ((*eq_of)[static_cast<std::size_t>(j)] == e) cols.push_back(j);
    if (cols.empty()) continue;
    for (Eigen::Index row = 0; row < reg.Psi.rows(); ++row)
      if (reg.equation[static_cast<std::size_t>(row)] == e) rows.push_back(row);
    const auto n_rows = static_cast<Eigen::Index>(rows.size()), n_cols = static_cast<Eigen::Index>(cols.size());
    Eigen::MatrixXd A(n_rows, n_cols);
    Eigen::VectorXd b(n_rows);
    for (Eigen::Index q = 0; q < n_cols; ++q)
      for (Eigen::Index k = 0; k < n_rows; ++k) A(k, q) = reg.Psi(rows[static_cast<std::size_t>(k)], cols[static_cast<std::size_t>(q)]);
    for (Eigen::Index k = 0; k < n_rows; ++k) b[k] = reg.y[rows[static_cast<std::size_t>(k)]];
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    qr.setThreshold(least_squares_rank_threshold);
    max_pivot = std::max(max_pivot, qr.maxPivot());
    for (Eigen::Index i = 0; i < std::min(n_rows, n_cols); ++i) pivots.push_back(std::abs(qr.matrixQR()(i, i)));
    if (n_rows < n_cols) continue;  // rank deficient: counted below
    const Eigen::VectorXd part = qr.solve(b);
    for (Eigen::Index q = 0; q < n_cols; ++q) out.theta[cols[static_cast<std::size_t>(q)]] = part[q];
  }
  const double threshold = least_squares_rank_threshold * max_pivot;
  out.rank = static_cast<int>(std::count_if(pivots.begin(), pivots.end(), [&](double d) { return d > threshold; }));
  if (out.rank < m) out.theta = Eigen::VectorXd();
  return out;
}

Eigen::MatrixXd past_input_regressor(const Eigen::Ref<const Eigen::MatrixXd>& u, int past, bool with_current) {
  const int N = static_cast<int>(u.rows()), nu = static_cast<int>(u.cols()), p = past;
  if (p < 1 || N <= p) throw InputError("past_input_regressor: need 1 <= p < N");
  Eigen::MatrixXd Z(N - p, nu * p + (with_current ? nu : 0));
  // Row k (time t = p + k) holds u(t - p + b) in block b: block column b is u(b .. b + N - p - 1),
  // copied block column by block column (Z is column-major; row by row missed the cache).
  for (int b = 0; b < p; ++b) Z.middleCols(b * nu, nu) = u.middleRows(b, N - p);
  if (with_current) Z.middleCols(p * nu, nu) = u.middleRows(p, N - p);
  return Z;
}

namespace {

void check_propagator_input(const Eigen::Ref<const Eigen::MatrixXd>& u, const Eigen::Ref<const Eigen::MatrixXd>& y,
                            const PropagatorOptions& o) {
  const int N = static_cast<int>(u.rows());
  const int nu = static_cast<int>(u.cols()), ny = static_cast<int>(y.cols());
  const int n = o.order, p = o.past;
  if (y.rows() != N) throw InputError("identify_propagator: u has " + std::to_string(N) + " samples, y has " + std::to_string(y.rows()));
  if (nu < 1 || ny < 1) throw InputError("identify_propagator: need at least one input and one output column");
  if (n < 1) throw InputError("order n_x = " + std::to_string(n) + ": must be at least 1");
  if (p < n)
    throw InputError("past horizon p = " + std::to_string(p) + " is smaller than the order n_x = " + std::to_string(n) +
                     " (the method needs p >= n_x)");
  if (n > ny * p || n > nu * p)
    throw InputError("order n_x = " + std::to_string(n) + " is larger than the data support: Gamma_p K has at most rank min(n_y p, n_u p) = " +
                     std::to_string(std::min(ny, nu) * p));
  check_finite(u, "input");
  check_finite(y, "output");
  const int cols = nu * p + (o.estimate_d ? nu : 0);
  if (N - p <= cols + 1)
    throw InputError("too few samples: N = " + std::to_string(N) + ", the least squares for [CK D] with p = " +
                     std::to_string(p) + " needs more than " + std::to_string(p + cols + 1));
  for (int m = 0; m < nu; ++m)
    if (u.col(m).maxCoeff() == u.col(m).minCoeff())
      throw InputError("input column " + std::to_string(m + 1) + " is constant (" + std::to_string(u(0, m)) +
                       "): a constant input does not excite the system, CK cannot be estimated");
}

// Step 1: y(t) = CK u_p(t) + D u(t), t = p .. N-1, by least squares on the past-input regressor Z.
void estimate_markov_parameters(const Eigen::MatrixXd& Z, int nu, const Eigen::Ref<const Eigen::MatrixXd>& y,
                                const PropagatorOptions& o, PropagatorResult& r) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Z);
  qr.setThreshold(least_squares_rank_threshold);
  if (qr.rank() < Z.cols())
    throw InputError("the inputs are not persistently exciting of order p = " + std::to_string(o.past) +
                     ": the regressor [u_p; u] has rank " + std::to_string(qr.rank()) + " < " + std::to_string(Z.cols()));
  const Eigen::MatrixXd Theta = qr.solve(y.bottomRows(Z.rows()));
  r.markov = Theta.topRows(nu * o.past).transpose();
  r.d = o.estimate_d ? Eigen::MatrixXd(Theta.bottomRows(nu).transpose()) : Eigen::MatrixXd::Zero(y.cols(), nu);
}

// Step 2: block-upper-triangular Gamma_p K, block (i, k) = CA^{p-1-(k-i)} B = markov block k-i,
// and its singular values; returns the absolute rank tolerance.
double build_gamma_k(const PropagatorOptions& o, PropagatorResult& r) {
  const int p = o.past, ny = static_cast<int>(r.markov.rows()), nu = static_cast<int>(r.markov.cols()) / p;
  r.gamma_k = Eigen::MatrixXd::Zero(ny * p, nu * p);
  for (int i = 0; i < p; ++i)
    for (int k = i; k < p; ++k) r.gamma_k.block(i * ny, k * nu, ny, nu) = r.markov.block(0, (k - i) * nu, ny, nu);
  // Singular values only: BDCSVD (bidiagonalisation, then divide and conquer) is several times faster
  // than Jacobi rotations on the (p ny) x (p nu) matrix.
  r.gamma_k_singular_values = Eigen::BDCSVD<Eigen::MatrixXd>(r.gamma_k).singularValues();
  const auto& s = r.gamma_k_singular_values;
  const double abs_tol = o.rank_tolerance * s(0);
  const int rank = s(0) > 0 ? static_cast<int>((s.array() > abs_tol).count()) : 0;
  if (rank < o.order)
    throw InputError("order n_x = " + std::to_string(o.order) + " is larger than the data support: Gamma_p K^ has numerical rank " +
                     std::to_string(rank) + " (relative tolerance " + std::to_string(o.rank_tolerance) + ")");
  return abs_tol;
}

// Step 3a: the independent rows of Gamma_p K^, chosen greedily or given.
std::vector<ObservabilityRow> observability_rows(const PropagatorOptions& o, const PropagatorResult& r, double abs_tol) {
  const int n = o.order, p = o.past, ny = static_cast<int>(r.markov.rows());
  if (o.rows.empty()) {
    auto row = [&](int lag, int j) -> Eigen::RowVectorXd { return r.gamma_k.row(lag * ny + j); };
    auto rows = greedy_rows(row, n, ny, p - 2, o.selection, abs_tol);
    if (static_cast<int>(rows.size()) < n)
      throw InputError("order n_x = " + std::to_string(n) + " is larger than the data support: only " +
                       std::to_string(rows.size()) + " independent rows found in Gamma_p K^");
    return rows;
  }
  if (static_cast<int>(o.rows.size()) != n)
    throw InputError(std::to_string(o.rows.size()) + " observability rows given for order n_x = " + std::to_string(n));
  for (const auto& rw : o.rows)
    if (rw.lag < 0 || rw.lag > p - 2 || rw.output < 0 || rw.output >= ny)
      throw InputError("observability row " + to_string(rw) + " is outside lags 0.." + std::to_string(p - 2) +
                       " and outputs 1.." + std::to_string(ny));
  return o.rows;
}

// Step 3b: the propagator P (the other rows of Gamma_p K^ from the chosen ones G1) and the states
// x^(t) = G1 u_p(t); returns the other rows' indices (lag * ny + output), in P's row order.
std::vector<int> propagate(const Eigen::MatrixXd& Z, int p, double abs_tol, PropagatorResult& r) {
  const int n = static_cast<int>(r.rows.size()), ny = static_cast<int>(r.markov.rows());
  const Eigen::Index past_cols = r.gamma_k.cols();
  Eigen::MatrixXd G1(n, past_cols);
  for (int k = 0; k < n; ++k) G1.row(k) = r.gamma_k.row(r.rows[k].lag * ny + r.rows[k].output);
  if (smallest_singular_value(G1) <= abs_tol)
    throw InputError("the chosen observability rows are dependent in Gamma_p K^ (or the order exceeds the data support)");
  std::vector<int> other;
  for (int l = 0; l < p; ++l)
    for (int j = 0; j < ny; ++j)
      if (find_row(r.rows, {l, j}) < 0) other.push_back(l * ny + j);
  Eigen::MatrixXd G2(other.size(), past_cols);
  for (std::size_t k = 0; k < other.size(); ++k) G2.row(k) = r.gamma_k.row(other[k]);
  const Eigen::MatrixXd G1G1t = G1 * G1.transpose();
  r.propagator = G1G1t.ldlt().solve(G1 * G2.transpose()).transpose();
  r.states = G1 * Z.leftCols(past_cols).transpose();
  r.first_state = p;
  return other;
}

// Equation (6): A_c and C_c of the propagator model read directly from [I; P].
void read_propagator_model(const std::vector<int>& other, PropagatorResult& r) {
  const int n = static_cast<int>(r.rows.size()), ny = static_cast<int>(r.markov.rows());
  auto ip_row = [&](int lag, int j) -> Eigen::RowVectorXd {
    const int k = find_row(r.rows, {lag, j});
    if (k >= 0) return Eigen::RowVectorXd::Unit(n, k);
    const auto it = std::find(other.begin(), other.end(), lag * ny + j);
    return r.propagator.row(it - other.begin());
  };
  r.propagator_model = r.model;
  for (int i = 0; i < n; ++i) r.propagator_model.A.row(i) = ip_row(r.rows[i].lag + 1, r.rows[i].output);
  for (int j = 0; j < ny; ++j) r.propagator_model.C.row(j) = ip_row(0, j);
}

}  // namespace

PropagatorResult identify_propagator(const Eigen::Ref<const Eigen::MatrixXd>& u,
                                     const Eigen::Ref<const Eigen::MatrixXd>& y, const PropagatorOptions& o) {
  check_propagator_input(u, y, o);
  const int nu = static_cast<int>(u.cols()), ny = static_cast<int>(y.cols()), p = o.past;
  const Eigen::MatrixXd Z = past_input_regressor(u, p, o.estimate_d);
  PropagatorResult r;
  estimate_markov_parameters(Z, nu, y, o, r);
  const double abs_tol = build_gamma_k(o, r);
  r.rows = observability_rows(o, r, abs_tol);
  r.structure = CanonicalStructure(r.rows, nu, ny, o.estimate_d);
  const std::vector<int> other = propagate(Z, p, abs_tol, r);

  // Step 4: least squares for theta~.
  r.regression = canonical_regression(r.structure, r.states, p, u, y);
  const RegressionLeastSquares ls = regression_least_squares(r.regression);
  if (ls.rank < r.structure.parameter_count())
    throw InputError("the canonical parameters are not identifiable from these data: regressor rank " +
                     std::to_string(ls.rank) + " < " + std::to_string(r.structure.parameter_count()));
  r.theta = ls.theta;
  r.model = r.structure.to_model(r.theta);
  read_propagator_model(other, r);
  return r;
}

}  // namespace sets
