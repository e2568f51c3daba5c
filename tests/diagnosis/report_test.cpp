// The report of the diagnosis (src/diagnosis/report.cpp) on a hand-made result: the JSON has the
// documented keys and values (non-finite numbers as null, the three answers), the text names the
// fits with units and the verdict.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "sets/diagnosis/diagnosis.hpp"
#include "sets/models/model_file.hpp"
#include "support/messages.hpp"

using namespace sets;
using sets::test::contains;

namespace {

Diagnosis hand_made() {
  Diagnosis d;
  d.outputs = {"x_meas"};
  d.nominal = parse_model(R"json({"sample_time": 0.1, "parameters": {"k": 4.25, "c": 0.5}, "states": {"x": 0.0},
    "derivatives": {"x": "-k*x - c"}, "outputs": {"x": "x_meas"}})json", "nominal.json");
  d.free_nominal = {"k"};
  d.has_validation = true;
  d.fit_start_estimation = {40.0};
  d.fit_start_validation = {std::numeric_limits<double>::quiet_NaN()};
  d.fit_nominal_estimation = {87.5};
  d.fit_nominal_validation = {86.0};
  d.fit_augmented_estimation = {98.25};
  d.fit_augmented_validation = {97.0};
  d.windows.push_back({"x_meas", 1.5, 2.5, 0.125, true});
  d.error_bound = {0.03};
  DiagnosedEffect e;
  e.name = "coulomb_friction";
  e.equation = "v";
  e.term = "-Fc*sign(v)";
  EffectParameter fc;
  fc.name = "Fc";
  fc.role = "Fc";
  fc.estimate = 0.31;
  fc.lo = 0.28;
  fc.hi = 0.33;
  fc.has_ee = fc.ee_certified = true;
  fc.ee_lo = 0.28, fc.ee_hi = 0.33, fc.ee_delta = 0.01;
  fc.estimate_oe_lo = 0.305, fc.estimate_oe_hi = 0.315;
  fc.oe_delta = {0.05};
  e.parameters.push_back(fc);
  d.effects.push_back(e);
  d.verdict = "Missing physics: coulomb_friction (v).";
  return d;
}

}  // namespace

TEST(Report, JsonHasTheDocumentedKeysAndValues) {
  Diagnosis d = hand_made();
  const auto j = nlohmann::json::parse(diagnosis_json(d, "augmented.json"));
  EXPECT_EQ(j.at("nominal").at("parameters").at("k").get<double>(), 4.25);
  EXPECT_FALSE(j.at("nominal").at("parameters").contains("c"));  // fixed parameters are not reported
  EXPECT_EQ(j.at("nominal").at("fit").at("estimation").at("x_meas").get<double>(), 87.5);
  EXPECT_TRUE(j.at("nominal").at("fit_before_calibration").at("validation").at("x_meas").is_null());  // NaN
  EXPECT_EQ(j.at("augmented").at("fit").at("validation").at("x_meas").get<double>(), 97.0);
  EXPECT_EQ(j.at("augmented").at("model").get<std::string>(), "augmented.json");
  EXPECT_EQ(j.at("mismatch").at("error_bound").at("x_meas").get<double>(), 0.03);
  ASSERT_EQ(j.at("mismatch").at("windows").size(), 1u);
  ASSERT_EQ(j.at("effects").size(), 1u);
  EXPECT_EQ(j.at("effects").at(0).at("name").get<std::string>(), "coulomb_friction");
  EXPECT_EQ(j.at("verdict").get<std::string>(), d.verdict);
  EXPECT_EQ(j.at("answer").get<std::string>(), "missing");
  // The other two answers, and no augmented model path.
  d.effects.clear();
  d.nothing_missing = true;
  auto k = nlohmann::json::parse(diagnosis_json(d, ""));
  EXPECT_EQ(k.at("answer").get<std::string>(), "nothing_missing");
  EXPECT_TRUE(k.at("augmented").at("model").is_null());
  d.nothing_missing = false;
  d.unexplained = true;
  k = nlohmann::json::parse(diagnosis_json(d, ""));
  EXPECT_EQ(k.at("answer").get<std::string>(), "unexplained");
  EXPECT_TRUE(k.at("unexplained").get<bool>());
}

TEST(Report, TextNamesTheFitsWithUnitsTheParametersAndTheVerdict) {
  const std::string t = diagnosis_text(hand_made());
  EXPECT_TRUE(contains(t, "x_meas 87.5 %")) << t;
  EXPECT_TRUE(contains(t, "x_meas 98.2 %") || contains(t, "x_meas 98.3 %")) << t;
  EXPECT_TRUE(contains(t, "k = 4.25")) << t;
  EXPECT_TRUE(contains(t, "x_meas: t = 1.5 .. 2.5 s")) << t;
  EXPECT_TRUE(contains(t, "falsified")) << t;
  EXPECT_TRUE(contains(t, "Verdict: Missing physics: coulomb_friction (v).")) << t;
  EXPECT_TRUE(contains(t, "coulomb_friction in v: -Fc*sign(v)")) << t;
  EXPECT_TRUE(contains(t, "Fc = 0.31, bounded-error interval [0.28, 0.33]")) << t;
  EXPECT_TRUE(contains(t, "estimates: output error linearised at the estimate [0.305, 0.315]")) << t;
  // Without a certified equation-error PUI there is no bounded-error interval, only estimates.
  Diagnosis d = hand_made();
  d.effects[0].parameters[0].ee_certified = false;
  const std::string u = diagnosis_text(d);
  EXPECT_TRUE(contains(u, "Fc = 0.31, no bounded-error interval (equation-error PUI not certified)")) << u;
  const auto j = nlohmann::json::parse(diagnosis_json(d, ""));
  const auto& fcj = j.at("effects").at(0).at("parameters").at("Fc");
  EXPECT_TRUE(fcj.contains("estimate_interval_output_error_linearised"));
  EXPECT_TRUE(fcj.contains("estimate_statistical_95"));
  EXPECT_FALSE(fcj.contains("interval_output_error"));
}

TEST(Report, FileValuesThatBlowUpAreNotAvailableWithWhyNotANumber) {
  Diagnosis d = hand_made();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  d.fit_start_estimation = {nan};
  d.fit_start_validation = {nan};
  d.fit_start_note = "the file's values cannot be simulated over the estimation record: the simulation blew up at t = 358.672 s";
  const std::string text = diagnosis_text(d);
  EXPECT_TRUE(contains(text, "x_meas not available")) << text;
  EXPECT_TRUE(contains(text, "blew up at t = 358.672 s")) << text;
  EXPECT_FALSE(contains(text, "nan %")) << text;
  const auto j = nlohmann::json::parse(diagnosis_json(d, ""));
  EXPECT_TRUE(j.at("nominal").at("fit_before_calibration").at("estimation").at("x_meas").is_null());
  EXPECT_EQ(j.at("nominal").at("fit_before_calibration_note").get<std::string>(), d.fit_start_note);
}

// An effect the data cannot tell from another: the other is printed beside it, in the text and
// the JSON, with its share of the misfit; none printed when there is none.
TEST(Report, EquallyGoodAlternativesArePrintedWhereThereAreSome) {
  Diagnosis d = hand_made();
  EXPECT_FALSE(contains(diagnosis_text(d), "equally good")) << diagnosis_text(d);
  EXPECT_TRUE(nlohmann::json::parse(diagnosis_json(d, "")).at("effects").at(0).at("equally_good").empty());
  d.effects[0].equally_good.push_back({{"constant_offset"}, {"v"}, 0.034, 0.029});
  const std::string t = diagnosis_text(d);
  EXPECT_TRUE(contains(t, "equally good on these data: constant_offset in v (removes 96.6 % of the squared misfit, 97.1 % on validation)"))
      << t;
  EXPECT_TRUE(contains(t, "the data cannot tell them apart")) << t;
  const auto a = nlohmann::json::parse(diagnosis_json(d, "")).at("effects").at(0).at("equally_good").at(0);
  EXPECT_EQ(a.at("effects").at(0).get<std::string>(), "constant_offset");
  EXPECT_EQ(a.at("equations").at(0).get<std::string>(), "v");
  EXPECT_DOUBLE_EQ(a.at("misfit_share").get<double>(), 0.034);
}
