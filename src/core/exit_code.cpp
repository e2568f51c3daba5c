#include "sets/core/exit_code.hpp"

#include <cstdio>
#include <string>

#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"

namespace sets {

namespace {

// The message as a terminal may receive it (printable() per line: a message may span lines).
std::string printable_message(const std::string& s) {
  std::string out;
  for (std::size_t pos = 0;;) {
    const auto nl = s.find('\n', pos);
    out += printable(std::string_view(s).substr(pos, nl == std::string::npos ? std::string::npos : nl - pos),
                     std::string::npos);
    if (nl == std::string::npos) return out;
    out += '\n';
    pos = nl + 1;
  }
}

}  // namespace

int exit_code_for(const std::exception& e) noexcept {
  if (dynamic_cast<const NumericalError*>(&e)) return exit_numerical;
  if (dynamic_cast<const EmptySetError*>(&e)) return exit_falsified;
  return exit_bad_input;
}

int report_failure(const char* app, const std::exception& e) noexcept {
  const int code = exit_code_for(e);
  const char* kind = code == exit_numerical ? "numerical failure" : code == exit_falsified ? "falsified" : "error";
  try {
    const std::string what = printable_message(e.what());
    std::fprintf(stderr, "%s: %s: %s\n", app, kind, what.c_str());  // stdio: no exceptions from here
  } catch (...) {
    std::fprintf(stderr, "%s: %s\n", app, kind);  // out of memory while escaping
  }
  return code;
}

}  // namespace sets
