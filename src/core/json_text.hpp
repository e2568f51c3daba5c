#pragma once
// JSON text -> nlohmann value, with errors an engineer can act on: malformed JSON, a number
// outside the range of double (1e400) and absurdly deep nesting are InputError naming the file,
// the line and the column, never nlohmann's own exceptions.

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

namespace sets {

/// Deeper nesting of arrays and objects is refused (no file of ours needs more than a handful;
/// recursive code downstream, e.g. dump(), must not run out of stack).
inline constexpr int max_json_depth = 64;

nlohmann::json parse_json_text(const std::string& text, const std::string& source);
nlohmann::ordered_json parse_ordered_json_text(const std::string& text, const std::string& source);

/// "line L, column C" of a byte offset (both counted from 1; a column counts bytes).
std::string line_and_column(const std::string& text, std::size_t offset);

}  // namespace sets
