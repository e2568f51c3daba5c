// The one CSV reader of the library (sets/data/recording.hpp): the forms the apps accept, columns
// given by name or number; and recordings from hostile CSV files: every error is an InputError
// naming the file and the line/column; bytes of the file are escaped in messages. (The .mat reader:
// tests/data/mat_file_test.cpp.)

#include "sets/data/recording.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "sets/core/error.hpp"
#include "support/messages.hpp"

using sets::parse_csv;

namespace {

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const sets::InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace

TEST(Recording, HeaderLessFileNamesColumnsByNumber) {
  const auto r = parse_csv("# a comment\n1,2\n3,+4\n", "r.csv");
  ASSERT_EQ(r.names, (std::vector<std::string>{"1", "2"}));
  EXPECT_EQ(r.column("1"), (std::vector<double>{1, 3}));
  EXPECT_EQ(r.column("2"), (std::vector<double>{2, 4}));
}

TEST(Recording, SemicolonsAndTabsSeparateWhenTheFirstLineHasNoComma) {
  const auto s = parse_csv("u;y\n1;2\n3;4\n", "s.csv");
  EXPECT_EQ(s.column("y"), (std::vector<double>{2, 4}));
  const auto t = parse_csv("u\ty\n1\t2\n", "t.csv");
  EXPECT_EQ(t.column("u"), (std::vector<double>{1}));
}

TEST(Recording, CommentLinesAreSkippedAndLinesStillCounted) {
  const auto msg = message_of([] { parse_csv("t,y\n# note\n0,1\n0.1,2x\n", "r.csv"); });
  EXPECT_NE(msg.find("line 4, column 2"), std::string::npos) << msg;
}

TEST(Recording, NumbersAreReadWhole) {
  for (const char* cell : {"0.5abc", "12:30", "0x10", "1 2"}) {
    const auto msg = message_of([&] { parse_csv(std::string("u,y\n1,") + cell + "\n", "r.csv"); });
    EXPECT_NE(msg.find("line 2, column 2 (\"y\"): not a number"), std::string::npos) << cell << ": " << msg;
  }
}

TEST(Recording, ColumnsByNameOrNumber) {
  const auto r = parse_csv("t,u,y\n0,1,2\n1,3,4\n", "r.csv");
  EXPECT_EQ(r.column_index("y"), 2u);
  EXPECT_EQ(r.column_index("2"), 1u);
  const Eigen::MatrixXd m = r.matrix({"y", "1"}, "--x");
  ASSERT_EQ(m.rows(), 2);
  ASSERT_EQ(m.cols(), 2);
  EXPECT_EQ(m(1, 0), 4);
  EXPECT_EQ(m(1, 1), 1);
  const auto msg = message_of([&] { r.column_index("4", "--u"); });
  EXPECT_NE(msg.find("r.csv: no column \"4\" (given by --u); the file has: t, u, y"), std::string::npos) << msg;
}

TEST(Recording, ANameThatIsANumberWinsOverThePosition) {
  const auto r = parse_csv("x,1\n5,6\n", "r.csv");
  EXPECT_EQ(r.column_index("1"), 1u);  // the column called "1", not the first column
}

using namespace sets;
using sets::test::contains;
using sets::test::input_error_of;

TEST(Recording, CsvEscapesBinaryGarbageInMessages) {
  const std::string m = input_error_of([] { parse_csv("a,b\n1,\x1b[31mred\x07\n", "r.csv"); });
  EXPECT_TRUE(contains(m, "r.csv: line 2, column 2 (\"b\"): not a number: \"\\x1b[31mred\\x07\"")) << m;
  EXPECT_FALSE(sets::test::has_raw_control_bytes(m)) << m;
  const std::string header = input_error_of([] { parse_csv("a,\x1b]0;title\x07\n1\n", "r.csv").column("x"); });
  EXPECT_FALSE(sets::test::has_raw_control_bytes(header)) << header;
}

TEST(Recording, CsvNumbersOutsideDoubleRangeAndDuplicateNames) {
  EXPECT_TRUE(contains(input_error_of([] { parse_csv("a\n1e400\n", "r.csv"); }),
                       "r.csv: line 2, column 1 (\"a\"): the number 1e400 is outside the range of double precision"));
  EXPECT_EQ(parse_csv("a\n1e-400\n", "r.csv").column("a")[0], 0.0);  // underflow is 0
  EXPECT_TRUE(contains(input_error_of([] { parse_csv("t,y,t\n1,2,3\n", "r.csv"); }),
                       "r.csv: line 1, column 3: the column name \"t\" is given twice"));
}

TEST(Recording, NanRowIsNamed) {
  const auto msg = message_of([] { parse_csv("t,y\n0,1\n0.1,2\n0.2,nan\n", "r.csv"); });
  EXPECT_NE(msg.find("r.csv"), std::string::npos) << msg;
  EXPECT_NE(msg.find("data row 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("\"y\""), std::string::npos) << msg;
}

TEST(Recording, BadNumberNamesLineAndColumn) {
  const auto msg = message_of([] { parse_csv("t,y\n0,1\n0.1,2x\n", "r.csv"); });
  EXPECT_NE(msg.find("line 3, column 2"), std::string::npos) << msg;
}
