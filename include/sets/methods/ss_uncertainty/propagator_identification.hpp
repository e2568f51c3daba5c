#pragma once
// Propagator subspace least squares (Farah, Mercère, Poinot, van Wingerden, Section III).
//
//   1. Least squares for [CK D] from y(t) ~ CK u_p(t) + D u(t), u_p(t) = [u(t-p); ...; u(t-1)].
//   2. Gamma_p K from the block-upper-triangular approximation (4) (A^j = 0 for j >= p).
//   3. A choice of n_x independent rows of Gamma_p (made explicit, see ObservabilityRow), the
//      propagator P with Gamma_2 K = P Gamma_1 K, and the state x_hat(t) = Gamma_1 K u_p(t) (5).
//   4. The observable canonical form (6) in the coordinates x_c = Gamma_1 x and the least-squares
//      estimate of its free parameters theta~ (Remark 1) from the linear regression
//        x_hat(t+1) = A_c x_hat(t) + B_c u(t),   y(t) = C_c x_hat(t) + D_c u(t).
//
// Indices: time t and the rows/columns of every matrix are 0-based; parameter *names* follow the
// paper ("-a0", "c0^2", "b0^1": b_i^j = B_c(i, j-1), c_k^j = C_c(j-1, k)).

#include <Eigen/Core>

#include <string>
#include <vector>

#include "sets/models/state_space_model.hpp"

namespace sets {

/// One row of the extended observability matrix Gamma_p: output `output` at lag `lag`
/// (the row C(output,:) A^lag).
struct ObservabilityRow {
  int lag = 0;
  int output = 0;
  friend bool operator==(const ObservabilityRow&, const ObservabilityRow&) = default;
};

/// How the n_x independent rows are chosen when the user does not list them.
enum class RowSelection {
  output_major,  // all lags of output 0, then output 1, ... (the paper's choice: c1, c1 A, c1 A^2)
  lag_major      // lag 0 of every output, then lag 1, ... (Luenberger's observability indices)
};

/// The observable canonical form implied by a row selection: x_c = Gamma_1 x. Row i of A_c is the
/// unit row e_k when the shifted row (lag+1, output) is selected row k, otherwise free; row j of
/// C_c is e_k when (0, j) is selected row k, otherwise free. B_c is free; D_c is free or zero.
class CanonicalStructure {
 public:
  CanonicalStructure() = default;
  CanonicalStructure(std::vector<ObservabilityRow> rows, int nu, int ny, bool estimate_d);

  int nx() const { return static_cast<int>(rows_.size()); }
  int nu() const { return nu_; }
  int ny() const { return ny_; }
  bool estimate_d() const { return estimate_d_; }
  const std::vector<ObservabilityRow>& rows() const { return rows_; }
  /// Column of the unit row of A_c(i,:) / C_c(j,:), or -1 when the row is free.
  int a_unit(int i) const { return a_unit_[i]; }
  int c_unit(int j) const { return c_unit_[j]; }

  /// theta~ = [free rows of A_c (row-major); free rows of C_c; B_c (row-major); D_c (row-major)].
  int parameter_count() const;
  std::vector<std::string> parameter_names() const;
  StateSpaceModel to_model(const Eigen::Ref<const Eigen::VectorXd>& theta) const;
  /// Reads the free entries of a model already in this canonical form.
  Eigen::VectorXd to_parameters(const StateSpaceModel& canonical) const;

  // Column of the first parameter of each free block in theta~ (-1 when the row is fixed).
  int a_offset(int i) const { return a_offset_[i]; }
  int c_offset(int j) const { return c_offset_[j]; }
  int b_offset(int i) const { return b0_ + i * nu_; }
  int d_offset(int j) const { return estimate_d_ ? d0_ + j * nu_ : -1; }

 private:
  std::vector<ObservabilityRow> rows_;
  int nu_ = 0, ny_ = 0;
  bool estimate_d_ = false;
  std::vector<int> a_unit_, c_unit_, a_offset_, c_offset_;
  int b0_ = 0, d0_ = 0, count_ = 0;
};

/// Rank of the observability matrix [C; CA; ...; CA^{n-1}] (SVD, relative tolerance).
int observability_rank(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& C,
                       double rel_tol = 1e-10);

/// Rows chosen by `selection` on a known system: throws InputError when (A, C) is not observable.
std::vector<ObservabilityRow> select_rows(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                          const Eigen::Ref<const Eigen::MatrixXd>& C, RowSelection selection);

/// The canonical form of a known system under a row selection (T = Gamma_1: A_c = T A T^-1,
/// B_c = T B, C_c = C T^-1, D_c = D). Throws InputError if (A, C) is not observable or the
/// chosen rows are dependent.
StateSpaceModel canonical_form(const StateSpaceModel& system, const std::vector<ObservabilityRow>& rows);

/// The linear regression y_M = Psi theta~ + eps of Remark 1, one row per (sample, equation).
/// Equations 0..nx-1 are the state rows, nx..nx+ny-1 the output rows. Rows whose regressor is
/// all zero (a unit row of C_c with D_c known to be zero) are kept: they carry a residual only.
struct CanonicalRegression {
  Eigen::MatrixXd Psi;
  Eigen::VectorXd y;
  std::vector<int> equation;  // per row
  std::vector<int> sample;    // per row: the time t of x_hat(t), u(t), y(t)
  int equations = 0;          // nx + ny
  int state_equations = 0;    // nx
};

/// Builds the regression from a state sequence: states.col(k) = x(first + k), k = 0..K-1;
/// u and y are N x nu and N x ny (time along rows). Uses t = first .. first+K-2.
CanonicalRegression canonical_regression(const CanonicalStructure& structure,
                                         const Eigen::Ref<const Eigen::MatrixXd>& states, int first,
                                         const Eigen::Ref<const Eigen::MatrixXd>& u,
                                         const Eigen::Ref<const Eigen::MatrixXd>& y);

/// The regressor of step 1: row k = [u_p(t)^T, u(t)^T] for t = p + k, k = 0..N-p-1, with
/// u_p(t) = [u(t-p); ...; u(t-1)] and the u(t) block only `with_current` (D estimated).
Eigen::MatrixXd past_input_regressor(const Eigen::Ref<const Eigen::MatrixXd>& u, int past, bool with_current);

/// Relative threshold of the rank decisions of the column-pivoted QR least squares (step 1 and
/// theta~): level_set_domain(regression) repeats the theta~ one with the same threshold.
inline constexpr double least_squares_rank_threshold = 1e-10;

/// The least-squares theta~ of a regression, and the rank of Psi. Every parameter of a
/// canonical regression belongs to one equation (a row of A_c, B_c, C_c or D_c), so Psi is block
/// diagonal up to the order of rows and columns: one column-pivoted QR per equation's block. The
/// rank is Psi's (the blocks' pivots are those of a pivoted QR of Psi, whose columns of different
/// blocks are orthogonal), counted against least_squares_rank_threshold times the largest pivot.
/// A Psi whose columns mix equations gets one QR of the whole. theta is empty when rank < cols.
struct RegressionLeastSquares {
  Eigen::VectorXd theta;
  int rank = 0;
};
RegressionLeastSquares regression_least_squares(const CanonicalRegression& regression);

struct PropagatorOptions {
  int order = 0;                      // n_x
  int past = 20;                      // p >= n_x
  bool estimate_d = false;            // false: D = 0 is known
  std::vector<ObservabilityRow> rows; // explicit choice; empty: automatic by `selection`
  RowSelection selection = RowSelection::output_major;
  double rank_tolerance = 1e-8;       // relative singular-value tolerance for rank decisions
};

struct PropagatorResult {
  Eigen::MatrixXd markov;      // CK^ = [CA^{p-1}B ... CB], ny x nu p
  Eigen::MatrixXd d;           // D^ of step 1 (zero when D is known)
  Eigen::MatrixXd gamma_k;     // Gamma_p K^ of (4), ny p x nu p (row lag*ny + output)
  Eigen::VectorXd gamma_k_singular_values;
  std::vector<ObservabilityRow> rows;
  Eigen::MatrixXd propagator;  // P, (ny p - nx) x nx, rows in Gamma_p order without the selected
  StateSpaceModel propagator_model;  // A_c, C_c read from [I; P] as in (6); B_c, D_c from theta~
  Eigen::MatrixXd states;      // x_hat(t) for t = first_state + k, nx x (N - p)
  int first_state = 0;
  CanonicalStructure structure;
  CanonicalRegression regression;
  Eigen::VectorXd theta;       // least-squares theta~
  StateSpaceModel model;       // canonical model from theta~
};

/// Identifies a model from input/output data u (N x nu) and y (N x ny), time along rows.
/// Throws InputError for p < n_x, too few samples, constant or non-exciting inputs, an order the
/// data do not support (rank of Gamma_p K^ below n_x) and dependent user rows.
PropagatorResult identify_propagator(const Eigen::Ref<const Eigen::MatrixXd>& u,
                                     const Eigen::Ref<const Eigen::MatrixXd>& y, const PropagatorOptions& options);

std::string to_string(const ObservabilityRow& row);  // "y1[t+0]" (1-based output)

}  // namespace sets
