#include "runs.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <random>
#include <sstream>

#include "common/gnuplot.hpp"
#include "sets/core/error.hpp"
#include "sets/examples/hakvoort.hpp"

namespace fs = std::filesystem;
using cd = std::complex<double>;

namespace {

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

// Failure rates over the runs that were not falsified.
struct Rates {
  double b = 0, grid = 0, data = 0, regions = 0;
};
Rates rates(const Settings& s, const Runs& r) {
  const int valid = s.runs - r.falsified - static_cast<int>(r.failed.size());
  if (!s.builtin || !valid) return {};
  return {double(r.fail_b) / valid, double(r.fail_grid) / valid, double(r.fail_data) / valid,
          double(r.fail_regions) / valid};
}

bool per_frequency(const Settings& s) { return !s.options.uncertainty.simultaneous; }

std::vector<double> std_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

Runs run_all(const Settings& s, const sets::HinfData& data, const sets::TransferFunction& G0) {
  std::mt19937_64 rng(s.seed);
  Runs out;
  bool have_first = false;
  sets::HinfData d = data;
  for (int run = 0; run < s.runs; ++run) {
    if (s.builtin) {
      const auto sim = sets::hakvoort::simulate(G0, s.N, s.noise_std, s.bounded, rng);
      d.u = sim.u;
      d.y = sim.y;
    }
    const auto t0 = std::chrono::steady_clock::now();
    sets::HinfBoundResult R;
    try {
      R = sets::hinf_bound(d, s.structure, s.options);
    } catch (const sets::NumericalError& e) {
      if (!s.builtin) throw;  // one data set: the failure is the answer (exit code 3)
      out.failed.push_back({run + 1, e.what()});
      continue;
    }
    out.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const bool first = !have_first;
    have_first = true;
    if (first) out.first = R;
    if (R.set.empty()) {
      ++out.falsified;
      continue;
    }
    if (s.builtin) {
      const double e = sets::weighted_error([&](double w) { return G0(w); }, R.nominal.model, R.weight.h);
      out.fail_b += e > R.bound.b;
      out.fail_grid += e > R.bound.b_grid;
      out.fail_data += e > R.bound.b_data;
      out.fail_prior += e > R.bound.b_prior;
      bool miss = false;
      for (Eigen::Index j = 0; j < s.structure.grid.size(); ++j)
        miss |= !R.set.regions[j].contains(G0(s.structure.grid[j]));
      out.fail_regions += miss;
    }
    out.bs.push_back(R.bound.b);
    out.bgrids.push_back(R.bound.b_grid);
    out.bdatas.push_back(R.bound.b_data);
    out.ubdatas.push_back(R.unweighted.b_data);
    out.ubs.push_back(R.unweighted.b);
    out.bpriors.push_back(R.bound.b_prior);
    out.ubpriors.push_back(R.unweighted.b_prior);
    out.ubgrids.push_back(R.unweighted.b_grid);
    double rad = 0;
    for (const auto& P : R.set.regions) rad += std::hypot(P.half_re, P.half_im) / R.set.regions.size();
    out.radii.push_back(rad);
  }
  if (!have_first)
    throw sets::NumericalError("every one of the " + std::to_string(s.runs) + " runs failed; run 1: " +
                               out.failed.front().reason);
  return out;
}

void print_results(const Settings& s, const Runs& r, double cpu_per_run) {
  const auto& R = r.first;
  const auto& grid = s.structure.grid;
  const double alpha = s.options.uncertainty.alpha, share = s.options.uncertainty.coefficient_share;
  if (!s.quiet) {
    std::cout << "\nRun 1, per frequency (w in rad/sample):\n"
              << "        w     Re Gc      Im Gc    delta(w)     |W^-1|   delta_u    f1(noise)  f2(tail est) "
                 "f3(init)  f4(tail)\n";
    std::cout << std::fixed;
    for (Eigen::Index j = 0; j < grid.size(); ++j) {
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
  std::cout << "\nNominal model (order " << s.options.nominal.order << ", K = " << R.nominal.polygon_sides << "-gon, "
            << R.nominal.iterations << " LP iterations): Ghat(z) = " << R.nominal.model.to_string()
            << "\n  max_j |Gc - Ghat| = " << R.nominal.max_error << "\n";
  std::cout << "Weight: |W^-1|^2 trigonometric polynomial of degree " << s.options.weight.degree
            << ", W^-1(z) = sum h_k z^-k minimum phase; max_j W1^2 (|W^-1|^2 - delta^2) with W1 = 1/delta: "
            << R.weight.max_gap << "\n";
  std::cout << "beta1 (eq. 12) = " << R.set.beta1 << ", first regression sample " << R.set.first_sample + 1
            << ", tail terms evaluated " << R.set.tail_terms << "\n";
  const std::string level = s.bounded         ? "guaranteed given the priors"
                            : per_frequency(s) ? "regions at alpha per frequency: no simultaneous level"
                                               : "holds with probability >= " + std::to_string(alpha);
  std::cout << "Bound (run 1): b = " << R.bound.b << " on [0, pi] (the full-band bound, min(b_data, b_prior); " << level << ")\n"
            << "               b_data = " << R.bound.b_data << " (between-grid term from the identified coefficient set and the tail prior)\n"
            << "               b_prior = " << R.bound.b_prior << " (between-grid slope from the coefficient prior, eq. 12: the paper's bound)\n"
            << "               b_grid = " << R.bound.b_grid << " (max_j delta_u(w_j): grid only, the paper's practical choice)\n"
            << "               unweighted (W = 1): ||G0 - Ghat||_inf <= " << R.unweighted.b << " on [0, pi] ("
            << R.unweighted.b_prior << " with the prior slope), on the grid " << R.unweighted.b_grid << "\n";
  std::cout << "Means over " << r.bs.size() << " runs: region radius " << mean(r.radii) << ", unweighted bound on the grid "
            << mean(r.ubgrids) << ", unweighted bound " << mean(r.ubs) << " (" << mean(r.ubpriors)
            << " with the prior slope), b " << mean(r.bs) << ", b_data " << mean(r.bdatas) << ", b_prior " << mean(r.bpriors)
            << ", b_grid " << mean(r.bgrids) << "\n";
  std::cout << "Time per data set: " << r.seconds / s.runs << " s wall, " << cpu_per_run
            << " s CPU (CPU includes simulating the data and the Monte Carlo check)\n";
  if (!s.builtin) return;
  const Rates fr = rates(s, r);
  const int valid = s.runs - r.falsified - static_cast<int>(r.failed.size());
  const double mc = std::sqrt(std::max(1 - alpha, 1e-12) * alpha / std::max(valid, 1));
  std::cout << "\nMonte Carlo, " << s.runs << " runs (" << r.falsified << " falsified, " << r.failed.size()
            << " failed numerically; rates over the other " << valid << "):\n"
            << "  G0 outside G(Ghat, W, b)      (dense grid, 4096 points): " << r.fail_b << " -> failure rate " << fr.b << "\n"
            << "  G0 outside G(Ghat, W, b_data) (dense grid, 4096 points): " << r.fail_data << " -> failure rate " << fr.data << "\n"
            << "  G0 outside G(Ghat, W, b_prior)(dense grid, 4096 points): " << r.fail_prior << "\n"
            << "  G0 outside G(Ghat, W, b_grid) (dense grid, 4096 points): " << r.fail_grid << " -> failure rate " << fr.grid << "\n"
            << "  some G0(w_j) outside its region P(w_j):                  " << r.fail_regions << " -> " << fr.regions << "\n";
  for (std::size_t k = 0; k < r.failed.size() && k < 10; ++k)
    std::cout << "  failed run " << r.failed[k].run << ": " << r.failed[k].reason << "\n";
  if (r.failed.size() > 10) std::cout << "  (" << r.failed.size() - 10 << " more failed runs in the JSON)\n";
  if (!s.bounded) {
    std::cout << "  allowed: 1 - alpha = " << 1 - alpha << " (Monte Carlo std error at that rate " << mc << ")\n";
    std::cout << "  (b and b_data share the level; the coefficient set takes " << share << " / (1 + " << share
              << ") of 1 - alpha from the regions)\n";
  }
}

sets::app::Json results_json(const Settings& s, const Runs& r, int samples, double cpu_per_run) {
  const auto& R = r.first;
  const Rates fr = rates(s, r);
  sets::app::Json j;
  j["runs"] = s.runs;
  j["alpha"] = s.options.uncertainty.alpha;
  j["noise"] = s.noise_name;
  j["b"] = R.bound.b;
  j["b_grid"] = R.bound.b_grid;
  j["b_data"] = R.bound.b_data;
  j["b_prior"] = R.bound.b_prior;
  j["b_unweighted_prior"] = R.unweighted.b_prior;
  j["mean_b_prior"] = mean(r.bpriors);
  j["b_prior_runs"] = r.bpriors;
  j["failures_prior"] = r.fail_prior;
  j["b_unweighted_data"] = R.unweighted.b_data;
  j["failure_rate_data"] = fr.data;
  j["b_data_runs"] = r.bdatas;
  j["mean_b"] = mean(r.bs);
  j["mean_b_data"] = mean(r.bdatas);
  j["mean_b_grid"] = mean(r.bgrids);
  j["mean_unweighted_b_data"] = mean(r.ubdatas);
  j["b_unweighted"] = R.unweighted.b;
  j["b_unweighted_grid"] = R.unweighted.b_grid;
  j["failure_rate"] = fr.b;
  j["failure_rate_grid"] = fr.grid;
  j["region_miss_rate"] = fr.regions;
  j["falsified_runs"] = r.falsified;
  j["failed_runs"] = r.failed.size();
  std::vector<sets::app::Json> failures;
  for (const auto& f : r.failed) failures.push_back({{"run", f.run}, {"reason", f.reason}});
  j["failures"] = failures;
  j["basis"] = s.basis_name;
  j["order"] = s.structure.order;
  j["N"] = samples;
  j["M"] = s.structure.priors.M;
  j["rho"] = s.structure.priors.rho;
  j["polygon_sides"] = R.nominal.polygon_sides;
  j["seconds_per_run"] = r.seconds / s.runs;
  j["cpu_seconds_per_run"] = cpu_per_run;
  j["nominal"] = {{"b", std_vector(R.nominal.model.b)}, {"a", std_vector(R.nominal.model.a)}};
  std::vector<double> wi;
  for (Eigen::Index k = 0; k < s.structure.grid.size(); ++k) wi.push_back(std::abs(R.weight.inverse(s.structure.grid[k])));
  j["frequencies"] = sets::app::to_json(s.structure.grid);
  j["delta"] = sets::app::to_json(R.delta);
  j["w_inv"] = wi;
  j["b_runs"] = r.bs;
  j["mean_region_radius"] = mean(r.radii);
  j["mean_unweighted_b_grid"] = mean(r.ubgrids);
  j["mean_unweighted_b"] = mean(r.ubs);
  j["b_grid_runs"] = r.bgrids;
  return j;
}

void plot(const std::string& png, const sets::HinfBoundResult& R, const sets::TransferFunction* G0) {
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
        const double w = std::numbers::pi * i / 1999;
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
       << " u 1:4 w l lw 2 lc rgb 'red' t '|nominal|', " << freq << " u 1:5 w l lc rgb 'blue' t 'delta(w) = max |G - Ghat|', "
       << freq << " u 1:6 w l lc rgb 'orange' t '|W^-1|', " << freq << " u 1:7 w l dt 3 lc rgb 'orange' t 'b_grid |W^-1|'"
       << (G0 ? ", " + dense + " u 1:7 w l dt 2 lc rgb 'dark-green' t '|G0|'" : std::string()) << "\n"
       << "unset multiplot\n";
    return gp.str();
  });
}
