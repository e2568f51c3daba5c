#pragma once
// "Do the data falsify the model?" — the one three-valued verdict every method reports.
//
// A wrong "the data falsify the model" is the worst answer this library can give (the apps turn
// it into exit code 2 and the user throws the model away), so `yes` needs a proof that holds in
// exact arithmetic, and so does `no`:
//   yes      an infeasibility (Farkas) certificate checked in exact rational arithmetic on the
//            stored double data (see sets/numeric/lp_certificate.hpp);
//   no       a parameter value checked to satisfy every sample (outward rounding or exact
//            rationals);
//   unknown  floating point could not decide: never report it as falsified.
// Callers report falsification on `yes` only; `unknown` goes on with the computation (its
// result says whether it is guaranteed) and tells the user that consistency was not certified.

#include <iosfwd>
#include <string>
#include <vector>

namespace sets {

enum class Falsified { no, yes, unknown };

/// Samples that cannot all hold at once, with how far the best compromise violates each. A
/// report for the user (which samples to look at); the proof of `Falsified::yes` is separate.
struct Falsification {
  std::vector<int> samples;
  std::vector<double> violation;  // in output units
  std::string message() const;
};

struct ConsistencyVerdict {
  Falsified falsified = Falsified::unknown;
  /// yes: the conflicting samples. unknown after an infeasible floating-point LP: the samples
  /// the floating-point compromise violates (an estimate, not a proof). Otherwise empty.
  Falsification conflict;
  /// unknown: why neither answer could be certified (for the user).
  std::string reason;

  bool certified_falsified() const { return falsified == Falsified::yes; }
  bool certified_consistent() const { return falsified == Falsified::no; }
  /// One line for the user: "the data falsify the model: ..." / "... consistent ..." /
  /// "could not be decided: <reason>".
  std::string message() const;
};

const char* to_string(Falsified f);
std::ostream& operator<<(std::ostream& os, Falsified f);

}  // namespace sets
