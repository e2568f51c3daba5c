#pragma once
// sets-lpv-pui's reproduction of Cerone & Regruto's Tables I-IV: Monte Carlo runs of the paper's
// experiment (sets::cerone_regruto), our figures printed beside the paper's, and the JSON.

#include <string>
#include <vector>

#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/methods/lpv_pui/unreliable_lpv_pui.hpp"

struct TableRuns {
  std::vector<int> tables;   // indices into sets::cerone_regruto::paper_tables()
  int runs = 20;
  std::uint64_t seed = 1;
  double delta_e = 0;        // > 0: one noise bound instead of the four levels
  sets::PuiOptions options;
  unsigned threads = 1;
  std::string json_path;
  // Diagnostics (docs/reproduction/cerone.md): regressor boxes without some errors (not
  // guaranteed), and the lagged reading of the coefficients (simulation and identification).
  sets::RegressorErrors regressor_errors = sets::RegressorErrors::both;
  bool lagged_coefficients = false;
};

/// Runs, prints and writes the tables; returns the exit code.
int run_tables(const TableRuns& runs);
