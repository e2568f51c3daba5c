#pragma once
// The apps' exit codes (docs/contributing.md) in one place, so every app maps an exception that
// ends it the same way: 0 success, 1 bad input or usage, 2 the data falsify the model, 3 a
// numerical failure. No app returns another code (a signal ends it with the signal's status).

#include <exception>

namespace sets {

enum ExitCode : int { exit_success = 0, exit_bad_input = 1, exit_falsified = 2, exit_numerical = 3 };

/// NumericalError -> 3, EmptySetError (the data leave no feasible set) -> 2, anything else
/// (InputError, UnsupportedError, file-system errors, ...) -> 1.
int exit_code_for(const std::exception& e) noexcept;

/// Prints "<app>: error: <what>" (or "<app>: numerical failure: ...", "<app>: falsified: ...")
/// to stderr and returns exit_code_for(e). Use it in the one top-level catch of an app's main.
/// Bytes of the message that a terminal would interpret (control characters, invalid UTF-8, e.g.
/// from a binary file quoted in the message) are printed as \xNN.
int report_failure(const char* app, const std::exception& e) noexcept;

}  // namespace sets
