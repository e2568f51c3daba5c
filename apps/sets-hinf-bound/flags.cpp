#include "flags.hpp"

#include <complex>
#include <iostream>

#include "sets/core/error.hpp"
#include "sets/data/recording.hpp"
#include "sets/examples/hakvoort.hpp"

void add_flags(sets::app::Cli& cli, Settings& s, Flags& f) {
  CLI::App& app = cli.app();
  auto& p = s.structure.priors;
  auto& o = s.options;
  app.add_option("--N", s.N, "samples per data set (built-in example)")->check(CLI::Range(100, 1000000));
  app.add_option("--runs", s.runs, "Monte Carlo runs (built-in example; 1 = a single data set)")->check(CLI::Range(1, 100000));
  app.add_option("--alpha", o.uncertainty.alpha, "probability that G0 is in the set (stochastic noise)");
  app.add_option("--basis", s.basis_name, "fir | laguerre | kautz")->check(CLI::IsMember({"fir", "laguerre", "kautz"}));
  app.add_option("--order", s.structure.order, "number of basis functions n")->check(CLI::PositiveNumber);
  app.add_option("--pole", f.pole, "basis pole: Laguerre a, or Kautz |xi|");
  app.add_option("--pole-angle", f.pole_angle, "Kautz pole angle arg(xi) in rad/sample");
  app.add_option("--noise", s.noise_name, "stochastic | bounded")->check(CLI::IsMember({"stochastic", "bounded"}));
  app.add_option("--shape", f.shape, "rectangle | ellipse (stochastic)")->check(CLI::IsMember({"rectangle", "ellipse"}));
  app.add_flag("--per-frequency", f.per_frequency, "alpha per frequency (the paper) instead of simultaneous");
  app.add_option("--grid", f.grid_points, "number of frequencies in (0, pi)")->check(CLI::Range(2, 100000));
  app.add_option("--w-min", f.w_min, "lowest grid frequency (rad/sample, >= 0)");
  app.add_option("--w-max", f.w_max, "highest grid frequency (rad/sample, <= pi)");
  app.add_option("--nominal-order", o.nominal.order, "order of the nominal model");
  app.add_option("--polygon", o.nominal.polygon_sides, "K: sides of the polygon replacing |.| in the nominal-model LP");
  app.add_option("--weight-degree", o.weight.degree, "degree of the trigonometric polynomial |W^-1|^2");
  app.add_option("--rho", p.rho, "prior: |g0(k)| <= M rho^k (basis coefficients)");
  app.add_option("--M", p.M, "prior M (built-in: derived from the true coefficients when not given)");
  app.add_option("--u-bar", p.u_bar, "prior: |u(t)| <= u_bar before the data");
  app.add_option("--M-ic", p.M_ic, "prior: impulse response |h0(s)| <= M_ic rho_ic^s (initial conditions)");
  app.add_option("--rho-ic", p.rho_ic, "prior rho_ic");
  app.add_option("--v-bar", f.v_bar, "prior: |v(t)| <= v_bar (bounded noise)");
  app.add_option("--noise-std", s.noise_std,
                 "built-in: std (stochastic) or bound (bounded) of the white noise before the 1/(1-0.7q^-1) filter");
  app.add_option("--seed", s.seed, "random seed");
  cli.add_output_file("--json", f.json_path, "write the results as JSON");
  cli.add_output_file("--plot", f.plot_path, "write a PNG plot (gnuplot)");
  app.add_option("--data", f.data_path, "CSV file with real data (header row optional)");
  app.add_option("--u", f.ucol, "input column (name or 1-based number)");
  app.add_option("--y", f.ycol, "output column");
  app.add_option("--r", f.rcol, "reference column: instrumental variables for closed-loop data");
  app.add_flag("--quiet", s.quiet, "do not print the per-frequency table");
}

std::string configure(Settings& s, Flags& f, const sets::TransferFunction& G0) {
  auto& p = s.structure.priors;
  auto& o = s.options;
  s.builtin = f.data_path.empty();
  s.bounded = s.noise_name == "bounded";
  s.structure.basis = s.basis_name == "fir"        ? sets::OrthonormalBasis::fir()
                      : s.basis_name == "laguerre" ? sets::OrthonormalBasis::laguerre(f.pole)
                                                   : sets::OrthonormalBasis::kautz(std::polar(f.pole, f.pole_angle));
  s.structure.grid = sets::midpoint_grid(f.grid_points, f.w_min, f.w_max);
  sets::check_frequency_grid(s.structure.grid);
  const double M = p.M;
  p.M = sets::HinfPriors{}.M;
  sets::check_priors(p);  // rho first: the derived M needs a valid rho
  p.M = M;
  std::string prior_note;
  if (s.builtin)
    p = sets::hakvoort::priors_for(G0, s.structure.basis, p, prior_note);  // true for G0, 20% margin
  else if (p.M <= 0)
    throw sets::InputError("--M: the tail prior M must be given with --data");
  if (s.bounded && f.v_bar < 0) {
    if (!s.builtin) throw sets::InputError("--v-bar: the noise bound must be given for --noise bounded");
    f.v_bar = s.noise_std / 0.3;  // |v| <= sum_s 0.7^s |e| <= e_max / 0.3
  }
  o.uncertainty.noise = s.bounded ? sets::NoiseModel::bounded : sets::NoiseModel::stochastic;
  o.uncertainty.shape = f.shape == "ellipse" ? sets::RegionShape::ellipse : sets::RegionShape::rectangle;
  o.uncertainty.simultaneous = !f.per_frequency;
  o.uncertainty.v_bar = std::max(0.0, f.v_bar);
  return prior_note;
}

void print_header(const Settings& s, const Flags& f, const std::string& prior_note) {
  const auto& p = s.structure.priors;
  std::cout << "sets-hinf-bound: Hakvoort-Van den Hof H-infinity error bound\n";
  std::cout << "  basis: " << s.structure.basis.describe() << ", n = " << s.structure.order << " functions\n";
  std::cout << "  priors: |g0(k)| <= " << p.M << " * " << p.rho << "^k, |u(t<=0)| <= " << p.u_bar;
  if (p.M_ic > 0) std::cout << ", |h0(s)| <= " << p.M_ic << " * " << p.rho_ic << "^s";
  std::cout << (s.bounded ? ", |v(t)| <= " + std::to_string(f.v_bar)
                          : ", noise stochastic, alpha = " + std::to_string(s.options.uncertainty.alpha))
            << "\n";
  if (!prior_note.empty()) std::cout << "  " << prior_note << "\n";
}

sets::HinfData load_data(Settings& s, const Flags& f, const sets::TransferFunction& G0) {
  sets::HinfData data;
  if (!s.builtin) {
    if (f.ucol.empty() || f.ycol.empty()) throw sets::InputError("--data needs --u and --y");
    const sets::Recording c = sets::read_csv(f.data_path);
    data.u = c.matrix({f.ucol}, "--u").col(0);
    data.y = c.matrix({f.ycol}, "--y").col(0);
    if (!f.rcol.empty()) data.r = c.matrix({f.rcol}, "--r").col(0);
    s.runs = 1;
    std::cout << "  data: " << f.data_path << ", " << data.u.size() << " samples\n";
  } else {
    std::cout << "  true system (order 4): " << G0.to_string() << "\n"
              << "    poles 0.97 e^{+-0.6i} (lightly damped resonance, damping ratio ~0.05), 0.8 e^{+-0.9i}\n"
              << "  data: N = " << s.N << ", u uniform in [-1, 1], noise " << (s.bounded ? "uniform" : "Gaussian")
              << " white (" << s.noise_std << ") through 1/(1 - 0.7 q^-1)\n";
  }
  return data;
}

