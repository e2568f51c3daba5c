#include "report.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "common/gnuplot.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/examples/synthetic_plants.hpp"

namespace fs = std::filesystem;
using namespace sets;
using sets::app::gnuplot_quote;

namespace {

void write_series(const std::string& path, const Eigen::VectorXd& t, const std::vector<const Eigen::MatrixXd*>& cols) {
  std::ofstream o(path);
  o.precision(10);
  const Eigen::Index N = t.size(), stride = std::max<Eigen::Index>(1, N / 5000);
  for (Eigen::Index k = 0; k < N; k += stride) {
    o << t[k];
    for (const auto* m : cols)
      for (Eigen::Index j = 0; j < m->cols(); ++j) o << " " << (*m)(k, j);
    o << "\n";
  }
  if (!o) throw InputError(path + ": cannot write");
}

}  // namespace

void write_report(const Diagnosis& d, const std::string& dir, const std::string& augmented_text) {
  AtomicDirectory out(dir);
  const fs::path tmp = out.staging();
  std::vector<std::string> pngs;
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1200,800 noenhanced\nset grid\n";
  const auto ny = static_cast<Eigen::Index>(d.outputs.size());
  auto signals = [&](const std::string& tag, const Eigen::VectorXd& t, const Eigen::MatrixXd& meas,
                     const Eigen::MatrixXd& nom, const Eigen::MatrixXd& aug, bool windows) {
    write_series((tmp / (tag + ".dat")).string(), t, {&meas, &nom, &aug});
    gp << "set output " << gnuplot_quote((tmp / ("signals_" + tag + ".png")).string()) << "\n";
    gp << "set multiplot layout " << ny << ",1 title "
       << gnuplot_quote("measured, nominal (calibrated) and augmented: " + tag + " record") << "\n";
    for (Eigen::Index j = 0; j < ny; ++j) {
      gp << "unset object\n";
      if (windows) {
        int id = 1;
        for (const auto& w : d.windows)
          if (w.output == d.outputs[static_cast<std::size_t>(j)])
            gp << "set object " << id++ << " rect from " << w.start << ", graph 0 to " << w.end
               << ", graph 1 fc rgb '#ffd0d0' fs solid 0.5 noborder behind\n";
      }
      gp << "set xlabel 't [s]'\nset ylabel " << gnuplot_quote(d.outputs[static_cast<std::size_t>(j)]) << "\n";
      const auto c = [&](int block) { return 2 + block * ny + j; };
      gp << "plot " << gnuplot_quote((tmp / (tag + ".dat")).string()) << " using 1:" << c(0)
         << " with lines lw 2 lc rgb 'black' title 'measured', '' using 1:" << c(1)
         << " with lines lc rgb 'red' title 'nominal', '' using 1:" << c(2)
         << " with lines lc rgb 'blue' title 'augmented'\n";
    }
    gp << "unset multiplot\nunset object\n";
    pngs.push_back("signals_" + tag + ".png");
  };
  signals("estimation", d.time_estimation, d.measured_estimation, d.nominal_estimation, d.augmented_estimation, true);
  if (d.has_validation)
    signals("validation", d.time_validation, d.measured_validation, d.nominal_validation, d.augmented_validation, false);
  {
    std::ofstream o(tmp / "signature.dat");
    const Eigen::Index N = d.signature_x.size(), stride = std::max<Eigen::Index>(1, N / 8000);
    for (Eigen::Index k = 0; k < N; k += stride) o << d.signature_x[k] << " " << d.signature_residual[k] << "\n";
    gp << "set output " << gnuplot_quote((tmp / "signature.png").string()) << "\n";
    gp << "set title "
       << gnuplot_quote("signature: residual of " + d.signature_output + " (measured - calibrated nominal) against " +
                        d.signature_variable)
       << "\n";
    gp << "set xlabel " << gnuplot_quote(d.signature_variable) << "\nset ylabel "
       << gnuplot_quote("residual of " + d.signature_output) << "\n";
    gp << "plot " << gnuplot_quote((tmp / "signature.dat").string()) << " using 1:2 with points pt 7 ps 0.3 notitle\n";
    pngs.push_back("signature.png");
  }
  {
    std::ofstream o(tmp / "plots.gp");
    o << gp.str();
  }
  sets::app::run_gnuplot(tmp / "plots.gp", tmp / "gnuplot.log");
  for (const auto& p : pngs)
    if (!fs::exists(tmp / p) || fs::file_size(tmp / p) == 0) throw InputError("gnuplot did not write " + p);
  {
    std::ofstream o(tmp / "report.txt");
    o << diagnosis_text(d);
    std::ofstream a(tmp / "augmented_model.json");
    a << augmented_text;
    if (!o || !a) throw InputError(dir + ": cannot write the report");
  }
  // Only the report's own files move into place.
  for (const auto& e : fs::directory_iterator(tmp)) {
    const std::string n = e.path().filename().string();
    if (n.ends_with(".dat") || n == "plots.gp" || n == "gnuplot.log") fs::remove(e.path());
  }
  out.commit();
}

void print_suite(const std::string& plant, const DiagnosisOptions& options) {
  // Every plant of the suite: true effect against the first effect named.
  std::cout << "| plant | true effect | named (ranked) | right | nominal fit (val) | augmented fit (val) | s | true value: "
               "guaranteed interval (equation error, output error) |\n"
               "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  int right = 0, total = 0, clean = 0, clean_ok = 0, checked = 0, contained = 0;
  for (const auto& name : synthetic_plant_names()) {
    if (!plant.empty() && name != plant) continue;
    const SyntheticPlant p = synthetic_plant(name);
    const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation, options);
    if (!plant.empty()) std::cerr << diagnosis_text(d);
    std::string named;
    for (const auto& e : d.effects) named += (named.empty() ? "" : ", ") + e.name;
    if (named.empty()) named = "none";
    const std::string first = d.effects.empty() ? "none" : d.effects.front().name;
    const bool ok = first == p.true_effect;
    ++total;
    right += ok;
    if (p.true_effect == "none") ++clean, clean_ok += ok;
    char buf[256];
    std::snprintf(buf, sizeof buf, " | %.1f | %.1f | %.1f |", d.fit_nominal_validation.at(0),
                  d.fit_augmented_validation.at(0), d.seconds);
    // Does the reported guaranteed interval contain the true value?
    std::string truth;
    for (const auto& [pn, tv] : p.true_values)
      for (const auto& e : d.effects)
        for (const auto& ep : e.parameters)
          if (ep.name == pn) {
            const bool in = ep.lo <= tv && tv <= ep.hi;
            ++checked;
            contained += in;
            char t[256];
            char ee[96] = "none";
            if (ep.has_ee)
              std::snprintf(ee, sizeof ee, "[%.4g, %.4g]%s", ep.ee_lo, ep.ee_hi,
                            ep.ee_lo <= tv && tv <= ep.ee_hi ? "" : " **misses**");
            std::snprintf(t, sizeof t, "%s = %g: [%.4g, %.4g] %s (EE %s, OE [%.4g, %.4g])", pn.c_str(), tv, ep.lo,
                          ep.hi, in ? "contains" : "**misses**", ee, ep.oe_lo, ep.oe_hi);
            truth += (truth.empty() ? "" : "; ") + std::string(t);
          }
    std::cout << "| " << name << " | " << p.true_effect << " | " << named << " | " << (ok ? "yes" : "**no**") << buf
              << " " << (truth.empty() ? "–" : truth) << " |\n"
              << std::flush;
  }
  std::cout << "\nNamed right (first effect = true effect): " << right << " of " << total
            << "; clean plants with no invented effect: " << clean_ok << " of " << clean
            << "; true effect values inside the guaranteed interval: " << contained << " of " << checked << "\n";
}
