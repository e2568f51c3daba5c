#pragma once
// Three-valued truth for predicates that floating point cannot always decide.

#include <iosfwd>

namespace sets {

/// `yes` and `no` are certain; `unknown` means the computation could not decide (for example a
/// point within rounding error of a boundary). Never turn `unknown` into a guess.
enum class BoolInterval { no = 0, yes = 1, unknown = 2 };

inline BoolInterval operator&&(BoolInterval a, BoolInterval b) {
  if (a == BoolInterval::no || b == BoolInterval::no) return BoolInterval::no;
  if (a == BoolInterval::yes && b == BoolInterval::yes) return BoolInterval::yes;
  return BoolInterval::unknown;
}
inline BoolInterval operator||(BoolInterval a, BoolInterval b) {
  if (a == BoolInterval::yes || b == BoolInterval::yes) return BoolInterval::yes;
  if (a == BoolInterval::no && b == BoolInterval::no) return BoolInterval::no;
  return BoolInterval::unknown;
}
inline BoolInterval operator!(BoolInterval a) {
  if (a == BoolInterval::unknown) return a;
  return a == BoolInterval::yes ? BoolInterval::no : BoolInterval::yes;
}
inline BoolInterval to_bool_interval(bool b) { return b ? BoolInterval::yes : BoolInterval::no; }

const char* to_string(BoolInterval b);
std::ostream& operator<<(std::ostream& os, BoolInterval b);

}  // namespace sets
