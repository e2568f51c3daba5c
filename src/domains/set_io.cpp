#include "sets/domains/set_io.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <ostream>
#include <sstream>

#include "core/json_text.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"
#include "sets/domains/conversions.hpp"

namespace sets {

namespace {

using nlohmann::json;

json number(double x) {
  if (std::isfinite(x)) return x;
  return x > 0 ? "inf" : "-inf";
}

json vec(const Eigen::VectorXd& v) {
  json a = json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(number(v[i]));
  return a;
}

json rows(const Eigen::MatrixXd& M) {
  json a = json::array();
  for (Eigen::Index i = 0; i < M.rows(); ++i) a.push_back(vec(M.row(i).transpose()));
  return a;
}

[[noreturn]] void bad(const std::string& where, const std::string& field, const std::string& what) {
  throw InputError(where + ": field '" + field + "': " + what);
}

double read_number(const json& x, const std::string& where, const std::string& field) {
  if (x.is_number()) return x.get<double>();
  if (x.is_string()) {
    const auto s = x.get<std::string>();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
  }
  bad(where, field, std::string("expected a number (or \"inf\", \"-inf\"), got ") +
                        (x.is_string() ? "the string \"" + printable(x.get<std::string>(), 40) + "\"" : x.type_name()));
}

Eigen::VectorXd read_vec(const json& j, const std::string& where, const std::string& field) {
  if (!j.is_array()) bad(where, field, "expected an array of numbers");
  Eigen::VectorXd v(j.size());
  for (std::size_t i = 0; i < j.size(); ++i)
    v[static_cast<Eigen::Index>(i)] = read_number(j[i], where, field + "[" + std::to_string(i) + "]");
  return v;
}

// Array of equally long arrays -> matrix whose rows (or columns) are those arrays. Sizes are
// checked against the data before anything is allocated.
Eigen::MatrixXd read_rows(const json& j, const std::string& where, const std::string& field, Eigen::Index width) {
  if (!j.is_array()) bad(where, field, "expected an array of arrays");
  for (std::size_t i = 0; i < j.size(); ++i) {
    const auto name = field + "[" + std::to_string(i) + "]";
    if (!j[i].is_array()) bad(where, name, "expected an array of numbers");
    if (j[i].size() != static_cast<std::size_t>(width))
      bad(where, name, "has " + std::to_string(j[i].size()) + " entries, expected " + std::to_string(width));
  }
  Eigen::MatrixXd M(static_cast<Eigen::Index>(j.size()), width);
  if (width == 0) return M;  // rows of no entries: a row view of a matrix without storage is UB
  for (std::size_t i = 0; i < j.size(); ++i)
    M.row(static_cast<Eigen::Index>(i)) = read_vec(j[i], where, field + "[" + std::to_string(i) + "]").transpose();
  return M;
}

const json& field(const json& j, const char* name, const std::string& where) {
  if (!j.contains(name)) bad(where, name, "missing");
  return j.at(name);
}

}  // namespace

json to_json(const AnySet& set) {
  return std::visit(
      [](const auto& s) -> json {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, IntervalVector>) {
          return {{"type", "box"}, {"lower", vec(lower(s))}, {"upper", vec(upper(s))}};
        } else if constexpr (std::is_same_v<T, Ellipsoid>) {
          return {{"type", "ellipsoid"}, {"center", vec(s.center())}, {"shape", rows(s.shape())}};
        } else if constexpr (std::is_same_v<T, Zonotope>) {
          return {{"type", "zonotope"}, {"center", vec(s.center())}, {"generators", rows(s.generators().transpose())}};
        } else if constexpr (std::is_same_v<T, HPolytope>) {
          return {{"type", "hpolytope"}, {"dimension", s.dimension()}, {"A", rows(s.A())}, {"b", vec(s.b())}};
        } else {
          return {{"type", "vpolytope"}, {"points", rows(s.points().transpose())}};
        }
      },
      set);
}

AnySet from_json(const json& j, const std::string& where) {
  if (!j.is_object()) throw InputError(where + ": expected a JSON object with a \"type\" field");
  const json& t = field(j, "type", where);
  if (!t.is_string()) bad(where, "type", "expected a string");
  const auto type = t.get<std::string>();
  try {
    if (type == "box") {
      const Eigen::VectorXd lo = read_vec(field(j, "lower", where), where, "lower");
      const Eigen::VectorXd hi = read_vec(field(j, "upper", where), where, "upper");
      return make_box(lo, hi);
    }
    if (type == "ellipsoid") {
      const Eigen::VectorXd c = read_vec(field(j, "center", where), where, "center");
      return Ellipsoid(c, read_rows(field(j, "shape", where), where, "shape", c.size()));
    }
    if (type == "zonotope") {
      const Eigen::VectorXd c = read_vec(field(j, "center", where), where, "center");
      return Zonotope(c, read_rows(field(j, "generators", where), where, "generators", c.size()).transpose());
    }
    if (type == "hpolytope") {
      const json& d = field(j, "dimension", where);
      const bool whole = d.is_number_unsigned() || (d.is_number_integer() && d.get<std::int64_t>() >= 0);
      if (!whole || d.get<std::uint64_t>() > static_cast<std::uint64_t>(max_set_dimension))
        bad(where, "dimension", "expected a whole number from 0 to " + std::to_string(max_set_dimension));
      return HPolytope(read_rows(field(j, "A", where), where, "A", d.get<Eigen::Index>()),
                       read_vec(field(j, "b", where), where, "b"));
    }
    if (type == "vpolytope") {
      const json& p = field(j, "points", where);
      if (!p.is_array() || p.empty() || !p[0].is_array()) bad(where, "points", "expected a non-empty array of points");
      return VPolytope(read_rows(p, where, "points", static_cast<Eigen::Index>(p[0].size())).transpose());
    }
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.rfind(where, 0) == 0) throw;
    throw InputError(where + ": " + msg);
  }
  bad(where, "type", "unknown set type '" + printable(type, 40) + "' (box, ellipsoid, zonotope, hpolytope, vpolytope)");
}

void save_json(const std::string& path, const AnySet& set) {
  write_file_atomically(path, to_json(set).dump(2) + "\n");
}

AnySet parse_set_json(const std::string& text, const std::string& where) {
  return from_json(parse_json_text(text, where), where);
}

AnySet load_json(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  if (!is) throw InputError(path + ": cannot open");
  std::ostringstream text;
  text << is.rdbuf();
  return parse_set_json(text.str(), path);
}

Eigen::MatrixXd projection_polygon(const AnySet& set, int i, int j, int directions) {
  return std::visit(
      [&](const auto& s) -> Eigen::MatrixXd {
        using T = std::decay_t<decltype(s)>;
        int n = 0;
        if constexpr (std::is_same_v<T, IntervalVector>) n = static_cast<int>(s.size());
        else n = s.dimension();
        if (i < 0 || j < 0 || i >= n || j >= n || i == j)
          throw InputError("projection_polygon: coordinates (" + std::to_string(i) + ", " + std::to_string(j) +
                           ") are not two different coordinates of a " + std::to_string(n) + "-D set");
        if constexpr (std::is_same_v<T, IntervalVector>) {
          Eigen::MatrixXd V(2, 4);
          V << s[i].lower(), s[i].upper(), s[i].upper(), s[i].lower(), s[j].lower(), s[j].lower(), s[j].upper(),
              s[j].upper();
          return V;
        } else if constexpr (std::is_same_v<T, Ellipsoid>) {
          return outer_polygon(project(s, {i, j}), directions);
        } else if constexpr (std::is_same_v<T, Zonotope>) {
          Eigen::MatrixXd G(2, s.num_generators());
          G << s.generators().row(i), s.generators().row(j);
          return polygon_vertices(Zonotope(Eigen::Vector2d(s.center()[i], s.center()[j]), G));
        } else if constexpr (std::is_same_v<T, VPolytope>) {
          Eigen::MatrixXd P(2, s.num_points());
          P << s.points().row(i), s.points().row(j);
          return polygon_vertices(VPolytope(P));
        } else {
          if (n == 2) return polygon_vertices(i == 0 ? s : HPolytope(s.A().rowwise().reverse(), s.b()));
          std::vector<Eigen::VectorXd> dirs;
          Eigen::MatrixXd A(directions, 2);
          for (int k = 0; k < directions; ++k) {
            const double t = 2 * std::numbers::pi * k / directions;
            A.row(k) << std::cos(t), std::sin(t);
            Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
            d[i] = A(k, 0);
            d[j] = A(k, 1);
            dirs.push_back(d);
          }
          const auto sup = support(s, dirs);
          Eigen::VectorXd b(directions);
          for (int k = 0; k < directions; ++k) {
            if (!std::isfinite(sup[k])) throw UnsupportedError("projection_polygon: the polytope is unbounded");
            b[k] = sup[k];
          }
          return polygon_vertices(HPolytope(A, b));
        }
      },
      set);
}

void write_polygon(std::ostream& os, const Eigen::Ref<const Eigen::MatrixXd>& V) {
  if (V.rows() != 2) throw InputError("write_polygon: vertices must be a 2 x k matrix");
  const auto old = os.precision(17);
  for (Eigen::Index k = 0; k <= V.cols(); ++k) {
    const Eigen::Index c = k % std::max<Eigen::Index>(V.cols(), 1);
    if (V.cols() == 0) break;
    os << V(0, c) << " " << V(1, c) << "\n";
  }
  os << "\n";
  os.precision(old);
}

std::string to_string(const AnySet& set) {
  return std::visit(
      [](const auto& s) -> std::string {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, IntervalVector>) {
          std::ostringstream os;
          os.precision(17);
          os << "Box(dim=" << s.size() << ", [";
          for (Eigen::Index k = 0; k < s.size(); ++k) os << (k ? ", " : "") << "[" << s[k].lower() << ", " << s[k].upper() << "]";
          os << "])";
          return os.str();
        } else {
          return sets::to_string(s);
        }
      },
      set);
}

}  // namespace sets
