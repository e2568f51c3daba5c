#pragma once
// Outward-rounded intervals: the scalar of every guaranteed computation in `sets`.
//
// Why a custom policy: Boost's default `interval<double>` rounds + - * / sqrt correctly, but its
// transcendental functions either do not exist (rounded_transc_dummy) or call libm under a
// directed rounding mode (rounded_transc_std), and libm does not promise a directed result.
// `WidenedTransc` calls libm (in round-to-nearest) and then steps the result outward by `transc_ulps` units in the last
// place, which is rigorous given glibc's documented error bound (< 2 ulp for exp, log, sin, cos,
// tan, atan, sinh, cosh, tanh, asin, acos).
//
// Build requirement: every translation unit that uses these types must be compiled with
// `-frounding-math` (the `sets::sets` target exports it), otherwise GCC may fold or move
// floating-point operations across rounding-mode changes at -O2/-O3.

#include <boost/numeric/interval.hpp>

#include <cmath>
#include <iosfwd>
#include <limits>
#include <string>

namespace sets {

namespace detail {

inline constexpr int transc_ulps = 4;

inline double step_down(double x, int n = transc_ulps) {
  for (int i = 0; i < n; ++i) x = std::nextafter(x, -std::numeric_limits<double>::infinity());
  return x;
}
inline double step_up(double x, int n = transc_ulps) {
  for (int i = 0; i < n; ++i) x = std::nextafter(x, std::numeric_limits<double>::infinity());
  return x;
}

template <class T, class Rounding>
struct WidenedTransc : Rounding {
#define SETS_WIDENED(f, lo_clamp, hi_clamp)                                           \
  T f##_down(const T& x) {                                                            \
    this->to_nearest();                                                               \
    T r = step_down(this->force_rounding(std::f(x)));                                 \
    this->upward();                                                                   \
    return r < (lo_clamp) ? T(lo_clamp) : r;                                          \
  }                                                                                   \
  T f##_up(const T& x) {                                                              \
    this->to_nearest();                                                               \
    T r = step_up(this->force_rounding(std::f(x)));                                   \
    this->upward();                                                                   \
    return r > (hi_clamp) ? T(hi_clamp) : r;                                          \
  }
  static constexpr T inf = std::numeric_limits<T>::infinity();
  SETS_WIDENED(exp, 0.0, inf)
  SETS_WIDENED(log, -inf, inf)
  SETS_WIDENED(sin, -1.0, 1.0)
  SETS_WIDENED(cos, -1.0, 1.0)
  SETS_WIDENED(tan, -inf, inf)
  SETS_WIDENED(asin, -inf, inf)
  SETS_WIDENED(acos, 0.0, inf)
  SETS_WIDENED(atan, -inf, inf)
  SETS_WIDENED(sinh, -inf, inf)
  SETS_WIDENED(cosh, 1.0, inf)
  SETS_WIDENED(tanh, -1.0, 1.0)
  SETS_WIDENED(asinh, -inf, inf)
  SETS_WIDENED(acosh, 0.0, inf)
  SETS_WIDENED(atanh, -inf, inf)
#undef SETS_WIDENED
};

namespace bi = boost::numeric::interval_lib;
// rounded_arith_opp keeps the FPU in upward mode and gets downward results by negation
// (down(a/b) = -((-a)/b)). rounded_arith_std instead switches modes between two identical
// expressions, which GCC merges at -O2 even with -frounding-math (both ends of 1/3 came out
// equal in our test): never use it.
using Rounding = bi::save_state<WidenedTransc<double, bi::rounded_arith_opp<double>>>;
// Comparisons of overlapping intervals throw instead of guessing; use `certainly_*` and
// `possibly_*` (or BoolInterval) where a comparison may be undecided.
using Policies = bi::policies<Rounding, bi::checking_base<double>>;

}  // namespace detail

/// A closed interval [lo, hi] of reals, with every operation rounded outward.
using Interval = boost::numeric::interval<double, detail::Policies>;

/// Interval arithmetic for a block of work with ONE rounding-mode switch instead of one per
/// operation. Every `Interval` operation saves the FPU mode, sets it upward and restores it
/// (fegetround + 2 fesetround): for short operations that is most of the cost (perf in
/// docs/performance.md). Usage:
///
///     RoundingScope upward;                 // FPU rounds upward until the end of the block
///     UnprotectedInterval s(0.0);
///     for (...) s += UnprotectedInterval(a[i]) * x[i];
///     Interval result = s;                  // back to the protected type (no switch)
///
/// Rules: UnprotectedInterval operations are enclosures only while a RoundingScope is alive on
/// this thread (they assume upward rounding); keep the block to interval work, since plain
/// double arithmetic, Eigen, libm and GLPK inside it round upward too. Protected `Interval`
/// operations inside the block stay correct (they save and restore the mode themselves).
class RoundingScope {
 public:
  RoundingScope() = default;
  RoundingScope(const RoundingScope&) = delete;
  RoundingScope& operator=(const RoundingScope&) = delete;

 private:
  Interval::traits_type::rounding mode_;  // saves the mode and sets upward; restores it at the end
};
using UnprotectedInterval = boost::numeric::interval_lib::unprotect<Interval>::type;

/// The smallest interval that contains the decimal or real number written in `text`.
/// ("0.1" is not a double; a guaranteed computation must start from an enclosure of it.)
Interval interval_from_string(const std::string& text);

/// Interval [x - r, x + r], rounded outward.
Interval interval_around(double x, double r);

/// The interval hull of two intervals.
inline Interval hull(const Interval& a, const Interval& b) { return boost::numeric::hull(a, b); }

/// x^n for integer n >= 0, tight: even powers of an interval that contains 0 start at 0.
inline Interval pow(const Interval& x, int n) { return boost::numeric::pow(x, n); }

/// Outward-rounded real power x^p for p real and x >= 0 (exp(p log x)).
Interval pow(const Interval& x, const Interval& p);

double midpoint(const Interval& x);
double radius(const Interval& x);  // rounded up: [mid - rad, mid + rad] contains x

/// "[lo, hi]" with enough digits to round-trip. (Interval is a Boost type, so the stream
/// operator below is found only inside namespace sets or with `using sets::operator<<;`.)
std::string to_string(const Interval& x);
std::ostream& operator<<(std::ostream& os, const Interval& x);

}  // namespace sets
