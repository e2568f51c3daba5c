#pragma once
// What every harness checks besides "no crash, no sanitizer report, no leak": a reader returns or
// throws one of the documented exceptions of sets, and that message starts with the name of the
// input and holds no raw control bytes (printable() leaves it unchanged). Anything else — another
// exception type, a message that echoes raw bytes — is reported as a bug by abort(), which
// libFuzzer records as a crash with its input.

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"

namespace sets::fuzz {

[[noreturn]] inline void bug(const std::string& what) {
  std::fprintf(stderr, "fuzz harness: %s\n", printable(what, 2000).c_str());
  std::abort();
}

inline void check_message(const std::exception& e, const std::string& source) {
  const std::string m = e.what();
  if (m.rfind(source, 0) != 0) bug("the message does not start with the input's name \"" + source + "\": " + m);
  if (printable(m, m.size()) != m) bug("the message holds raw control or invalid UTF-8 bytes: " + m);
}

/// Runs `read` and accepts a return or InputError (and NumericalError where `numerical_ok`).
template <class Read>
void expect_documented_errors(Read&& read, const std::string& source, bool numerical_ok = false) {
  try {
    read();
  } catch (const InputError& e) {
    check_message(e, source);
  } catch (const NumericalError& e) {
    if (!numerical_ok) bug(std::string("NumericalError from a reader: ") + e.what());
    check_message(e, source);
  }
  // Any other exception propagates out of LLVMFuzzerTestOneInput: std::terminate, a crash.
}

}  // namespace sets::fuzz
