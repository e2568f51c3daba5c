#pragma once
// The message of the InputError a call throws ("<no InputError>" if it returns or throws anything
// else, so that a test comparing messages fails).

#include <functional>
#include <string>

#include "sets/core/error.hpp"

namespace sets::test {

inline std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (...) {
    return "<not an InputError>";
  }
  return "<no InputError>";
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Whether the text holds a byte a terminal would act on (C0 control or DEL).
inline bool has_raw_control_bytes(const std::string& text) {
  for (unsigned char c : text)
    if (c < 0x20 || c == 0x7F) return true;
  return false;
}

}  // namespace sets::test
