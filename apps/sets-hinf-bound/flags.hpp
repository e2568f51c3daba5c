#pragma once
// sets-hinf-bound's flags: their declaration, and the Settings, priors and data they give.

#include <numbers>
#include <string>

#include "common/cli.hpp"
#include "runs.hpp"

// Flags that only shape Settings (read once, after parsing).
struct Flags {
  double pole = 0.93, pole_angle = 0.66, v_bar = -1, w_min = 0, w_max = std::numbers::pi;
  int grid_points = 150;
  std::string shape = "rectangle", json_path, plot_path, data_path, ucol, ycol, rcol;
  bool per_frequency = false;
};

void add_flags(sets::app::Cli& cli, Settings& s, Flags& f);
/// Basis, grid, priors and noise model from the flags; returns the note on derived priors.
std::string configure(Settings& s, Flags& f, const sets::TransferFunction& G0);
void print_header(const Settings& s, const Flags& f, const std::string& prior_note);
/// The real data set (--data), or the built-in example's description (its data are simulated per run).
sets::HinfData load_data(Settings& s, const Flags& f, const sets::TransferFunction& G0);
