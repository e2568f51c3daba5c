#include "report.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "common/gnuplot.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/examples/diagnosis_suite.hpp"
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

void print_suite(const std::string& kind, const std::string& plant, int count, unsigned seed, const DiagnosisOptions& options,
                 bool quiet) {
  SuiteOptions so;
  so.threads = options.threads;
  so.diagnosis = options;
  if (!quiet)
    so.on_plant = [](const SuitePlantResult& r, int done, int total) {
      std::string truth, named;
      for (const auto& t : r.truth) truth += (truth.empty() ? "" : ", ") + t.name;
      for (const auto& n : r.named) named += (named.empty() ? "" : ", ") + n;
      std::cerr << "[sets-diagnose] " << done << "/" << total << " " << r.name << (r.family.empty() ? "" : " (" + r.family + ")")
                << ": true " << (truth.empty() ? "none" : truth) << ", named " << (named.empty() ? "none" : named) << ", "
                << r.seconds << " s" << (r.error.empty() ? "" : ", ERROR " + r.error) << std::endl;
    };
  const auto results = kind == "fixed" ? run_fixed_suite(plant, so) : run_random_suite(seed, count, so);
  if (kind == "fixed" && !plant.empty()) {
    const SyntheticPlant p = synthetic_plant(plant);
    DiagnosisOptions verbose = options;
    if (!quiet) verbose.progress = [](const std::string& s) { std::cerr << "[sets-diagnose] " << s << std::endl; };
    std::cerr << diagnosis_text(diagnose(p.nominal, p.estimation, &p.validation, verbose));
  }
  std::cout << suite_report(results);
}
