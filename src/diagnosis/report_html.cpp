// The diagnosis as one HTML page (see sets/diagnosis/report_html.hpp). Everything shown is read
// back from the JSON of the diagnosis, so the page says what the JSON says.

#include "sets/diagnosis/report_html.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace sets {

namespace {

using J = nlohmann::ordered_json;

std::string escape(const std::string& s) {
  std::string r;
  for (char c : s) {
    switch (c) {
      case '&': r += "&amp;"; break;
      case '<': r += "&lt;"; break;
      case '>': r += "&gt;"; break;
      case '"': r += "&quot;"; break;
      case '\'': r += "&#39;"; break;
      default: r += c;
    }
  }
  return r;
}

// A number as an engineer reads it: 5 significant digits; JSON null (a non-finite value) as "–".
std::string num(const J& v, int digits = 5) {
  if (!v.is_number()) return "&ndash;";
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, v.get<double>());
  return b;
}
// A fit in percent with two decimals (as the terminal report; 99 % and 99.00 % differ in what they claim).
std::string percent(const J& v) {
  if (!v.is_number()) return "&ndash;";
  char b[64];
  std::snprintf(b, sizeof b, "%.2f", v.get<double>());
  return b;
}
std::string interval(const J& v) {
  if (!v.is_array() || v.size() != 2) return "&ndash;";
  return "[" + num(v[0]) + ", " + num(v[1]) + "]";
}
std::string with_unit(const std::string& name, const std::string& unit) {
  return escape(name) + (unit.empty() ? "" : " <span class=\"unit\">[" + escape(unit) + "]</span>");
}
std::string unit_suffix(const std::string& unit) { return unit.empty() ? "" : " " + escape(unit); }

const char* style = R"(
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;max-width:1180px;margin:1.5em auto;padding:0 1em;color:#222;line-height:1.4}
h1{font-size:1.5em;margin-bottom:.2em}h2{font-size:1.2em;border-bottom:1px solid #ccc;padding-bottom:.2em;margin-top:1.6em}
.verdict{font-size:1.15em;padding:.8em 1em;border-left:6px solid #c33;background:#fbeaea}
.verdict.ok{border-color:#393;background:#eaf6ea}
table{border-collapse:collapse;margin:.6em 0}th,td{border:1px solid #ccc;padding:.3em .6em;text-align:right;vertical-align:top}
th{background:#f2f2f2}td.l,th.l{text-align:left}.unit{color:#666;font-weight:normal}
.note{color:#555;font-size:.92em}figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}
figcaption{color:#444;font-size:.92em;margin-top:.3em}code{background:#f4f4f4;padding:0 .2em}
)";

void fit_table(std::ostringstream& o, const J& j, const std::vector<std::string>& outputs, bool validation) {
  o << "<table><tr><th class=\"l\">model</th><th class=\"l\">record</th>";
  for (const auto& y : outputs) o << "<th>" << escape(y) << " fit [%]</th>";
  o << "</tr>\n";
  auto row = [&](const char* label, const J& fits, const char* record) {
    if (!fits.is_object() || fits.empty()) return;
    o << "<tr><td class=\"l\">" << label << "</td><td class=\"l\">" << record << "</td>";
    for (const auto& y : outputs) o << "<td>" << (fits.contains(y) ? percent(fits[y]) : "&ndash;") << "</td>";
    o << "</tr>\n";
  };
  row("nominal, file values", j["nominal"]["fit_before_calibration"]["estimation"], "estimation");
  row("nominal, calibrated", j["nominal"]["fit"]["estimation"], "estimation");
  if (!j["effects"].empty()) row("augmented", j["augmented"]["fit"]["estimation"], "estimation");
  if (validation) {
    row("nominal, file values", j["nominal"]["fit_before_calibration"]["validation"], "validation");
    row("nominal, calibrated", j["nominal"]["fit"]["validation"], "validation");
    if (!j["effects"].empty()) row("augmented", j["augmented"]["fit"]["validation"], "validation");
  }
  o << "</table>\n<p class=\"note\">fit = 100 (1 &minus; &Vert;y &minus; &#375;&Vert; / &Vert;y &minus; mean y&Vert;)";
  const std::string why = j["nominal"].value("fit_before_calibration_note", "");
  if (!why.empty()) o << "; file values &ndash;: " << escape(why);
  o << "</p>\n";
}

void effects_section(std::ostringstream& o, const J& j, const ModelFile& model) {
  o << "<h2>Missing physics found</h2>\n";
  if (j["effects"].empty()) {
    o << "<p>None: " << (j["nothing_missing"].get<bool>() ? "the nominal model explains the data to within the noise."
                                                             : "no hypothesis of the catalogue improved the fit enough.")
      << "</p>\n";
    return;
  }
  o << "<table><tr><th>#</th><th class=\"l\">effect</th><th class=\"l\">equation</th><th class=\"l\">term added</th>"
       "<th class=\"l\">parameter</th><th>estimate</th><th>bounded-error interval<br><span class=\"unit\">under the stated "
       "error bounds</span></th><th>equation-error PUI</th><th>estimate: output-error PUI<br><span class=\"unit\">linearised at the "
       "estimate</span></th><th>estimate: statistical 95&nbsp;% interval<br><span class=\"unit\">white-noise assumption, not "
       "guaranteed</span></th></tr>\n";
  int k = 0;
  for (const auto& e : j["effects"]) {
    ++k;
    const auto& ps = e["parameters"];
    const std::size_t rows = std::max<std::size_t>(1, ps.size());
    bool first = true;
    auto head = [&] {
      o << "<tr><td rowspan=\"" << rows << "\">" << k << "</td><td class=\"l\" rowspan=\"" << rows << "\">"
        << escape(e["name"].get<std::string>()) << "</td><td class=\"l\" rowspan=\"" << rows << "\"><code>"
        << escape(e["equation"].get<std::string>()) << "</code></td><td class=\"l\" rowspan=\"" << rows << "\"><code>"
        << escape(e["term"].get<std::string>()) << "</code></td>";
    };
    if (ps.empty()) head(), o << "<td colspan=\"6\"></td></tr>\n";
    for (auto it = ps.begin(); it != ps.end(); ++it) {
      if (first) head();
      else o << "<tr>";
      first = false;
      const std::string u = unit_suffix(model.unit(it.key()));
      const auto& p = it.value();
      o << "<td class=\"l\">" << escape(it.key()) << "</td><td>" << num(p["estimate"]) << u << "</td><td><b>"
        << interval(p["interval"]) << "</b>" << u << "</td><td>" << interval(p["interval_equation_error"])
        << "</td><td>" << interval(p["estimate_interval_output_error_linearised"]) << "</td><td>" << interval(p["estimate_statistical_95"])
        << "</td></tr>\n";
    }
  }
  o << "</table>\n<ul class=\"note\">";
  for (const auto& e : j["effects"]) {
    o << "<li><b>" << escape(e["name"].get<std::string>()) << "</b>: " << escape(e["evidence"].get<std::string>());
    if (e.contains("equally_good") && !e["equally_good"].empty()) {
      o << "<br>Equally good on these data (the data cannot tell them apart):";
      for (const auto& a : e["equally_good"]) o << " " << escape(a["text"].get<std::string>()) << ";";
    }
    o << "</li>";
  }
  o << "</ul>\n<p class=\"note\">The bounded-error interval is the equation-error parameter uncertainty interval "
       "(certified LP bounds) met with the parameter's declared range; it holds when the error bounds below hold. The "
       "output-error interval (linearised at the estimate) and the statistical one are estimates and do not cut it. "
    << escape(j["bound_note"].get<std::string>()) << "</p>\n";
}

void mismatch_section(std::ostringstream& o, const J& j, const ModelFile& model) {
  const auto& m = j["mismatch"];
  o << "<h2>Where the nominal model fails</h2>\n";
  if (!m["error_bound"].empty()) {
    o << "<p>Error bound per output (used for the windows and the intervals):";
    for (auto it = m["error_bound"].begin(); it != m["error_bound"].end(); ++it)
      o << (it == m["error_bound"].begin() ? " " : "; ") << escape(it.key()) << " &le; " << num(it.value())
        << unit_suffix(model.unit(it.key()));
    o << ".</p>\n";
  }
  if (!m["windows"].empty()) {
    o << "<table><tr><th class=\"l\">output</th><th>from [s]</th><th>to [s]</th><th>residual RMS</th><th class=\"l\">"
         "falsified (no parameter value keeps the residual within the bound)</th></tr>\n";
    for (const auto& w : m["windows"])
      o << "<tr><td class=\"l\">" << escape(w["output"].get<std::string>()) << "</td><td>" << num(w["start"]) << "</td><td>"
        << num(w["end"]) << "</td><td>" << num(w["rms"], 4) << unit_suffix(model.unit(w["output"].get<std::string>()))
        << "</td><td class=\"l\">" << (w["falsified"].get<bool>() ? "yes" : "no") << "</td></tr>\n";
    o << "</table>\n";
  }
  if (!m["regions"].empty()) {
    o << "<p>Residual concentrated:</p><ul>";
    for (const auto& r : m["regions"])
      o << "<li>" << escape(r["description"].get<std::string>()) << ": " << num(100 * r["residual_share"].get<double>(), 3)
        << "&nbsp;% of the squared residual in " << num(100 * r["sample_share"].get<double>(), 3)
        << "&nbsp;% of the samples</li>";
    o << "</ul>\n";
  }
  for (const auto& b : m["frequency_band"])
    o << "<p>Frequency band of the " << escape(b["output"].get<std::string>()) << " residual (80&nbsp;% of its energy): "
      << interval(b["band_hz"]) << " Hz, peak " << num(b["peak_hz"]) << " Hz.</p>\n";
  if (!m["varying_parameters"].empty()) {
    o << "<p>Parameters that would have to vary over time (Salehpour&ndash;Johansson <i>estimates</i>, not bounds):</p>"
         "<table><tr><th class=\"l\">parameter</th><th>calibrated</th><th>estimated range</th><th>share of the "
         "residual's window-norm bound removed</th><th class=\"l\">method</th></tr>\n";
    for (const auto& v : m["varying_parameters"]) {
      const std::string u = unit_suffix(model.unit(v["name"].get<std::string>()));
      o << "<tr><td class=\"l\">" << escape(v["name"].get<std::string>()) << "</td><td>" << num(v["value"]) << u
        << "</td><td>" << interval(v["range"]) << u << "</td><td>" << num(100 * v["explained"].get<double>(), 3)
        << "&nbsp;%</td><td class=\"l\">" << escape(v["method"].get<std::string>()) << "</td></tr>\n";
    }
    o << "</table>\n";
  }
}

// The estimated noise level per output: from the calibrated nominal's residual (the floor the
// rules use) and from the final model's (the augmented one when effects were named).
void noise_section(std::ostringstream& o, const J& j, const std::vector<std::string>& outputs, const ModelFile& model) {
  o << "<h2>Noise level (estimated)</h2>\n<table><tr><th class=\"l\">output</th><th class=\"l\">residual of</th>"
       "<th>sigma</th><th class=\"l\">method</th><th class=\"l\">record</th><th class=\"l\">reason</th></tr>\n";
  auto rows = [&](const J& levels, const char* label) {
    for (const auto& y : outputs) {
      if (!levels.contains(y)) continue;
      const J& n = levels[y];
      o << "<tr><td class=\"l\">" << escape(y) << "</td><td class=\"l\">" << label << "</td><td>" << num(n["sigma"], 3)
        << unit_suffix(model.unit(y)) << "</td><td class=\"l\">" << escape(n["method"].get<std::string>()) << "</td><td class=\"l\">"
        << escape(n["record"].get<std::string>()) << "</td><td class=\"l\">" << escape(n["reason"].get<std::string>()) << "</td></tr>\n";
    }
  };
  rows(j["noise_level"], "calibrated nominal (the rules&#39; floor)");
  if (!j["effects"].empty()) rows(j["noise_level_final"], "augmented model (final)");
  o << "</table>\n<p class=\"note\">Estimates, not bounds (docs/methods/noise-level.md).</p>\n";
}

}  // namespace

std::string diagnosis_html(const Diagnosis& d, const std::vector<ReportFigure>& figures,
                           const std::string& augmented_path) {
  const J j = J::parse(diagnosis_json(d, augmented_path));
  const ModelFile& model = d.nominal;
  const std::string title = "Diagnosis" + (model.name.empty() ? std::string() : ": " + model.name);
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" << escape(title)
    << "</title>\n<style>" << style << "</style></head>\n<body>\n<h1>" << escape(title) << "</h1>\n"
    << "<p class=\"note\">sets-diagnose report" << (model.source.empty() ? "" : " of " + escape(model.source))
    << ". Outputs compared: ";
  for (std::size_t i = 0; i < d.outputs.size(); ++i)
    o << (i ? ", " : "") << with_unit(d.outputs[i], model.unit(d.outputs[i]));
  o << ".</p>\n<div class=\"verdict" << (j["effects"].empty() && j["nothing_missing"].get<bool>() ? " ok" : "")
    << "\"><b>Verdict:</b> " << escape(j["verdict"].get<std::string>()) << "</div>\n";
  o << "<h2>Fit</h2>\n";
  fit_table(o, j, d.outputs, d.has_validation);
  o << "<h2>Calibrated nominal parameters</h2>\n<table><tr><th class=\"l\">parameter</th><th>value</th></tr>\n";
  for (auto it = j["nominal"]["parameters"].begin(); it != j["nominal"]["parameters"].end(); ++it)
    o << "<tr><td class=\"l\">" << escape(it.key()) << "</td><td>" << num(it.value()) << unit_suffix(model.unit(it.key()))
      << "</td></tr>\n";
  o << "</table>\n";
  noise_section(o, j, d.outputs, model);
  effects_section(o, j, model);
  mismatch_section(o, j, model);
  if (!figures.empty()) {
    o << "<h2>Figures</h2>\n";
    for (const auto& f : figures)
      o << "<figure><img src=\"" << escape(f.file) << "\" alt=\"" << escape(f.caption) << "\"><figcaption>"
        << escape(f.caption) << "</figcaption></figure>\n";
  }
  if (!augmented_path.empty())
    o << "<p>Augmented model file: <a href=\"" << escape(augmented_path) << "\"><code>" << escape(augmented_path)
      << "</code></a>. Full numbers: the JSON of <code>sets-diagnose --json</code>.</p>\n";
  o << "<p class=\"note\">Computed in " << num(j["seconds"], 3) << " s.</p>\n</body></html>\n";
  return o.str();
}

}  // namespace sets
