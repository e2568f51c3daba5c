// JSON save/load of every set type (exact round trip, clear errors) and 2-D projection polygons.
// (The text form: tests/domains/set_text_test.cpp.)

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <unistd.h>

#include <algorithm>
#include <limits>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "sets/core/error.hpp"
#include "sets/domains/conversions.hpp"
#include "sets/domains/set_io.hpp"
#include "support/messages.hpp"

namespace {

std::mt19937_64 rng(42);
double u() { return std::uniform_real_distribution<double>(-1, 1)(rng); }
Eigen::MatrixXd mat(int r, int c) { return Eigen::MatrixXd::NullaryExpr(r, c, [] { return u(); }); }

// Point-in-convex-polygon (counter-clockwise vertices), with a small tolerance for rounding.
bool in_polygon(const Eigen::MatrixXd& V, const Eigen::Vector2d& x) {
  for (int k = 0; k < V.cols(); ++k) {
    const Eigen::Vector2d a = V.col(k), b = V.col((k + 1) % V.cols());
    if ((b - a).x() * (x - a).y() - (b - a).y() * (x - a).x() < -1e-12) return false;
  }
  return true;
}

}  // namespace

TEST(SetIo, JsonRoundTripIsExact) {
  const Eigen::MatrixXd L = mat(3, 3);
  const std::vector<sets::AnySet> all = {
      sets::make_box(Eigen::Vector2d(-0.1, 1.0 / 3), Eigen::Vector2d(0.7, 2.0)),
      sets::Ellipsoid(Eigen::Vector3d(u(), u(), u()), L * L.transpose()),
      sets::Zonotope(Eigen::Vector3d(u(), u(), u()), mat(3, 5)),
      sets::HPolytope(mat(4, 3), Eigen::Vector4d(1, 2, std::numeric_limits<double>::infinity(), 0.1)),
      sets::VPolytope(mat(3, 6))};
  const auto dir = std::filesystem::temp_directory_path() / ("sets_io_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const auto& s : all) {
    const std::string path = (dir / "set.json").string();
    sets::save_json(path, s);
    const sets::AnySet back = sets::load_json(path);
    ASSERT_EQ(back.index(), s.index());
    EXPECT_EQ(sets::to_json(back), sets::to_json(s));  // exact: doubles survive the text form
    EXPECT_FALSE(sets::to_string(back).empty());
  }
  std::filesystem::remove_all(dir);
}

TEST(SetIo, BadJsonNamesTheField) {
  using nlohmann::json;
  auto message = [](const json& j) {
    try {
      sets::from_json(j, "input.json");
    } catch (const sets::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({{"type", "ellipsoid"}, {"center", {0, 0}}}).find("'shape': missing"), std::string::npos);
  EXPECT_NE(message({{"type", "zonotope"}, {"center", {0, 0}}, {"generators", {{1, "x"}}}}).find("generators[0][1]"),
            std::string::npos);
  EXPECT_NE(message({{"type", "ellipsoid"}, {"center", {0, 0}}, {"shape", {{1, 0}, {0, -1}}}}).find("input.json"),
            std::string::npos);
  EXPECT_NE(message({{"type", "circle"}}).find("unknown set type"), std::string::npos);
  const auto path = std::filesystem::temp_directory_path() / "sets_io_bad.json";
  std::ofstream(path) << "{\"type\": \"box\", \"lower\": [0,";
  EXPECT_THROW(sets::load_json(path.string()), sets::InputError);
  std::filesystem::remove(path);
}

TEST(SetIo, ProjectionPolygonsContainTheProjectedSets) {
  const sets::Zonotope Z(Eigen::Vector3d(0, 1, 2), mat(3, 6));
  const Eigen::MatrixXd L = mat(3, 3);
  const sets::Ellipsoid E(Eigen::Vector3d(0, 1, 2), L * L.transpose() + 0.1 * Eigen::Matrix3d::Identity());
  const sets::HPolytope H = sets::to_hpolytope(Z);
  const Eigen::MatrixXd PZ = sets::projection_polygon(Z, 0, 2);
  const Eigen::MatrixXd PE = sets::projection_polygon(E, 0, 2);
  const Eigen::MatrixXd PH = sets::projection_polygon(H, 0, 2);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(E.shape());
  const Eigen::MatrixXd S = es.eigenvectors() * es.eigenvalues().cwiseSqrt().asDiagonal();
  for (int k = 0; k < 300; ++k) {
    Eigen::VectorXd xi = Eigen::VectorXd::NullaryExpr(6, [] { return u() > 0 ? 1.0 : -1.0; });
    const Eigen::VectorXd z = Z.center() + Z.generators() * xi;
    EXPECT_TRUE(in_polygon(PZ, Eigen::Vector2d(z[0], z[2])));
    EXPECT_TRUE(in_polygon(PH, Eigen::Vector2d(z[0], z[2])));
    Eigen::Vector3d w(u(), u(), u());
    const Eigen::VectorXd e = E.center() + S * w.normalized();
    EXPECT_TRUE(in_polygon(PE, Eigen::Vector2d(e[0], e[2])));
  }
  std::ostringstream os;
  sets::write_polygon(os, PZ);
  const std::string text = os.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), PZ.cols() + 2);  // closed + blank line
  EXPECT_THROW(sets::projection_polygon(Z, 0, 0), sets::InputError);
}

TEST(SetIo, HostileJsonAndTextAreInputErrorsWithTheirPlace) {
  using sets::test::contains;
  using sets::test::input_error_of;
  // 1e400 escaped as nlohmann's own exception, without file, line or column.
  std::string m = input_error_of([] { sets::parse_set_json("{\"type\": \"box\",\n \"lower\": [1e400], \"upper\": [1]}", "s.json"); });
  EXPECT_TRUE(contains(m, "s.json: malformed JSON at line 2, column 12")) << m;
  // A dimension that would allocate exabytes before a row is looked at.
  m = input_error_of([] { sets::parse_set_json(R"({"type": "hpolytope", "dimension": 1000000000000000000, "A": [[1]], "b": [1]})", "s.json"); });
  EXPECT_TRUE(contains(m, "s.json: field 'dimension': expected a whole number from 0 to 100000")) << m;
  m = input_error_of([] { sets::parse_set_json(R"({"type": "hpolytope", "dimension": 2, "A": [[1, 0], [1]], "b": [1, 2]})", "s.json"); });
  EXPECT_TRUE(contains(m, "field 'A[1]': has 1 entries, expected 2")) << m;
  // The offending value is described, not dumped (a dump of a huge value was the message).
  m = input_error_of([] { sets::parse_set_json(R"({"type": "box", "lower": [{"a": [1, 2, 3]}], "upper": [1]})", "s.json"); });
  EXPECT_TRUE(contains(m, "field 'lower[0]': expected a number (or \"inf\", \"-inf\"), got object")) << m;
  m = input_error_of([] { sets::parse_set_json("{\"type\": \"box\", \"lower\": [\"\x1b[2J\"], \"upper\": [1]}", "s.json"); });
  EXPECT_FALSE(sets::test::has_raw_control_bytes(m)) << m;
  // Found by fuzz_set_json: the type was echoed raw.
  m = input_error_of([] { sets::parse_set_json("{\"type\": \"hp\x7flytope\"}", "s.json"); });
  EXPECT_TRUE(contains(m, "unknown set type 'hp\\x7flytope'")) << m;
  // Found by fuzz_set_text: a 0-dimensional ellipsoid took the largest entry of an empty matrix
  // (an Eigen assertion; a read past the end without assertions).
  EXPECT_EQ(std::get<sets::Ellipsoid>(sets::from_string("Ellipsoid(dim=0, center=[], shape=[])")).dimension(), 0);
  // Found by fuzz_set_text (UBSan): points of no entries made row views of a 2x0 matrix, which has
  // no storage; now the dimension check names the mismatch.
  m = input_error_of([] { sets::from_string("VPolytope(dim=2, points=[[ ], []])", "s.txt"); });
  EXPECT_TRUE(contains(m, "s.txt (VPolytope at line 1, column 1): field 'dim': says 2 but the data have dimension 0")) << m;
  // dim = 1e300 was cast to long: undefined behaviour.
  m = input_error_of([] { sets::from_string("Box(dim=1e300, [[0, 1]])", "s.txt"); });
  EXPECT_TRUE(contains(m, "s.txt: line 1, column 9: 'dim' must be a whole number from 0 to 100000")) << m;
  m = input_error_of([] { sets::from_string("Box(dim=1, " + std::string(100000, '[') + "0" + std::string(100000, ']') + ")", "s.txt"); });
  EXPECT_TRUE(contains(m, "lists nested more than 16 levels deep")) << m;
}
