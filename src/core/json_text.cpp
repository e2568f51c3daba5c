#include "core/json_text.hpp"

#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"

namespace sets {

std::string line_and_column(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

namespace {

// Offset of the first bracket that opens nesting level max_json_depth + 1, or npos.
std::size_t too_deep_at(const std::string& text) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_json_depth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::string::npos;
}

// nlohmann's DOM builder, except that an error is remembered with its byte offset instead of
// thrown without one (a number overflow carries no position in the exception itself).
template <class Json>
class Located_sax {
 public:
  using Dom = nlohmann::detail::json_sax_dom_parser<Json>;
  explicit Located_sax(Json& root) : dom_(root, false) {}

  bool null() { return dom_.null(); }
  bool boolean(bool v) { return dom_.boolean(v); }
  bool number_integer(typename Json::number_integer_t v) { return dom_.number_integer(v); }
  bool number_unsigned(typename Json::number_unsigned_t v) { return dom_.number_unsigned(v); }
  bool number_float(typename Json::number_float_t v, const typename Json::string_t& s) { return dom_.number_float(v, s); }
  bool string(typename Json::string_t& v) { return dom_.string(v); }
  bool binary(typename Json::binary_t& v) { return dom_.binary(v); }
  bool start_object(std::size_t n) { return dom_.start_object(n); }
  bool key(typename Json::string_t& v) { return dom_.key(v); }
  bool end_object() { return dom_.end_object(); }
  bool start_array(std::size_t n) { return dom_.start_array(n); }
  bool end_array() { return dom_.end_array(); }

  template <class Exception>
  bool parse_error(std::size_t offset, const std::string& last_token, const Exception& e) {
    failed = true;
    // The offset is just past the offending token; point at its start.
    at = offset >= last_token.size() ? offset - last_token.size() : 0;
    reason = e.what();
    // "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error while ..."
    if (const auto p = reason.find("] "); p != std::string::npos) reason = reason.substr(p + 2);
    if (reason.rfind("parse error", 0) == 0)
      if (const auto p = reason.find(": "); p != std::string::npos) reason = reason.substr(p + 2);
    return false;
  }

  bool failed = false;
  std::size_t at = 0;
  std::string reason;

 private:
  Dom dom_;
};

template <class Json>
Json parse(const std::string& text, const std::string& source) {
  if (const std::size_t deep = too_deep_at(text); deep != std::string::npos)
    throw InputError(source + ": " + line_and_column(text, deep) + ": JSON nested deeper than " +
                     std::to_string(max_json_depth) + " levels");
  Json j;
  Located_sax<Json> sax(j);
  Json::sax_parse(text, &sax);
  if (sax.failed)
    throw InputError(source + ": malformed JSON at " + line_and_column(text, sax.at) + ": " + printable(sax.reason));
  return j;
}

}  // namespace

nlohmann::json parse_json_text(const std::string& text, const std::string& source) {
  return parse<nlohmann::json>(text, source);
}

nlohmann::ordered_json parse_ordered_json_text(const std::string& text, const std::string& source) {
  return parse<nlohmann::ordered_json>(text, source);
}

}  // namespace sets
