// The text form of sets (src/domains/set_text.cpp): to_string/from_string round trips bit for bit
// for every set type, and syntax errors name the line and column, data errors the field.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include "sets/core/error.hpp"
#include "sets/domains/conversions.hpp"
#include "sets/domains/set_io.hpp"
#include "support/random_matrices.hpp"

TEST(SetIo, TextRoundTripIsExact) {
  sets::test::Rng r(42);
  const Eigen::MatrixXd L = r.mat(3, 3);
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<sets::AnySet> all = {
      sets::make_box(Eigen::Vector2d(-inf, 1.0 / 3), Eigen::Vector2d(0.7, inf)),
      sets::Ellipsoid(Eigen::Vector3d(r.u(), r.u(), r.u()), L * L.transpose()),
      sets::Zonotope(Eigen::Vector3d(r.u(), r.u(), r.u()), r.mat(3, 5)),
      sets::Zonotope(Eigen::Vector2d(r.u(), r.u()), Eigen::MatrixXd(2, 0)),  // a point
      sets::HPolytope(r.mat(4, 3), Eigen::Vector4d(1, 2, inf, 0.1)),
      sets::HPolytope(Eigen::MatrixXd(0, 2), Eigen::VectorXd(0)),  // the whole plane
      sets::VPolytope(r.mat(3, 6))};
  const auto path = std::filesystem::temp_directory_path() / ("sets_io_" + std::to_string(::getpid()) + ".txt");
  for (const auto& s : all) {
    const sets::AnySet back = sets::from_string(sets::to_string(s));
    ASSERT_EQ(back.index(), s.index()) << sets::to_string(s);
    EXPECT_EQ(sets::to_json(back), sets::to_json(s)) << sets::to_string(s);  // bit for bit
    sets::save_text(path.string(), s);
    EXPECT_EQ(sets::to_json(sets::load_text(path.string())), sets::to_json(s));
  }
  std::filesystem::remove(path);
  // Hand-written text with line breaks and spacing reads the same.
  const auto hp = sets::from_string("HPolytope(dim=2,\n  rows=[[1, 0 | 1],\n        [0, 1|2e0]])");
  EXPECT_EQ(std::get<sets::HPolytope>(hp).b()[1], 2.0);
}

TEST(SetIo, BadTextNamesLineColumnOrField) {
  auto message = [](const std::string& text) {
    try {
      sets::from_string(text, "set.txt");
    } catch (const sets::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto has = [](const std::string& m, const char* part) { return m.find(part) != std::string::npos; };
  std::string m = message("Zonotope(dim=2, center=[0, 0],\n generators=[[1, x]])");
  EXPECT_TRUE(has(m, "set.txt: line 2, column 18: expected a number")) << m;
  m = message("Circle(dim=2, center=[0, 0])");
  EXPECT_TRUE(has(m, "line 1, column 1: unknown set type 'Circle'")) << m;
  m = message("Ellipsoid(dim=2, center=[0, 0])");
  EXPECT_TRUE(has(m, "field 'shape' is missing")) << m;
  m = message("Ellipsoid(dim=2, center=[0, 0], shape=[[1, 0], [0, -1]])");  // not positive definite
  EXPECT_TRUE(has(m, "set.txt (Ellipsoid at line 1, column 1)")) << m;
  m = message("VPolytope(dim=3, points=[[0, 0], [1, 0]])");
  EXPECT_TRUE(has(m, "field 'dim': says 3 but the data have dimension 2")) << m;
  m = message("HPolytope(dim=2, rows=[[1, 0 | 1 | 2]])");
  EXPECT_TRUE(has(m, "column 34: expected ']' after the value following '|'")) << m;
  m = message("Box(dim=1, [[0, nan]])");
  EXPECT_TRUE(has(m, "NaN")) << m;
  m = message("Box(dim=1, [[0, 1]]) trailing");
  EXPECT_TRUE(has(m, "unexpected text after the set")) << m;
  EXPECT_THROW(sets::load_text("/nonexistent/set.txt"), sets::InputError);
}

TEST(SetText, ExtremeNumbersRoundTripBitForBit) {
  // The shortest text that reads back as the same double, at the ends of the double range too.
  const double tiny = std::numeric_limits<double>::denorm_min(), big = std::numeric_limits<double>::max();
  const Eigen::Vector4d lo(-big, tiny, 0.1, 1.0 / 3), hi(-2.2250738585072014e-308, 2 * tiny, 0.30000000000000004, big);
  const sets::AnySet box = sets::make_box(lo, hi);
  const std::string text = sets::to_string(box);
  const sets::AnySet read = sets::from_string(text, "box.txt");
  const auto& back = std::get<sets::IntervalVector>(read);
  ASSERT_EQ(back.size(), 4);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(back[i].lower(), lo[i]) << text;
    EXPECT_EQ(back[i].upper(), hi[i]) << text;
  }
}
