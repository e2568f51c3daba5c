#include "sets/core/exit_code.hpp"

#include <cstdio>

#include "sets/core/error.hpp"

namespace sets {

int exit_code_for(const std::exception& e) noexcept {
  if (dynamic_cast<const NumericalError*>(&e)) return exit_numerical;
  if (dynamic_cast<const EmptySetError*>(&e)) return exit_falsified;
  return exit_bad_input;
}

int report_failure(const char* app, const std::exception& e) noexcept {
  const int code = exit_code_for(e);
  const char* kind = code == exit_numerical ? "numerical failure" : code == exit_falsified ? "falsified" : "error";
  std::fprintf(stderr, "%s: %s: %s\n", app, kind, e.what());  // stdio: no exceptions from a noexcept path
  return code;
}

}  // namespace sets
