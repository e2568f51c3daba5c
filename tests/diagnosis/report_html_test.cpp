// The diagnosis page: what it says and that it says it safely (sets/diagnosis/report_html.hpp).
// The page in a browser: tests/diagnosis/report_html_chromium_test.py.

#include <gtest/gtest.h>

#include <limits>

#include "sets/diagnosis/report_html.hpp"
#include "sets/models/model_file.hpp"

using namespace sets;

namespace {

Diagnosis small_diagnosis() {
  Diagnosis d;
  d.nominal = parse_model(R"json({"name": "axis <A&B>", "time": "t", "inputs": {"u": "force"},
    "parameters": {"M": 2.0}, "states": {"q": "q_meas", "v": 0.0},
    "derivatives": {"q": "v", "v": "u/M"}, "outputs": {"q": "q_meas"},
    "units": {"q": "m", "M": "kg"}})json", "axis.json");
  d.nominal.units.push_back({"Fc", "N"});  // as if the catalogue gave the new parameter's unit
  d.augmented = d.nominal;
  d.outputs = {"q_meas"};
  d.free_nominal = {"M"};
  d.fit_start_estimation = {12.5};
  d.fit_nominal_estimation = {80.25};
  d.fit_augmented_estimation = {97.5};
  d.fit_start_validation = {11};
  d.fit_nominal_validation = {79};
  d.fit_augmented_validation = {96.75};
  d.has_validation = true;
  d.windows = {{"q_meas", 1.5, 2.25, 0.0125, true}};
  d.error_bound = {0.003};
  d.bound_note = "3 sigma of the noise";
  d.verdict = "coulomb_friction is missing";
  DiagnosedEffect e;
  e.name = "coulomb_friction";
  e.equation = "v";
  e.term = "-Fc*sign(v)/M";
  e.evidence = "residual jumps at reversals";
  EffectParameter p;
  p.name = "Fc";
  p.estimate = 0.31;
  p.lo = 0.25, p.hi = 0.35, p.estimate_oe_lo = 0.2, p.estimate_oe_hi = 0.4, p.has_ee = true, p.ee_lo = 0.25, p.ee_hi = 0.35;
  p.estimate_stat_lo = 0.3, p.estimate_stat_hi = 0.32;
  e.parameters = {p};
  d.effects = {e};
  return d;
}

bool has(const std::string& page, const std::string& s) { return page.find(s) != std::string::npos; }

}  // namespace

TEST(ReportHtml, ShowsVerdictFitsAndIntervalsUnderHonestNamesWithUnits) {
  const std::string page = diagnosis_html(small_diagnosis(), {{"signals_estimation.png", "signals"}});
  EXPECT_TRUE(has(page, "<!DOCTYPE html>"));
  EXPECT_TRUE(has(page, "coulomb_friction is missing"));
  EXPECT_TRUE(has(page, "<td>80.25</td>"));   // calibrated nominal fit
  EXPECT_TRUE(has(page, "<td>12.50</td>"));   // fits with two decimals
  EXPECT_TRUE(has(page, "<td>96.75</td>"));   // augmented validation fit
  EXPECT_TRUE(has(page, "<b>[0.25, 0.35]</b> N"));  // guaranteed interval with the unit of Fc
  EXPECT_TRUE(has(page, "statistical 95&nbsp;% interval"));
  EXPECT_TRUE(has(page, "not guaranteed"));
  EXPECT_TRUE(has(page, "<td>2 kg</td>"));    // calibrated parameter with its unit
  EXPECT_TRUE(has(page, "q_meas <span class=\"unit\">[m]</span>"));  // output column takes its symbol's unit
  EXPECT_TRUE(has(page, "0.0125 m"));         // window RMS in output units
  EXPECT_TRUE(has(page, "<img src=\"signals_estimation.png\""));
}

TEST(ReportHtml, EscapesTextAndNeedsNoExternalResource) {
  const std::string page = diagnosis_html(small_diagnosis(), {{"a\"b.png", "x<y"}});
  EXPECT_TRUE(has(page, "axis &lt;A&amp;B&gt;"));
  EXPECT_FALSE(has(page, "<A&B>"));
  EXPECT_TRUE(has(page, "src=\"a&quot;b.png\""));
  EXPECT_FALSE(has(page, "<script"));
  EXPECT_FALSE(has(page, "http"));
}

TEST(ReportHtml, SaysSoWhenNothingIsMissing) {
  Diagnosis d = small_diagnosis();
  d.effects.clear();
  d.nothing_missing = true;
  d.verdict = "nothing missing";
  const std::string page = diagnosis_html(d, {});
  EXPECT_TRUE(has(page, "class=\"verdict ok\""));
  EXPECT_TRUE(has(page, "explains the data to within the noise"));
  EXPECT_FALSE(has(page, "<h2>Figures</h2>"));
}

TEST(ReportHtml, SaysWhyTheFileValuesHaveNoFit) {
  Diagnosis d = small_diagnosis();
  d.fit_start_estimation = {std::numeric_limits<double>::quiet_NaN()};
  d.fit_start_note = "the file's values cannot be simulated over the estimation record: the simulation blew up at t = 3 s (v <x>)";
  const std::string page = diagnosis_html(d, {});
  EXPECT_TRUE(has(page, "<td class=\"l\">nominal, file values</td><td class=\"l\">estimation</td><td>&ndash;</td>")) << page;
  EXPECT_TRUE(has(page, "blew up at t = 3 s (v &lt;x&gt;)")) << page;
  EXPECT_FALSE(has(page, ">nan<"));
}

TEST(ReportHtml, ListsTheEquallyGoodAlternativesOfAnEffect) {
  Diagnosis d = small_diagnosis();
  EXPECT_FALSE(has(diagnosis_html(d, {}), "Equally good on these data"));
  d.effects[0].equally_good.push_back({{"constant_offset", "dead_zone"}, {"v", "u"}, 0.05, 0.04});
  const std::string page = diagnosis_html(d, {});
  EXPECT_TRUE(has(page, "Equally good on these data"));
  EXPECT_TRUE(has(page, "constant_offset in v + dead_zone in u (removes 95.0 % of the squared misfit, 96.0 % on validation)"));
}
