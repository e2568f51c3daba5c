#pragma once
// SISO LPV input-output models with bounded errors on the output AND on the scheduling signal
// (Cerone & Regruto, "Set-membership identification of LPV models with uncertain measurements of
// the time-varying parameter").
//
//   A(q^-1, lambda_t) w_t = B(q^-1, lambda_t) u_t,   y_t = w_t + eta_t,  r_t = lambda_t + eps_t,
//   a_i(lambda) = sum_k a_{i,k} f_{i,k}(lambda),      b_j(lambda) = sum_h b_{j,h} g_{j,h}(lambda),
//
// with |eta_t| <= Delta_eta_t and |eps_{s,t}| <= Delta_eps_{s,t}. Every coefficient is evaluated at
// lambda_t (eq. 13). The regressor phi_t = [-w_{t-i} f_{i,k}(lambda_t) ..., u_{t-j} g_{j,h}(lambda_t) ...]
// is only known to lie in a box: w_{t-i} in [y -+ Delta_eta] (eq. 20), f(lambda_t) in its tight range
// over the lambda box (eqs. 21–24), and rho, gamma by interval products (eqs. 25–26; exact, since
// the two factors vary independently). This header is the model: its structure, the interval
// regression it defines and a simulator; the method (PUIs, eqs. 27–42) is in
// sets/methods/lpv_pui/lpv_pui.hpp.

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "sets/numeric/interval_matrix.hpp"
#include "sets/numeric/tight_range.hpp"

namespace sets {

/// A basis function of the scheduling vector lambda in R^alpha: scale * prod_s f_s(lambda_s)
/// (each component at most once), or a user-supplied multivariate function. Its range over a
/// box is exact for products of polynomials/monotone factors (the factors vary independently),
/// otherwise tight to RangeOptions::tolerance by subdivision.
class BasisFunction {
 public:
  /// The constant 1.
  BasisFunction() = default;
  /// f(lambda_component), component counted from 0.
  static BasisFunction of(int component, UnivariateFunction f);
  /// lambda_component^n.
  static BasisFunction power(int component, int n);
  /// Any function of lambda with an enclosure over boxes; its range is found by bisection.
  static BasisFunction custom(std::string name, std::function<double(const Eigen::VectorXd&)> value,
                              std::function<Interval(const IntervalVector&)> extension);

  /// Product of two basis functions; factors of the same component are merged into one
  /// univariate function (so lambda * lambda is lambda^2, with its exact range).
  friend BasisFunction operator*(const BasisFunction& a, const BasisFunction& b);
  BasisFunction scaled(double c) const;

  double operator()(const Eigen::Ref<const Eigen::VectorXd>& lambda) const;
  /// Guaranteed enclosure of {f(lambda) : lambda in box}.
  Interval range(const IntervalVector& box, const RangeOptions& options = {}) const;
  /// Largest scheduling component used (-1 for a constant).
  int max_component() const;
  std::string name(int alpha = 1) const;

 private:
  struct Factor {
    int component;
    UnivariateFunction f;
  };
  double scale_ = 1;
  std::vector<Factor> factors_;  // sorted by component, each component once
  std::string custom_name_;
  std::function<double(const Eigen::VectorXd&)> custom_value_;
  std::function<Interval(const IntervalVector&)> custom_extension_;
};

/// Parses a basis function: factors joined by '*', each a number, `1`, a scheduling variable
/// (`lambda`/`l` when alpha = 1, or `l1`, `l2`, ..., `lambda1`, ...) with an optional `^n`, or a
/// built-in function of one variable: sin, cos, exp, tanh, atan (e.g. "l1^2*sin(l2)").
BasisFunction parse_basis_function(const std::string& text, int alpha);

/// Orders, scheduling dimension and the basis of every coefficient.
struct LpvModelStructure {
  int alpha = 1;                              // dimension of lambda
  std::vector<std::vector<BasisFunction>> a;  // a[i-1]: basis f_{i,k} of a_i, i = 1..na
  std::vector<std::vector<BasisFunction>> b;  // b[j]: basis g_{j,h} of b_j, j = 0..nb (may be empty)

  int na() const { return static_cast<int>(a.size()); }
  int nb() const { return static_cast<int>(b.size()) - 1; }
  int num_parameters() const;
  /// First sample index with a complete regression: max(na, nb).
  int first_regression() const;
  /// "a1,1[lambda]" ... "b2,2[lambda^2]": theta's ordering (eq. 11).
  std::vector<std::string> parameter_names() const;
  /// Throws InputError if alpha < 1, no parameter, or a basis uses a component >= alpha.
  void validate() const;
};

/// Parses a structure from JSON text:
///   {"alpha": 1, "a": [["lambda"], ["1", "lambda^2"]], "b": [[], ["1"], ["lambda", "lambda^2"]]}
/// (`na`/`nb` are implied by the lengths; `source` names the file in messages).
LpvModelStructure parse_lpv_structure_json(const std::string& text, const std::string& source = "model");

/// Measurements of length T: u, y, r (T x alpha), and the error bounds (a single row/entry
/// applies to every sample).
struct LpvMeasurements {
  Eigen::VectorXd u, y;
  Eigen::MatrixXd r;
  Eigen::VectorXd delta_eta;  // size T or 1
  Eigen::MatrixXd delta_eps;  // T x alpha or 1 x alpha
};

/// The interval regression of eqs. 18–34.
struct LpvRegression {
  IntervalMatrix Phi;        // N x p regressor boxes (rho, gamma; eqs. 25–26)
  IntervalVector Y;          // N outputs [y_t - Delta_eta_t, y_t + Delta_eta_t]
  Eigen::MatrixXd central;   // N x p central regressors (eq. 33)
  Eigen::MatrixXd radius;    // N x p radii Delta phi (eqs. 29–31), rounded up
  std::vector<int> time;     // sample index t (0-based) of each row
  bool all_ranges_tight = true;  // every basis range reached its tolerance
};

/// Builds the interval regression. Throws InputError (naming sample and field) on NaN/inf data,
/// negative bounds, size mismatches, or fewer regressions than parameters.
LpvRegression lpv_regression(const LpvModelStructure& model, const LpvMeasurements& data,
                             const RangeOptions& range = {});

/// Noise-free simulation of eq. (2) from zero initial conditions: w (length T) for inputs u
/// (length T) and scheduling lambda (T x alpha).
Eigen::VectorXd simulate_lpv(const LpvModelStructure& model, const Eigen::Ref<const Eigen::VectorXd>& theta,
                             const Eigen::Ref<const Eigen::VectorXd>& u, const Eigen::Ref<const Eigen::MatrixXd>& lambda);

}  // namespace sets
