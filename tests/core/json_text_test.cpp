// JSON text -> nlohmann value (src/core/json_text.cpp): every error is an InputError naming the
// source, the line and the column of the offending token; numbers outside double range and nesting
// deeper than max_json_depth are refused; brackets inside strings do not count as nesting.

#include "core/json_text.hpp"

#include <gtest/gtest.h>

#include <string>

#include "sets/core/error.hpp"
#include "support/messages.hpp"

using sets::parse_json_text;
using sets::parse_ordered_json_text;
using sets::test::contains;
using sets::test::input_error_of;

TEST(JsonText, LineAndColumnCountFromOneAndRestartAfterANewline) {
  const std::string text = "ab\ncd\n\nx";
  EXPECT_EQ(sets::line_and_column(text, 0), "line 1, column 1");
  EXPECT_EQ(sets::line_and_column(text, 1), "line 1, column 2");
  EXPECT_EQ(sets::line_and_column(text, 2), "line 1, column 3");  // the newline itself
  EXPECT_EQ(sets::line_and_column(text, 3), "line 2, column 1");
  EXPECT_EQ(sets::line_and_column(text, 7), "line 4, column 1");
  EXPECT_EQ(sets::line_and_column(text, 1000), "line 4, column 2");  // past the end: the end
}

TEST(JsonText, ValidTextKeepsValuesAndTheOrderedFormKeepsKeyOrder) {
  const auto j = parse_json_text(R"({"b": [1, 2.5, "x"], "a": {"t": true, "n": null}})", "v.json");
  EXPECT_EQ(j.at("b").at(0).get<int>(), 1);
  EXPECT_EQ(j.at("b").at(1).get<double>(), 2.5);
  EXPECT_EQ(j.at("b").at(2).get<std::string>(), "x");
  EXPECT_TRUE(j.at("a").at("t").get<bool>());
  EXPECT_TRUE(j.at("a").at("n").is_null());
  const auto o = parse_ordered_json_text(R"({"z": 1, "a": 2, "m": 3})", "o.json");
  std::string keys;
  for (const auto& [k, v] : o.items()) keys += k;
  EXPECT_EQ(keys, "zam");
}

TEST(JsonText, MalformedJsonNamesTheSourceLineAndColumnOfTheOffendingToken) {
  // The missing colon: the token "2" starts at line 3, column 7.
  const std::string m = input_error_of([] { parse_json_text("{\n  \"a\": 1,\n  \"b\" 2\n}", "f.json"); });
  EXPECT_TRUE(contains(m, "f.json: malformed JSON at line 3, column 7")) << m;
  // Cut short: the end of the text.
  const std::string cut = input_error_of([] { parse_json_text("[1,\n 2,", "cut.json"); });
  EXPECT_TRUE(contains(cut, "cut.json: malformed JSON at line 2")) << cut;
  // The ordered form reports the same place.
  const std::string o = input_error_of([] { parse_ordered_json_text("{\n  \"a\": 1,\n  \"b\" 2\n}", "f.json"); });
  EXPECT_EQ(o, m);
}

TEST(JsonText, NumberOutsideDoubleRangeIsAnInputErrorWithItsPlace) {
  const std::string m = input_error_of([] { parse_json_text("[1,\n 1e400]", "big.json"); });
  EXPECT_TRUE(contains(m, "big.json: malformed JSON at line 2, column 2")) << m;
  EXPECT_EQ(parse_json_text("[1e-400]", "small.json").at(0).get<double>(), 0.0);  // underflow is 0
}

TEST(JsonText, NestingDeeperThanTheLimitIsRefusedAtTheBracketThatOpensIt) {
  const int limit = sets::max_json_depth;
  const auto nested = [](int depth) { return std::string(static_cast<std::size_t>(depth), '[') + std::string(static_cast<std::size_t>(depth), ']'); };
  EXPECT_NO_THROW(parse_json_text(nested(limit), "ok.json"));
  const std::string m = input_error_of([&] { parse_json_text(nested(limit + 1), "deep.json"); });
  EXPECT_TRUE(contains(m, "deep.json: line 1, column " + std::to_string(limit + 1) + ": JSON nested deeper than " +
                              std::to_string(limit) + " levels")) << m;
  // Brackets inside strings, escaped quotes included, are text, not nesting.
  const std::string text = "[\"\\\"" + std::string(200, '[') + "\"]";
  EXPECT_EQ(parse_json_text(text, "s.json").at(0).get<std::string>().size(), 201u);
}

TEST(JsonText, BytesOfTheTextAreEscapedInMessages) {
  const std::string m = input_error_of([] { parse_json_text("{\"a\": \x1b[31m}", "esc.json"); });
  EXPECT_TRUE(contains(m, "esc.json: malformed JSON at line 1, column ")) << m;
  EXPECT_FALSE(sets::test::has_raw_control_bytes(m)) << m;
}
