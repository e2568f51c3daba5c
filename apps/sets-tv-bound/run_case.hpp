#pragma once
// sets-tv-bound: one case of Tables I-III on the crane — simulate it (sets::crane), estimate the
// bounds with the l-inf LP (8) (optionally re-linearised) and the sparse MILP (14), print a line
// per method and return the case's JSON.

#include <string>

#include "common/json_output.hpp"
#include "sets/examples/crane.hpp"

struct TvSettings {
  bool linf = true, milp = true;
  int N = 120;
  unsigned seed = 1, input_seed = 1;
  std::string input = "square", plant = "exact", milp_eps = "linf", formulation = "single", solver = "jump";
  double mu_rel = 0.001, box_rel = 4, time_limit = 60, gap = 1e-4;
  long node_limit = 0;
  bool warm = true, verbose = false;
  int relinearise = 0, grid = 1;
};

sets::app::Json run_case(const sets::crane::Case& c, const TvSettings& s);
