#include "sets/core/exit_code.hpp"

#include <cstdio>
#include <string>

#include "sets/core/error.hpp"

namespace sets {

namespace {

// Length of a well-formed UTF-8 sequence starting at s[i] (0 if there is none).
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto b = static_cast<unsigned char>(s[i]);
  const std::size_t n = b >= 0xC2 && b <= 0xDF ? 2 : b >= 0xE0 && b <= 0xEF ? 3 : b >= 0xF0 && b <= 0xF4 ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 0;
  return n;
}

// The message as a terminal may receive it: printable ASCII, newlines, tabs and UTF-8 as they are,
// every other byte as \xNN.
std::string printable_message(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if ((c >= 0x20 && c < 0x7F) || c == '\n' || c == '\t') {
      out += static_cast<char>(c);
      ++i;
    } else if (const std::size_t n = c >= 0x80 ? utf8_length(s, i) : 0) {
      out.append(s, i, n);
      i += n;
    } else {
      static const char hex[] = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
      ++i;
    }
  }
  return out;
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
