// sets-hinf-bound: a nominal model, a weighting W and a bound b with
// ||W (Ghat - G0)||_inf <= b, from time-domain data (Hakvoort & Van den Hof).
// Built-in example (no --data): Monte Carlo over simulated data; with --data: one real data set.


#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <random>
#include <sstream>

#include "common/cli.hpp"
#include "common/gnuplot.hpp"
#include "common/json_output.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/data/recording.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"

namespace fs = std::filesystem;
using cd = std::complex<double>;
using sets::InputError;

namespace {
constexpr double pi = std::numbers::pi;

sets::RationalModel true_system() { return sets::hinf_example_system(); }

Eigen::VectorXd lfilter(const Eigen::VectorXd& b, const Eigen::VectorXd& a, const Eigen::VectorXd& x) {
  sets::DiscreteTf f{b, a, {}};
  return f.filter(x);
}

struct Simulated {
  Eigen::VectorXd u, y;
};
// Input uniform in [-1, 1] (so u_bar = 1), started 3000 samples before the record: the initial
// conditions are real and unknown. Noise: e filtered by 1/(1 - 0.7 q^-1); Gaussian (stochastic)
// or uniform with |e| <= e_max (bounded, then |v| <= e_max / 0.3).
Simulated simulate(const sets::RationalModel& G, int N, double noise, bool bounded, std::mt19937_64& rng) {
  const int pre = 3000, T = N + pre;
  std::uniform_real_distribution<double> U(-1, 1);
  std::normal_distribution<double> Nn(0, 1);
  Eigen::VectorXd u(T), e(T);
  for (int t = 0; t < T; ++t) u[t] = U(rng);
  for (int t = 0; t < T; ++t) e[t] = bounded ? noise * U(rng) : noise * Nn(rng);
  const Eigen::VectorXd y0 = lfilter(G.b, G.a, u);
  const Eigen::VectorXd v = lfilter(Eigen::VectorXd::Ones(1), Eigen::Vector2d(1, -0.7), e);
  return {u.tail(N), (y0 + v).tail(N)};
}

// Coefficients g0(k) = <G0, F_k> by the trapezoid rule on a dense grid (G0 and F_k are smooth).
Eigen::VectorXd basis_coefficients(const sets::RationalModel& G, const sets::OrthonormalBasis& B, int count) {
  const int P = 1 << 14;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(count);
  for (int i = 0; i < P; ++i) {
    const double w = 2 * pi * i / P;
    const Eigen::VectorXcd F = B.frequency_responses(w, count);
    const cd Gw = G(w);
    for (int k = 0; k < count; ++k) g[k] += (Gw * std::conj(F[k])).real() / P;
  }
  return g;
}

// A column given by name or 1-based number.
Eigen::VectorXd column(const sets::Recording& r, const std::string& spec, const std::string& flag) {
  return r.matrix({spec}, flag).col(0);
}

void plot(const std::string& png, const sets::HinfBoundResult& R, const sets::RationalModel* G0) {
  using sets::app::gnuplot_quote;
  sets::app::render_png(png, "set terminal pngcairo size 1400,600 noenhanced", [&](const fs::path& dir, const std::string&) {
    const auto& S = R.set;
    {
      std::ofstream reg(dir / "regions.dat"), fr(dir / "freq.dat"), dense(dir / "dense.dat");
      for (size_t j = 0; j < S.regions.size(); ++j) {
        for (auto z : S.regions[j].boundary(48)) reg << z.real() << ' ' << z.imag() << '\n';
        reg << "\n";
      }
      for (Eigen::Index j = 0; j < S.frequencies.size(); ++j) {
        const double w = S.frequencies[j];
        fr << w << ' ' << S.regions[j].centre.real() << ' ' << S.regions[j].centre.imag() << ' '
           << std::abs(S.regions[j].centre) << ' ' << R.delta[j] << ' ' << std::abs(R.weight.inverse(w)) << ' '
           << std::abs(R.weight.inverse(w)) * R.bound.b_grid << '\n';
      }
      for (int i = 0; i < 2000; ++i) {
        const double w = pi * i / 1999;
        const cd g = R.nominal.model(w);
        dense << w << ' ' << g.real() << ' ' << g.imag() << ' ' << std::abs(g);
        if (G0) {
          const cd t = (*G0)(w);
          dense << ' ' << t.real() << ' ' << t.imag() << ' ' << std::abs(t);
        }
        dense << '\n';
      }
    }
    const std::string regions = gnuplot_quote((dir / "regions.dat").string()),
                      freq = gnuplot_quote((dir / "freq.dat").string()), dense = gnuplot_quote((dir / "dense.dat").string());
    std::ostringstream gp;
    gp << "set multiplot layout 1,2\n"
       << "set title 'Uncertainty regions P(w_j) in the complex plane'\nset xlabel 'Re'\nset ylabel 'Im'\nset grid\n"
       << "plot " << regions << " w l lc rgb '#9999cc' t 'regions P(w_j)', " << freq
       << " u 2:3 w p pt 7 ps 0.4 lc rgb 'black' t 'central estimate', " << dense
       << " u 2:3 w l lw 2 lc rgb 'red' t 'nominal model'"
       << (G0 ? ", " + dense + " u 5:6 w l dt 2 lc rgb 'dark-green' t 'true G0'" : std::string()) << "\n"
       << "set title 'Magnitudes against frequency'\nset xlabel 'frequency (rad/sample)'\nset ylabel 'magnitude'\n"
       << "set logscale y\nset xrange [0:pi]\n"
       << "plot " << freq << " u 1:4 w l lc rgb 'black' t '|central estimate|', " << dense
       << " u 1:4 w l lw 2 lc rgb 'red' t '|nominal|', " << freq
       << " u 1:5 w l lc rgb 'blue' t 'delta(w) = max |G - Ghat|', " << freq
       << " u 1:6 w l lc rgb 'orange' t '|W^-1|', " << freq
       << " u 1:7 w l dt 3 lc rgb 'orange' t 'b_grid |W^-1|'"
       << (G0 ? ", " + dense + " u 1:7 w l dt 2 lc rgb 'dark-green' t '|G0|'" : std::string()) << "\n"
       << "unset multiplot\n";
    return gp.str();
  });
}

}  // namespace

int main(int argc, char** argv) {
  sets::app::Cli cli("sets-hinf-bound", "sets-hinf-bound: nominal model + weighted H-infinity error bound from time-domain data "
               "(Hakvoort & Van den Hof)");
  CLI::App& app = cli.app();
  int N = 2000, runs = 200, order = 40, nominal_order = 2, grid_points = 150, polygon = 16, weight_degree = 12;
  double alpha = 0.95, pole = 0.93, pole_angle = 0.66, rho = 0.88, M = -1, u_bar = 1, M_ic = -1, rho_ic = -1;
  double v_bar = -1, noise_std = 0.02, w_min = 0, w_max = pi;
  std::string basis_name = "kautz", noise_name = "stochastic", shape_name = "rectangle", json_path, plot_path;
  std::string data_path, ucol, ycol, rcol;
  unsigned seed = 1;
  bool per_frequency = false, quiet = false;
  app.add_option("--N", N, "samples per data set (built-in example)")->check(CLI::Range(100, 1000000));
  app.add_option("--runs", runs, "Monte Carlo runs (built-in example; 1 = a single data set)")->check(CLI::Range(1, 100000));
  app.add_option("--alpha", alpha, "probability that G0 is in the set (stochastic noise)");
  app.add_option("--basis", basis_name, "fir | laguerre | kautz")->check(CLI::IsMember({"fir", "laguerre", "kautz"}));
  app.add_option("--order", order, "number of basis functions n")->check(CLI::PositiveNumber);
  app.add_option("--pole", pole, "basis pole: Laguerre a, or Kautz |xi|");
  app.add_option("--pole-angle", pole_angle, "Kautz pole angle arg(xi) in rad/sample");
  app.add_option("--noise", noise_name, "stochastic | bounded")->check(CLI::IsMember({"stochastic", "bounded"}));
  app.add_option("--shape", shape_name, "rectangle | ellipse (stochastic)")->check(CLI::IsMember({"rectangle", "ellipse"}));
  app.add_flag("--per-frequency", per_frequency, "alpha per frequency (the paper) instead of simultaneous");
  app.add_option("--grid", grid_points, "number of frequencies in (0, pi)")->check(CLI::Range(2, 100000));
  app.add_option("--w-min", w_min, "lowest grid frequency (rad/sample, >= 0)");
  app.add_option("--w-max", w_max, "highest grid frequency (rad/sample, <= pi)");
  app.add_option("--nominal-order", nominal_order, "order of the nominal model");
  app.add_option("--polygon", polygon, "K: sides of the polygon replacing |.| in the nominal-model LP");
  app.add_option("--weight-degree", weight_degree, "degree of the trigonometric polynomial |W^-1|^2");
  app.add_option("--rho", rho, "prior: |g0(k)| <= M rho^k (basis coefficients)");
  app.add_option("--M", M, "prior M (built-in: derived from the true coefficients when not given)");
  app.add_option("--u-bar", u_bar, "prior: |u(t)| <= u_bar before the data");
  app.add_option("--M-ic", M_ic, "prior: impulse response |h0(s)| <= M_ic rho_ic^s (initial conditions)");
  app.add_option("--rho-ic", rho_ic, "prior rho_ic");
  app.add_option("--v-bar", v_bar, "prior: |v(t)| <= v_bar (bounded noise)");
  app.add_option("--noise-std", noise_std, "built-in: std (stochastic) or bound (bounded) of the white noise before the 1/(1-0.7q^-1) filter");
  app.add_option("--seed", seed, "random seed");
  cli.add_output_file("--json", json_path, "write the results as JSON");
  cli.add_output_file("--plot", plot_path, "write a PNG plot (gnuplot)");
  app.add_option("--data", data_path, "CSV file with real data (header row optional)");
  app.add_option("--u", ucol, "input column (name or 1-based number)");
  app.add_option("--y", ycol, "output column");
  app.add_option("--r", rcol, "reference column: instrumental variables for closed-loop data");
  app.add_flag("--quiet", quiet, "do not print the per-frequency table");
  if (const auto code = cli.parse(argc, argv)) return *code;

  try {
    const bool builtin = data_path.empty();
    const bool bounded = noise_name == "bounded";
    sets::OrthonormalBasis basis = basis_name == "fir"        ? sets::OrthonormalBasis::fir()
                                   : basis_name == "laguerre" ? sets::OrthonormalBasis::laguerre(pole)
                                                              : sets::OrthonormalBasis::kautz(std::polar(pole, pole_angle));
    Eigen::VectorXd grid(grid_points);
    for (int j = 0; j < grid_points; ++j) grid[j] = w_min + (w_max - w_min) * (j + 0.5) / grid_points;
    sets::check_frequency_grid(grid);
    const sets::RationalModel G0 = true_system();

    sets::HinfPriors priors;
    priors.rho = rho;
    priors.u_bar = u_bar;
    priors.M_ic = M_ic;
    priors.rho_ic = rho_ic;
    sets::check_priors(priors);  // rho first: the derived M needs a valid rho
    std::string prior_note;
    if (builtin) {
      // Priors that are true for G0 (a simulation may know them): envelope of the true basis
      // coefficients and of the true impulse response, with a 20% margin.
      // Beyond ~200 the computed coefficients are rounding noise (< 1e-12), not the system.
      const Eigen::VectorXd g = basis_coefficients(G0, basis, 200);
      double Mneed = 0;
      for (int k = 0; k < g.size(); ++k) Mneed = std::max(Mneed, std::abs(g[k]) / std::pow(rho, k));
      if (M <= 0) M = 1.2 * Mneed;
      if (rho_ic <= 0) priors.rho_ic = 0.975;
      const Eigen::VectorXd imp = [&] {
        Eigen::VectorXd d = Eigen::VectorXd::Zero(3000);
        d[0] = 1;
        return lfilter(G0.b, G0.a, d);
      }();
      double Mic = 0;
      for (int s = 1; s < imp.size(); ++s) Mic = std::max(Mic, std::abs(imp[s]) / std::pow(priors.rho_ic, s));
      if (M_ic <= 0) priors.M_ic = 1.2 * Mic;
      prior_note = "prior check on the true system: max_k |g0(k)|/rho^k = " + std::to_string(Mneed) +
                   (Mneed <= M ? " <= M (holds)" : " > M (VIOLATED)");
    } else if (M <= 0)
      throw InputError("--M: the tail prior M must be given with --data");
    priors.M = M;
    if (bounded && v_bar < 0) {
      if (!builtin) throw InputError("--v-bar: the noise bound must be given for --noise bounded");
      v_bar = noise_std / 0.3;  // |v| <= sum_s 0.7^s |e| <= e_max / 0.3
    }

    sets::HinfBoundOptions opt;
    opt.uncertainty.noise = bounded ? sets::NoiseModel::bounded : sets::NoiseModel::stochastic;
    opt.uncertainty.shape = shape_name == "ellipse" ? sets::RegionShape::ellipse : sets::RegionShape::rectangle;
    opt.uncertainty.alpha = alpha;
    opt.uncertainty.simultaneous = !per_frequency;
    opt.uncertainty.v_bar = std::max(0.0, v_bar);
    opt.nominal.order = nominal_order;
    opt.nominal.polygon_sides = polygon;
    opt.weight.degree = weight_degree;

    std::cout << "sets-hinf-bound: Hakvoort-Van den Hof H-infinity error bound\n";
    std::cout << "  basis: " << basis.describe() << ", n = " << order << " functions\n";
    std::cout << "  priors: |g0(k)| <= " << priors.M << " * " << priors.rho << "^k, |u(t<=0)| <= " << priors.u_bar;
    if (priors.M_ic > 0) std::cout << ", |h0(s)| <= " << priors.M_ic << " * " << priors.rho_ic << "^s";
    std::cout << (bounded ? ", |v(t)| <= " + std::to_string(v_bar) : ", noise stochastic, alpha = " + std::to_string(alpha)) << "\n";
    if (!prior_note.empty()) std::cout << "  " << prior_note << "\n";

    Eigen::VectorXd u, y, r;
    if (!builtin) {
      if (ucol.empty() || ycol.empty()) throw InputError("--data needs --u and --y");
      const sets::Recording c = sets::read_csv(data_path);
      u = column(c, ucol, "--u");
      y = column(c, ycol, "--y");
      if (!rcol.empty()) r = column(c, rcol, "--r");
      runs = 1;
      std::cout << "  data: " << data_path << ", " << u.size() << " samples\n";
    } else {
      std::cout << "  true system (order 4): " << G0.to_string() << "\n"
                << "    poles 0.97 e^{+-0.6i} (lightly damped resonance, damping ratio ~0.05), 0.8 e^{+-0.9i}\n"
                << "  data: N = " << N << ", u uniform in [-1, 1], noise " << (bounded ? "uniform" : "Gaussian")
                << " white (" << noise_std << ") through 1/(1 - 0.7 q^-1)\n";
    }

    std::mt19937_64 rng(seed);
    int fail_b = 0, fail_grid = 0, fail_data = 0, fail_regions = 0, falsified = 0;
    double time_total = 0;
    const std::clock_t cpu0 = std::clock();
    sets::HinfBoundResult first;
    std::vector<double> bs, bgrids, bdatas, ubs, ubgrids, ubdatas, radii;
    for (int run = 0; run < runs; ++run) {
      if (builtin) {
        const Simulated s = simulate(G0, N, noise_std, bounded, rng);
        u = s.u;
        y = s.y;
      }
      const auto t0 = std::chrono::steady_clock::now();
      sets::HinfBoundResult R = sets::hinf_bound(u, y, basis, order, grid, priors, opt, r.size() ? &r : nullptr);
      time_total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (R.set.empty) {
        ++falsified;
        if (run == 0) first = R;
        continue;
      }
      if (builtin) {
        const double e = sets::weighted_error([&](double w) { return G0(w); }, R.nominal.model, R.weight.h);
        fail_b += e > R.bound.b;
        fail_grid += e > R.bound.b_grid;
        fail_data += e > R.bound.b_data;
        bool miss = false;
        for (int j = 0; j < grid_points; ++j) miss |= !R.set.regions[j].contains(G0(grid[j]));
        fail_regions += miss;
      }
      bs.push_back(R.bound.b);
      bgrids.push_back(R.bound.b_grid);
      bdatas.push_back(R.bound.b_data);
      ubdatas.push_back(R.unweighted.b_data);
      ubs.push_back(R.unweighted.b);
      ubgrids.push_back(R.unweighted.b_grid);
      double rad = 0;
      for (const auto& P : R.set.regions) rad += std::hypot(P.half_re, P.half_im) / R.set.regions.size();
      radii.push_back(rad);
      if (run == 0) first = R;
    }
    if (first.set.empty) {
      std::cout << "\nThe data falsify the priors (bounded noise): " << first.set.falsification << "\n";
      return int(sets::exit_falsified);
    }
    const auto& R = first;
    if (!quiet) {
      std::cout << "\nRun 1, per frequency (w in rad/sample):\n"
                << "        w     Re Gc      Im Gc    delta(w)     |W^-1|   delta_u    f1(noise)  f2(tail est) f3(init)  f4(tail)\n";
      std::cout << std::fixed;
      for (int j = 0; j < grid_points; ++j) {
        const auto& T = R.set.terms[j];
        std::cout << std::setprecision(4) << std::setw(9) << grid[j] << std::setprecision(5) << std::setw(10)
                  << R.set.regions[j].centre.real() << std::setw(11) << R.set.regions[j].centre.imag() << std::setw(11)
                  << R.delta[j] << std::setw(11) << std::abs(R.weight.inverse(grid[j])) << std::setw(10)
                  << R.bound.delta_u[j] << std::scientific << std::setprecision(2) << std::setw(11)
                  << std::max(T.noise_re, T.noise_im) << std::setw(11) << std::max(T.tail_est_re, T.tail_est_im)
                  << std::setw(11) << std::max(T.ic_re, T.ic_im) << std::setw(11) << std::max(T.tail_re, T.tail_im)
                  << std::fixed << "\n";
      }
      std::cout.unsetf(std::ios::floatfield);
    }
    std::cout << std::setprecision(6);
    std::cout << "\nNominal model (order " << nominal_order << ", K = " << R.nominal.polygon_sides
              << "-gon, " << R.nominal.iterations << " LP iterations): Ghat(z) = " << R.nominal.model.to_string()
              << "\n  max_j |Gc - Ghat| = " << R.nominal.max_error << "\n";
    std::cout << "Weight: |W^-1|^2 trigonometric polynomial of degree " << weight_degree
              << ", W^-1(z) = sum h_k z^-k minimum phase; max_j W1^2 (|W^-1|^2 - delta^2) with W1 = 1/delta: " << R.weight.max_gap << "\n";
    std::cout << "beta1 (eq. 12) = " << R.set.beta1 << ", first regression sample " << R.set.first_sample + 1
              << ", tail terms evaluated " << R.set.tail_terms << "\n";
    std::cout << "Bound (run 1): b = " << R.bound.b << " (with the interpolation term lambda_j beta_j; guaranteed on [0, pi])\n"
              << "               b_data = " << R.bound.b_data << " (between-grid term from the set's coefficient box"
              << (bounded ? "; guaranteed on [0, pi])\n"
                          : "; on [0, pi] at level >= " + std::to_string(1 - (1 + opt.uncertainty.coefficient_share) * (1 - alpha)) + ")\n")
              << "               b_grid = " << R.bound.b_grid << " (max_j delta_u(w_j): grid only, the paper's practical choice)\n"
              << "               unweighted (W = 1): ||G0 - Ghat||_inf <= " << R.unweighted.b << " (prior), "
              << R.unweighted.b_data << " (data), on the grid " << R.unweighted.b_grid << "\n";
    const double mean_time = time_total / runs;
    auto mean = [](const std::vector<double>& v) {
      double s = 0;
      for (double x : v) s += x;
      return v.empty() ? 0.0 : s / v.size();
    };
    std::cout << "Means over " << bs.size() << " runs: region radius " << mean(radii) << ", unweighted bound on the grid "
              << mean(ubgrids) << ", unweighted bound " << mean(ubs) << " (prior), " << mean(ubdatas) << " (data), b " << mean(bs)
              << ", b_data " << mean(bdatas) << ", b_grid " << mean(bgrids) << "\n";
    const double cpu_per_run = double(std::clock() - cpu0) / CLOCKS_PER_SEC / runs;  // includes simulation
    std::cout << "Time per data set: " << mean_time << " s wall, " << cpu_per_run
              << " s CPU (CPU includes simulating the data and the Monte Carlo check)\n";
    double fr = 0, fr_grid = 0, fr_reg = 0, fr_data = 0;
    const int valid = runs - falsified;
    if (builtin) {
      fr = valid ? double(fail_b) / valid : 0;
      fr_grid = valid ? double(fail_grid) / valid : 0;
      fr_data = valid ? double(fail_data) / valid : 0;
      fr_reg = valid ? double(fail_regions) / valid : 0;
      const double mc = std::sqrt(std::max(1 - alpha, 1e-12) * alpha / std::max(valid, 1));
      std::cout << "\nMonte Carlo, " << runs << " runs (" << falsified << " falsified):\n"
                << "  G0 outside G(Ghat, W, b)      (dense grid, 4096 points): " << fail_b << " -> failure rate " << fr << "\n"
                << "  G0 outside G(Ghat, W, b_data) (dense grid, 4096 points): " << fail_data << " -> failure rate " << fr_data << "\n"
                << "  G0 outside G(Ghat, W, b_grid) (dense grid, 4096 points): " << fail_grid << " -> failure rate " << fr_grid << "\n"
                << "  some G0(w_j) outside its region P(w_j):                  " << fail_regions << " -> " << fr_reg << "\n";
      if (!bounded) std::cout << "  allowed: 1 - alpha = " << 1 - alpha << " (Monte Carlo std error at that rate " << mc << ")\n";
      if (!bounded)
        std::cout << "  allowed for b_data: (1 + " << opt.uncertainty.coefficient_share << ") (1 - alpha) = "
                  << (1 + opt.uncertainty.coefficient_share) * (1 - alpha) << " (regions and coefficient box)\n";
    }

    if (!json_path.empty()) {
      sets::app::Json j;
      j["runs"] = runs;
      j["alpha"] = alpha;
      j["noise"] = noise_name;
      j["b"] = R.bound.b;
      j["b_grid"] = R.bound.b_grid;
      j["b_data"] = R.bound.b_data;
      j["b_unweighted_data"] = R.unweighted.b_data;
      j["failure_rate_data"] = fr_data;
      j["b_data_runs"] = bdatas;
      j["mean_b"] = mean(bs);
      j["mean_b_data"] = mean(bdatas);
      j["mean_b_grid"] = mean(bgrids);
      j["mean_unweighted_b_data"] = mean(ubdatas);
      j["b_unweighted"] = R.unweighted.b;
      j["b_unweighted_grid"] = R.unweighted.b_grid;
      j["failure_rate"] = fr;
      j["failure_rate_grid"] = fr_grid;
      j["region_miss_rate"] = fr_reg;
      j["falsified_runs"] = falsified;
      j["basis"] = basis_name;
      j["order"] = order;
      j["N"] = builtin ? N : static_cast<int>(u.size());
      j["M"] = priors.M;
      j["rho"] = priors.rho;
      j["polygon_sides"] = R.nominal.polygon_sides;
      j["seconds_per_run"] = mean_time;
      j["cpu_seconds_per_run"] = cpu_per_run;
      j["nominal"] = {{"b", std::vector<double>(R.nominal.model.b.data(), R.nominal.model.b.data() + R.nominal.model.b.size())},
                      {"a", std::vector<double>(R.nominal.model.a.data(), R.nominal.model.a.data() + R.nominal.model.a.size())}};
      std::vector<double> f(grid.data(), grid.data() + grid.size()), d(R.delta.data(), R.delta.data() + R.delta.size()), wi;
      for (double w : f) wi.push_back(std::abs(R.weight.inverse(w)));
      j["frequencies"] = f;
      j["delta"] = d;
      j["w_inv"] = wi;
      j["b_runs"] = bs;
      j["mean_region_radius"] = mean(radii);
      j["mean_unweighted_b_grid"] = mean(ubgrids);
      j["mean_unweighted_b"] = mean(ubs);
      j["b_grid_runs"] = bgrids;
      sets::app::write_json(json_path, j, 1);
    }
    if (!plot_path.empty()) plot(plot_path, R, builtin ? &G0 : nullptr);
    return 0;
  } catch (const std::exception& e) {
    return sets::report_failure("sets-hinf-bound", e);
  }
}
