#pragma once
// Exceptions of `sets`: checks throw, they never abort.

#include <stdexcept>
#include <string>

namespace sets {

/// Bad input: names what was wrong and where (file, line, column, sample or field).
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A numerical procedure could not produce a trustworthy answer (e.g. the LP solver failed).
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The request is valid but outside what this build supports (e.g. exact H->V above 3-D).
class UnsupportedError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// A set that the data or the operation proved empty (e.g. an ellipsoid and a strip that do not
/// meet: the data falsify the model). Not an input error: the caller decides what it means.
class EmptySetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace sets
