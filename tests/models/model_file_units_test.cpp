// The optional `units` field of the model file (docs/model-format.md).

#include <gtest/gtest.h>

#include "sets/core/error.hpp"
#include "sets/models/model_file.hpp"

using namespace sets;

namespace {

const char* kAxis = R"json({"name": "axis", "time": "t", "inputs": {"u": "force"},
  "parameters": {"M": 2.0, "Fv": 0.5}, "states": {"q": "q_meas", "v": 0.0},
  "derivatives": {"q": "v", "v": "(u - Fv*v)/M"}, "outputs": {"q": "q_meas"}%s})json";

std::string with(const std::string& units) {
  char b[1024];
  std::snprintf(b, sizeof b, kAxis, units.c_str());
  return b;
}

}  // namespace

TEST(ModelFileUnits, OldFilesKeepWorkingWithoutUnits) {
  const ModelFile m = parse_model(with(""), "old.json");
  EXPECT_TRUE(m.units.empty());
  EXPECT_EQ(m.unit("q_meas"), "");
  EXPECT_EQ(m.unit("t"), "s");  // the time column is in seconds by definition of the format
  EXPECT_EQ(to_json_text(m).find("units"), std::string::npos);  // nothing new written
}

TEST(ModelFileUnits, SymbolsAndColumnsShareTheirUnitAndRoundTrip) {
  const ModelFile m = parse_model(with(R"(, "units": {"q": "m", "v": "m/s", "force": "N", "M": "kg"})"), "axis.json");
  EXPECT_EQ(m.unit("q"), "m");
  EXPECT_EQ(m.unit("q_meas"), "m");  // the output column takes its symbol's unit
  EXPECT_EQ(m.unit("force"), "N");
  EXPECT_EQ(m.unit("M"), "kg");
  EXPECT_EQ(m.unit("Fv"), "");
  const ModelFile back = parse_model(to_json_text(m), "back.json");
  EXPECT_EQ(back.units, m.units);
  const ModelFile by_column = parse_model(with(R"(, "units": {"q_meas": "mm"})"), "c.json");
  EXPECT_EQ(by_column.unit("q"), "mm");  // and the symbol its column's
}

TEST(ModelFileUnits, BadUnitsNameTheField) {
  try {
    parse_model(with(R"(, "units": {"speed": "m/s"})"), "typo.json");
    FAIL() << "no error for an unknown name";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("typo.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("units.speed"), std::string::npos);
  }
  EXPECT_THROW(parse_model(with(R"(, "units": {"q": 1})"), "n.json"), InputError);
  EXPECT_THROW(parse_model(with(R"(, "units": ["m"])"), "a.json"), InputError);
  EXPECT_THROW(parse_model(with(R"(, "units": {"q": "m'\nsystem 'x'"})"), "c.json"), InputError);  // one line
  EXPECT_THROW(parse_model(with(R"(, "units": {"q": "m\u0007"})"), "c.json"), InputError);         // no control bytes
}
