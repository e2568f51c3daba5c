// The JSON model file reader on hostile input: every error is an InputError naming the file, and
// the line and column or the field; bytes of the file are escaped in messages.

#include "sets/models/model_file.hpp"

#include <gtest/gtest.h>

#include <string>

#include "support/messages.hpp"

using sets::parse_model;
using sets::test::contains;
using sets::test::input_error_of;

namespace {

const char* kDecay = R"json({"name": "decay", "sample_time": 0.1, "inputs": {"u": "u"},
  "parameters": {"a": 2.0}, "states": {"x": 1.0},
  "sampled": {"us": "u + 0*prev(x, 1)", "lag": "prev(x, 2)"},
  "derivatives": {"x": "-a*x + us"}, "outputs": {"x": "y", "lag": "y"}})json";

std::string model_with(const std::string& states, const std::string& derivatives) {
  return R"({"sample_time": 0.1, "states": )" + states + R"(, "derivatives": )" + derivatives +
         R"(, "outputs": {"x": "y"}})";
}

}  // namespace

TEST(ModelFile, NumberOutsideDoubleRangeIsAnInputErrorWithLineAndColumn) {
  // nlohmann's own out_of_range used to escape here, with no file, line or column.
  const std::string text = "{\"sample_time\": 0.1,\n  \"states\": {\"x\": 1e400},\n"
                           "  \"derivatives\": {\"x\": \"-x\"}, \"outputs\": {\"x\": \"y\"}}";
  const std::string m = input_error_of([&] { parse_model(text, "m.json"); });
  EXPECT_TRUE(contains(m, "m.json: malformed JSON at line 2, column 19")) << m;
  EXPECT_TRUE(contains(m, "1e400")) << m;
  EXPECT_NO_THROW(parse_model(model_with(R"({"x": 1e-400})", R"({"x": "-x"})"), "m.json"));  // underflow is 0
}

TEST(ModelFile, AbsurdNestingIsRefusedWithItsPlace) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  const std::string m = input_error_of([&] { parse_model("{\"name\": " + deep + "}", "m.json"); });
  EXPECT_TRUE(contains(m, "m.json: line 1, column 73: JSON nested deeper than 64 levels")) << m;
}

TEST(ModelFile, SymbolNamesMustBeNamesMuparserCanTake) {
  EXPECT_TRUE(contains(input_error_of([] { parse_model(model_with(R"({"x": 0, "sin": 1})", R"({"x": "-x", "sin": "0"})"), "m.json"); }),
                       "m.json: field \"states\": \"sin\" is a built-in function"));
  EXPECT_TRUE(contains(input_error_of([] { parse_model(model_with(R"({"x": 0, "a b": 1})", R"({"x": "-x", "a b": "0"})"), "m.json"); }),
                       "\"a b\" is not a name"));
  EXPECT_TRUE(contains(input_error_of([] { parse_model(model_with(R"({"x": 0, "prev__x__1": 1})", R"({"x": "-x", "prev__x__1": "0"})"), "m.json"); }),
                       "reserved for prev(x, n)"));
  EXPECT_TRUE(contains(input_error_of([] { parse_model(model_with(R"({"x": 0, "1x": 1})", R"({"x": "-x", "1x": "0"})"), "m.json"); }),
                       "not starting with a digit"));
}

TEST(ModelFile, BytesOfTheFileAreEscapedInMessages) {
  const std::string m = input_error_of([] { parse_model(R"({"sample_time": 1, "\u001b[2Jbogus": 1})", "m.json"); });
  EXPECT_TRUE(contains(m, "unknown field \"\\x1b[2Jbogus\"")) << m;
  EXPECT_FALSE(sets::test::has_raw_control_bytes(m)) << m;
  const std::string bad_json = input_error_of([] { parse_model("{\"name\": \"\x1b[31m", "m.json"); });
  EXPECT_FALSE(sets::test::has_raw_control_bytes(bad_json)) << bad_json;
  EXPECT_TRUE(contains(bad_json, "m.json: malformed JSON at line 1")) << bad_json;
}

TEST(ModelFile, MalformedJsonNamesLineAndColumn) {
  const std::string text = "{\n  \"name\": \"x\",\n  \"time\" \"t\"\n}";
  const auto msg = input_error_of([&] { parse_model(text, "m.json"); });
  EXPECT_NE(msg.find("m.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 3, column 10"), std::string::npos) << msg;  // start of the offending token
}

TEST(ModelFile, RoundTripKeepsEverything) {
  const sets::ModelFile m = parse_model(kDecay, "decay");
  const sets::ModelFile back = parse_model(sets::to_json_text(m), "back");
  EXPECT_EQ(back.sampled, m.sampled);
  EXPECT_EQ(back.derivatives, m.derivatives);
  EXPECT_EQ(back.outputs, m.outputs);
  ASSERT_EQ(back.parameters.size(), 1u);
  EXPECT_EQ(back.parameters[0].value, 2.0);
  ASSERT_TRUE(back.sample_time.has_value());
}
