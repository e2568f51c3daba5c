#pragma once
// Interval vectors (boxes) and interval matrices as Eigen objects.
//
// Eigen's arithmetic on these types uses the outward-rounded scalar operations, so products and
// sums are enclosures. Do not call Eigen's decompositions on them (they compare and divide in
// ways that are meaningless for intervals).

#include <Eigen/Core>

#include "sets/numeric/interval.hpp"

namespace Eigen {
template <>
struct NumTraits<sets::Interval> : GenericNumTraits<sets::Interval> {
  using Real = sets::Interval;
  using NonInteger = sets::Interval;
  using Nested = sets::Interval;
  using Literal = sets::Interval;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 2,
    AddCost = 8,
    MulCost = 16
  };
  static inline Real epsilon() { return Real(std::numeric_limits<double>::epsilon()); }
  static inline Real dummy_precision() { return Real(1e-12); }
  static inline int digits10() { return std::numeric_limits<double>::digits10; }
};
}  // namespace Eigen

namespace sets {

using IntervalVector = Eigen::Matrix<Interval, Eigen::Dynamic, 1>;
using IntervalMatrix = Eigen::Matrix<Interval, Eigen::Dynamic, Eigen::Dynamic>;

/// Degenerate interval vector/matrix holding exactly the given doubles (a vector gives an
/// IntervalVector, a matrix an IntervalMatrix; one template, so no overload is ambiguous).
template <typename Derived>
Eigen::Matrix<Interval, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> to_interval(
    const Eigen::MatrixBase<Derived>& x) {
  return x.template cast<Interval>();
}

Eigen::VectorXd lower(const IntervalVector& x);
Eigen::VectorXd upper(const IntervalVector& x);
// midpoint() and radius() of every entry, bit for bit the scalar ones, with one rounding-mode
// switch per call instead of several per entry.
Eigen::VectorXd midpoint(const IntervalVector& x);
Eigen::VectorXd radius(const IntervalVector& x);  // rounded up
Eigen::MatrixXd lower(const IntervalMatrix& x);
Eigen::MatrixXd upper(const IntervalMatrix& x);
Eigen::MatrixXd midpoint(const IntervalMatrix& x);
Eigen::MatrixXd radius(const IntervalMatrix& x);  // rounded up

/// Box [lo, hi]; throws InputError if lo > hi somewhere or a bound is NaN.
IntervalVector make_box(const Eigen::Ref<const Eigen::VectorXd>& lo,
                        const Eigen::Ref<const Eigen::VectorXd>& hi);

/// Outward-rounded enclosure of A x for interval or real operands (mixed products included).
IntervalVector multiply(const IntervalMatrix& A, const IntervalVector& x);
// `const MatrixXd&`, not Ref: an exact match beside the IntervalMatrix overload (a Ref would make
// calls with a MatrixXd ambiguous, Eigen converting it to either).
IntervalVector multiply(const Eigen::MatrixXd& A, const IntervalVector& x);

/// Does the box contain the point? (Closed box, exact comparison of doubles.)
bool contains(const IntervalVector& box, const Eigen::Ref<const Eigen::VectorXd>& x);
/// Interval hull of two boxes of equal dimension.
IntervalVector hull(const IntervalVector& a, const IntervalVector& b);
/// Product of the widths (rounded up).
double volume(const IntervalVector& box);

}  // namespace sets
