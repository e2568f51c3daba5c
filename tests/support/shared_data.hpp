#pragma once
// Where the tests find ../shared (papers and real recordings). SETS_SHARED_DIR overrides it.

#include <cstdlib>
#include <filesystem>
#include <string>

namespace sets::test {

inline std::filesystem::path shared_dir() {
  if (const char* env = std::getenv("SETS_SHARED_DIR")) return env;
  return std::filesystem::path(SETS_SOURCE_DIR) / ".." / "shared";
}

/// Path of a file under shared/data, or an empty path if it is not there (the test then skips).
inline std::filesystem::path shared_data(const std::string& relative) {
  const auto p = shared_dir() / "data" / relative;
  return std::filesystem::exists(p) ? p : std::filesystem::path();
}

}  // namespace sets::test
