// Reading the human-readable text form written by to_string(AnySet), e.g.
//   Box(dim=2, [[0, 1], [-1, 2.5]])
//   Ellipsoid(dim=2, center=[0, 0], shape=[[2, 0], [0, 1]])
//   Zonotope(dim=2, center=[0, 0], generators=[[1, 0], [0.5, 1]])      (one list per generator)
//   HPolytope(dim=2, rows=[[1, 0 | 1], [0, 1 | inf]])                   (a | b per row)
//   VPolytope(dim=2, points=[[0, 0], [1, 0], [0, 1]])
// The text is translated into the JSON layout of set_io.hpp and read by from_json, so both forms
// share one set of checks; syntax errors name the line and column.

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/domains/set_io.hpp"

namespace sets {

namespace {

using nlohmann::json;

class Text_parser {
 public:
  Text_parser(const std::string& text, const std::string& where) : s_(text), where_(where) {}

  AnySet parse() {
    skip_space();
    const std::size_t kind_at = pos_;
    const std::string kind = identifier("a set type (Box, Ellipsoid, Zonotope, HPolytope, VPolytope)");
    expect('(');
    if (identifier("'dim'") != "dim") fail("expected 'dim=' as the first argument");
    expect('=');
    skip_space();
    const std::size_t dim_at = pos_;
    const json dim_value = number();
    // Checked before the cast: a double outside the range of long makes the cast undefined.
    if (!dim_value.is_number() || std::floor(dim_value.get<double>()) != dim_value.get<double>() ||
        dim_value.get<double>() < 0 || dim_value.get<double>() > static_cast<double>(max_set_dimension))
      fail_at(dim_at, "'dim' must be a whole number from 0 to " + std::to_string(max_set_dimension));
    const long dim = static_cast<long>(dim_value.get<double>());

    json j = json::object();
    while (peek() == ',') {
      ++pos_;
      skip_space();
      if (peek() == '[') {  // Box's one positional argument: its intervals
        field(j, "intervals", list());
        continue;
      }
      const std::string name = identifier("a field name");
      expect('=');
      field(j, name, list());
    }
    expect(')');
    skip_space();
    if (pos_ != s_.size()) fail("unexpected text after the set");

    const std::string location = where_ + " (" + kind + " at " + position(kind_at) + ")";
    AnySet set = from_json(to_layout(kind, dim, j, kind_at), location);
    const long got = std::visit(
        [](const auto& x) -> long {
          if constexpr (std::is_same_v<std::decay_t<decltype(x)>, IntervalVector>) return static_cast<long>(x.size());
          else return x.dimension();
        },
        set);
    if (got != dim)
      throw InputError(location + ": field 'dim': says " + std::to_string(dim) + " but the data have dimension " +
                       std::to_string(got));
    return set;
  }

 private:
  // The JSON layout of set_io.hpp for the parsed fields.
  json to_layout(const std::string& kind, long dim, json& j, std::size_t at) {
    auto take = [&](const char* name) -> json {
      if (!j.contains(name)) fail_at(at, kind + ": field '" + name + "' is missing");
      json v = j[name];
      j.erase(name);
      return v;
    };
    json out;
    if (kind == "Box") {
      json lower = json::array(), upper = json::array();
      for (const json& iv : take("intervals")) {
        if (!iv.is_array() || iv.size() != 2) fail_at(at, "Box: each interval must be [lower, upper]");
        lower.push_back(iv[0]);
        upper.push_back(iv[1]);
      }
      out = {{"type", "box"}, {"lower", lower}, {"upper", upper}};
    } else if (kind == "Ellipsoid") {
      out = {{"type", "ellipsoid"}, {"center", take("center")}, {"shape", take("shape")}};
    } else if (kind == "Zonotope") {
      out = {{"type", "zonotope"}, {"center", take("center")}, {"generators", take("generators")}};
    } else if (kind == "HPolytope") {
      json A = json::array(), b = json::array();
      for (const json& row : take("rows")) {
        if (!row.is_object()) fail_at(at, "HPolytope: each row must be [a_1, ..., a_n | b]");
        A.push_back(row["a"]);
        b.push_back(row["b"]);
      }
      out = {{"type", "hpolytope"}, {"dimension", dim}, {"A", A}, {"b", b}};
    } else if (kind == "VPolytope") {
      out = {{"type", "vpolytope"}, {"points", take("points")}};
    } else {
      fail_at(at, "unknown set type '" + kind + "' (Box, Ellipsoid, Zonotope, HPolytope, VPolytope)");
    }
    if (!j.empty()) fail_at(at, kind + ": unknown field '" + j.begin().key() + "'");
    return out;
  }

  void field(json& j, const std::string& name, json value) {
    if (j.contains(name)) fail("field '" + name + "' is given twice");
    j[name] = std::move(value);
  }

  // '[' item (',' item)* ']' where an item is a number or a list; "[a, b | c]" (one bar) becomes
  // {"a": [a, b], "b": c} for the rows of an H-polytope.
  json list() {
    if (++depth_ > max_depth) fail("lists nested more than " + std::to_string(max_depth) + " levels deep");
    struct Leave {
      int& d;
      ~Leave() { --d; }
    } leave{depth_};
    expect('[');
    json items = json::array();
    json bar_value;
    bool bar = false;
    skip_space();
    if (peek() == ']') {
      ++pos_;
      return items;
    }
    for (;;) {
      skip_space();
      json item = peek() == '[' ? list() : number();
      if (bar) {
        if (!bar_value.is_null()) fail("only one value may follow '|'");
        bar_value = std::move(item);
      } else {
        items.push_back(std::move(item));
      }
      skip_space();
      const char c = peek();
      ++pos_;
      if (c == ',' && !bar) continue;
      if (c == '|' && !bar) {
        bar = true;
        continue;
      }
      if (c == ']') break;
      --pos_;
      fail(bar ? "expected ']' after the value following '|'" : "expected ',', '|' or ']'");
    }
    if (!bar) return items;
    return {{"a", items}, {"b", bar_value}};
  }

  // A double as written with 17 significant digits, or inf / -inf (stored as JSON strings).
  json number() {
    skip_space();
    const char* begin = s_.c_str() + pos_;
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(begin, &end);
    if (end == begin) fail("expected a number");
    if (std::isnan(x)) fail("NaN is not a valid coordinate");
    if (errno == ERANGE && std::isinf(x)) fail("number out of range");
    pos_ += static_cast<std::size_t>(end - begin);
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    return x;
  }

  std::string identifier(const std::string& what) {
    skip_space();
    const std::size_t start = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
    if (start == pos_) fail("expected " + what);
    return s_.substr(start, pos_ - start);
  }

  void expect(char c) {
    skip_space();
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++pos_;
  }

  char peek() {
    skip_space();
    return pos_ < s_.size() ? s_[pos_] : '\0';
  }

  void skip_space() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }

  std::string position(std::size_t at) const {
    int line = 1, column = 1;
    for (std::size_t k = 0; k < at && k < s_.size(); ++k) {
      if (s_[k] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
  }

  [[noreturn]] void fail(const std::string& what) const { fail_at(pos_, what); }
  [[noreturn]] void fail_at(std::size_t at, const std::string& what) const {
    throw InputError(where_ + ": " + position(at) + ": " + what);
  }

  static constexpr int max_depth = 16;  // the deepest layout (H-polytope rows) needs 2
  const std::string& s_;
  std::string where_;
  std::size_t pos_ = 0;
  int depth_ = 0;
};

}  // namespace

AnySet from_string(const std::string& text, const std::string& where) { return Text_parser(text, where).parse(); }

void save_text(const std::string& path, const AnySet& set) { write_file_atomically(path, to_string(set) + "\n"); }

AnySet load_text(const std::string& path) {
  std::ifstream is(path);
  if (!is) throw InputError(path + ": cannot open");
  std::ostringstream text;
  text << is.rdbuf();
  return from_string(text.str(), path);
}

}  // namespace sets
