#pragma once
// The diagnosis as a web page an engineer reads (sets-diagnose --report DIR writes it as
// DIR/index.html beside the figures): verdict, fit tables, calibrated parameters, the effects
// found with their intervals under their honest names, where the model fails, and the figures.
// Self-contained: inline style, no script, no external resource; the PNGs are referenced by
// file name (they sit beside the page).

#include <string>
#include <vector>

#include "sets/diagnosis/diagnosis.hpp"

namespace sets {

struct ReportFigure {
  std::string file;     // PNG file name, relative to the page
  std::string caption;  // one sentence: what the figure shows
};

/// The page. Its numbers are read from diagnosis_json(d, augmented_path), so the page and the
/// JSON cannot disagree; units come from the model file's `units` field (docs/model-format.md).
std::string diagnosis_html(const Diagnosis& d, const std::vector<ReportFigure>& figures,
                           const std::string& augmented_path = "augmented_model.json");

}  // namespace sets
