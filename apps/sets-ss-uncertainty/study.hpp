#pragma once
// sets-ss-uncertainty: its settings, flag parsing of the rows of Gamma_1, and the Monte Carlo study
// of Section V (Table I and the failure rates). The method is sets::ss_uncertainty.

#include <string>
#include <vector>

#include "sets/methods/ss_uncertainty/ss_uncertainty.hpp"

struct Settings {
  int runs = 1000;
  unsigned long long seed = 1;
  double snr_db = 20;
  int past = 20;
  int samples = 1000;
  int threads = 2;
  bool estimate_d = false;
  std::string rows;                  // "1:0,1:1,1:2" = output:lag (1-based output)
  std::string selection = "output-major";
  sets::LevelSetOptions level;
  int fps_pui_runs = -1;             // PUIs by LP in the first K runs (-1: all)
  std::string noise = "gaussian";    // or "uniform" (bounded: the guaranteed set's assumption holds)
  double noise_bound_sigmas = 4;     // Gaussian noise: the bound the guaranteed set assumes, in sigmas
  bool guaranteed = true;            // compute the guaranteed set in every run
  int guaranteed_pui_runs = 0;       // its PUIs by LP in the first K runs (-1: all); costly (interval regressors)
  std::string json_path;
  // real data
  std::string data, inputs, outputs;
  int order = 0;
};

/// "1:0,1:1,1:2" (OUTPUT:LAG, OUTPUT from 1) -> rows; InputError naming --rows.
std::vector<sets::ObservabilityRow> parse_rows(const std::string& spec, int ny);
sets::RowSelection parse_selection(const std::string& s);

/// Section V on the example system of sets::farah: runs, Table I, failure rates, JSON. Returns the exit code.
int monte_carlo(const Settings& st);
