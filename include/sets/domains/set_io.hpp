#pragma once
// Saving and loading every set type as JSON (nlohmann-json), and 2-D projections written as
// polygon vertex lists that a plotting tool can draw.
//
// JSON layout (doubles are written with 17 significant digits, so a round trip is exact):
//   {"type": "box",       "lower": [..], "upper": [..]}
//   {"type": "ellipsoid", "center": [..], "shape": [[row], ..]}
//   {"type": "zonotope",  "center": [..], "generators": [[column], ..]}
//   {"type": "hpolytope", "A": [[row], ..], "b": [..]}          (b entries may be "inf")
//   {"type": "vpolytope", "points": [[point], ..]}
// The human-readable text form of each type is its `to_string` (17 significant digits, so it also
// round-trips exactly); `from_string` / `load_text` read it back, e.g.
//   Box(dim=2, [[0, 1], [-1, 2.5]])
//   HPolytope(dim=2, rows=[[1, 0 | 1], [0, 1 | inf]])

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>
#include <variant>

#include "sets/domains/ellipsoid.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/numeric/interval_matrix.hpp"
#include "sets/domains/vpolytope.hpp"
#include "sets/domains/zonotope.hpp"

namespace sets {

using AnySet = std::variant<IntervalVector, Ellipsoid, Zonotope, HPolytope, VPolytope>;

/// Readers refuse a larger dimension before allocating anything for it (an H-polytope without
/// rows states its dimension with nothing else to check it against).
inline constexpr long max_set_dimension = 100000;

nlohmann::json to_json(const AnySet& set);
/// Throws InputError naming `where` (a file name or "JSON") and the offending field.
AnySet from_json(const nlohmann::json& j, const std::string& where = "JSON");

/// Writes the set to `path` completely or not at all (temporary file, then rename).
void save_json(const std::string& path, const AnySet& set);
/// Reads a set; InputError with the file name (and line/column for malformed JSON or a number
/// outside the range of double, such as 1e400).
AnySet load_json(const std::string& path);
/// The same from JSON text; `where` names it in messages.
AnySet parse_set_json(const std::string& text, const std::string& where = "JSON");

/// Convex polygon (2 x k, counter-clockwise) that contains the projection of the set onto
/// coordinates (i, j). Exact shadow (up to rounding) for zonotopes, V-polytopes and boxes; a
/// circumscribed polygon for ellipsoids; for H-polytopes the intersection of `directions`
/// supporting half-planes (certified support values), an outer approximation.
Eigen::MatrixXd projection_polygon(const AnySet& set, int i, int j, int directions = 64);

/// Writes polygons as "x y" lines, each closed (first vertex repeated) and separated by a blank
/// line: gnuplot's `plot 'file' with lines` and most plotting tools read it directly.
void write_polygon(std::ostream& os, const Eigen::Ref<const Eigen::MatrixXd>& vertices);

std::string to_string(const AnySet& set);
/// Reads the text form of to_string. Throws InputError naming `where`, the line and column of a
/// syntax error, or the offending field (through the same checks as from_json).
AnySet from_string(const std::string& text, const std::string& where = "text");
/// The text form in a file, written completely or not at all.
void save_text(const std::string& path, const AnySet& set);
AnySet load_text(const std::string& path);

}  // namespace sets
