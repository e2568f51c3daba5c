#pragma once
// sets-ss-uncertainty: its settings, flag parsing of the rows of Gamma_1, and the printout of the
// Monte Carlo study of Section V (sets::farah::study: Table I and the failure rates). The method
// is sets::ss_uncertainty.

#include <string>
#include <vector>

#include "sets/examples/farah_study.hpp"

struct Settings {
  sets::farah::StudyOptions study;   // also past, estimate_d and level for --data
  std::string rows;                  // "1:0,1:1,1:2" = output:lag (1-based output)
  std::string selection = "output-major";
  std::string noise = "gaussian";    // or "uniform" (bounded: the guaranteed set's assumption holds)
  std::string json_path;
  // real data
  std::string data, inputs, outputs;
  int order = 0;
};

/// "1:0,1:1,1:2" (OUTPUT:LAG, OUTPUT from 1) -> rows; InputError naming --rows.
std::vector<sets::ObservabilityRow> parse_rows(const std::string& spec, int ny);
sets::RowSelection parse_selection(const std::string& s);

/// Section V on the example system of sets::farah: runs sets::farah::study, prints Table I and the
/// failure rates, writes the JSON. Returns the exit code.
int monte_carlo(const Settings& st);
