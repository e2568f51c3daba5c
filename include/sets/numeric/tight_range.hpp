#pragma once
// Tight, guaranteed ranges of univariate functions over an interval.
//
// The natural interval extension of f (evaluate f's formula in interval arithmetic) always
// encloses {f(x) : x in X} but can be far too wide (x - x over [0,1] gives [-1,1]). Cerone and
// Regruto's regressor bounds (eqs. 23–24) need the *range* itself, so this header provides:
//   - exact ranges (up to outward rounding) of monotone functions and of polynomials of degree
//     <= 2 (e.g. lambda^2 over an interval that contains 0 is [0, max(a^2, b^2)], not [-ab, ..]);
//   - a branch-and-bound subdivision for everything else: the interval is split until each end
//     of the enclosure is within a tolerance of the true extremum. Pieces on which the derivative
//     enclosure has one sign are monotone and get their exact range from the two end values.
// Whatever the tolerance or piece budget, the result is an enclosure; the tolerance only says
// how tight it is.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sets/numeric/interval.hpp"

namespace sets {

struct RangeOptions {
  /// Each end is within tolerance * max(1, |end|) of the true extremum (when `tight`).
  double tolerance = 1e-10;
  /// Subdivision budget; when exhausted the (still guaranteed) enclosure is returned untight.
  int max_pieces = 4096;
};

struct RangeResult {
  Interval range;
  bool tight = false;  // both ends within the tolerance of the true extrema
  int pieces = 1;      // pieces examined
};

using RealFunction = std::function<double(double)>;
using IntervalFunction = std::function<Interval(const Interval&)>;

/// Branch-and-bound range of f over X. `extension` must enclose f on every interval; the optional
/// `derivative` must enclose f' (it lets monotone pieces be resolved exactly).
RangeResult branch_and_bound_range(const IntervalFunction& extension, const IntervalFunction& derivative,
                                   const Interval& X, const RangeOptions& options = {});

/// Range of the polynomial sum_k c[k] x^k over X: exact for monomials and degree <= 2, otherwise
/// branch and bound with the exact derivative.
RangeResult polynomial_range(const std::vector<double>& c, const Interval& X, const RangeOptions& options = {});

/// A real function of one variable with a guaranteed interval extension and a tight range.
/// Built-ins cover polynomials and the usual monotone / periodic functions; users can supply
/// their own (value + interval extension, optionally the derivative's extension or a monotonicity
/// promise).
class UnivariateFunction {
 public:
  enum class Shape { general, increasing, decreasing, polynomial };

  /// sum_k c[k] x^k (c[0] first).
  static UnivariateFunction polynomial(std::vector<double> c, std::string name = "");
  /// x^n, n >= 0.
  static UnivariateFunction monomial(int n);
  /// Non-decreasing (`increasing` true) or non-increasing f: its range is [f(lo), f(hi)] (or reversed).
  static UnivariateFunction monotone(std::string name, RealFunction value, IntervalFunction extension,
                                     bool increasing);
  /// Any f: range by branch and bound; give the derivative's extension when you have it.
  static UnivariateFunction general(std::string name, RealFunction value, IntervalFunction extension,
                                    IntervalFunction derivative = {});
  /// sin, cos, exp, tanh, atan (outward-rounded extensions from interval.hpp).
  static UnivariateFunction builtin(const std::string& name);
  /// f * g of the same variable (polynomials multiply exactly; otherwise a general function).
  static UnivariateFunction product(const UnivariateFunction& f, const UnivariateFunction& g);

  double operator()(double x) const { return value_(x); }
  /// Natural enclosure (possibly wide); use `range` for the tight one.
  Interval extension(const Interval& X) const { return extension_(X); }
  /// Guaranteed enclosure of {f(x) : x in X}, tight to options.tolerance.
  RangeResult range(const Interval& X, const RangeOptions& options = {}) const;

  const std::string& name() const { return name_; }
  Shape shape() const { return shape_; }
  const std::vector<double>& coefficients() const { return coeffs_; }  // polynomials only
  bool has_derivative() const { return static_cast<bool>(derivative_); }
  Interval derivative(const Interval& X) const { return derivative_(X); }

 private:
  std::string name_;
  Shape shape_ = Shape::general;
  RealFunction value_;
  IntervalFunction extension_, derivative_;
  std::vector<double> coeffs_;
};

}  // namespace sets
