#include "report.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "common/gnuplot.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/diagnosis/report_html.hpp"
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

// index.html beside the figures (sets/diagnosis/report_html.hpp).
void write_html_page(const Diagnosis& d, const fs::path& dir, const std::vector<std::string>& pngs) {
  std::vector<ReportFigure> figures;
  for (const auto& p : pngs) {
    const std::string record = p == "signals_validation.png" ? "validation" : "estimation";
    figures.push_back({p, p == "signature.png"
                              ? "Signature: the residual of " + d.signature_output + " (measured - calibrated nominal) against " +
                                    d.signature_variable + ", with the effects found (augmented - nominal) over it."
                              : "The " + record + " record: measured, calibrated nominal and augmented outputs; under each, "
                                "the residuals" + (record == "estimation" ? "; shaded: the mismatch windows." : ".")});
  }
  std::ofstream o(dir / "index.html");
  o << diagnosis_html(d, figures, "augmented_model.json");
  if (!o) throw InputError((dir / "index.html").string() + ": cannot write");
}

// The gnuplot script of the report's figures, written into the staging folder `dir`; `pngs`
// lists the figures it draws, in the order the page shows them.
struct PlotScript {
  fs::path dir;
  std::ostringstream gp;
  std::vector<std::string> pngs;
};

// An axis label with the model file's unit, if it declares one.
std::string axis_label(const Diagnosis& d, const std::string& name) {
  const std::string u = d.nominal.unit(name);
  return u.empty() ? name : name + " [" + u + "]";
}

// One output's two panels: its signals, and under them its residuals (measured - nominal,
// measured - augmented); the mismatch windows shaded on both when `windows`.
void output_panels(PlotScript& s, const Diagnosis& d, const std::string& data, Eigen::Index j, bool windows) {
  const auto ny = static_cast<Eigen::Index>(d.outputs.size());
  const std::string& out = d.outputs[static_cast<std::size_t>(j)];
  const double block = 0.92 / static_cast<double>(ny);
  const double top = 0.94 - static_cast<double>(j) * block, split = top - 0.6 * block, bottom = top - 0.9 * block;
  const auto c = [&](int block_index) { return std::to_string(2 + block_index * ny + j); };
  std::ostringstream& gp = s.gp;
  for (int panel = 0; panel < 2; ++panel) {
    gp << "unset object\n";
    if (windows) {
      int id = 1;
      for (const auto& w : d.windows)
        if (w.output == out)
          gp << "set object " << id++ << " rect from " << w.start << ", graph 0 to " << w.end
             << ", graph 1 fc rgb '#ffd0d0' fs solid 0.5 noborder behind\n";
    }
    gp << "set tmargin at screen " << (panel == 0 ? top : split - 0.03 * block) << "\nset bmargin at screen "
       << (panel == 0 ? split : bottom) << "\n";
    if (panel == 0) {
      gp << "set format x ''\nunset xlabel\nset ylabel " << gnuplot_quote(axis_label(d, out)) << "\n";
      gp << "plot " << data << " using 1:" << c(0) << " with lines lw 2 lc rgb 'black' title 'measured', '' using 1:"
         << c(1) << " with lines lc rgb 'red' title 'nominal', '' using 1:" << c(2)
         << " with lines lc rgb 'blue' title 'augmented'\n";
    } else {
      const std::string u = d.nominal.unit(out);
      gp << "set format x '%g'\nset xlabel 't [s]'\nset ylabel " << gnuplot_quote(u.empty() ? "residual" : "residual [" + u + "]")
         << "\n";
      gp << "plot " << data << " using 1:(column(" << c(0) << ")-column(" << c(1)
         << ")) with lines lc rgb 'red' title 'measured - nominal', '' using 1:(column(" << c(0) << ")-column(" << c(2)
         << ")) with lines lc rgb 'blue' title 'measured - augmented'\n";
    }
  }
}

// signals_<tag>.png: every output of one record, measured, nominal (calibrated) and augmented.
void signals_figure(PlotScript& s, const Diagnosis& d, const std::string& tag, const Eigen::VectorXd& t,
                    const Eigen::MatrixXd& meas, const Eigen::MatrixXd& nom, const Eigen::MatrixXd& aug, bool windows) {
  const auto ny = static_cast<Eigen::Index>(d.outputs.size());
  write_series((s.dir / (tag + ".dat")).string(), t, {&meas, &nom, &aug});
  std::ostringstream& gp = s.gp;
  gp << "set terminal pngcairo size 1200," << std::max<Eigen::Index>(800, 460 * ny) << " noenhanced\n";
  gp << "set output " << gnuplot_quote((s.dir / ("signals_" + tag + ".png")).string()) << "\n";
  gp << "set multiplot title "
     << gnuplot_quote("measured, nominal (calibrated) and augmented: " + tag + " record" +
                      (windows ? " (shaded: mismatch windows)" : "")) << "\n";
  gp << "set lmargin at screen 0.09\nset rmargin at screen 0.97\n";
  const std::string data = gnuplot_quote((s.dir / (tag + ".dat")).string());
  for (Eigen::Index j = 0; j < ny; ++j) output_panels(s, d, data, j, windows);
  gp << "unset multiplot\nunset object\nset format x '%g'\nset lmargin\nset rmargin\nset tmargin\nset bmargin\n";
  s.pngs.push_back("signals_" + tag + ".png");
}

// signature.png: the nominal's residual against the signature variable, and the effects found as
// they show in that output (augmented - nominal at the same samples) over it.
void signature_figure(PlotScript& s, const Diagnosis& d) {
  const auto ny = static_cast<Eigen::Index>(d.outputs.size());
  Eigen::Index main = 0;
  while (main + 1 < ny && d.outputs[static_cast<std::size_t>(main)] != d.signature_output) ++main;
  const bool overlay = !d.effects.empty() && d.augmented_estimation.rows() == d.signature_x.size() &&
                       d.nominal_estimation.rows() == d.signature_x.size();
  {
    std::ofstream o(s.dir / "signature.dat");
    const Eigen::Index N = d.signature_x.size(), stride = std::max<Eigen::Index>(1, N / 8000);
    for (Eigen::Index k = 0; k < N; k += stride)
      o << d.signature_x[k] << " " << d.signature_residual[k] << " "
        << (overlay ? d.augmented_estimation(k, main) - d.nominal_estimation(k, main) : 0.0) << "\n";
  }
  std::string effects;
  for (const auto& e : d.effects) effects += (effects.empty() ? "" : ", ") + e.name;
  std::ostringstream& gp = s.gp;
  gp << "set terminal pngcairo size 1200,800 noenhanced\n";
  gp << "set output " << gnuplot_quote((s.dir / "signature.png").string()) << "\n";
  gp << "set title "
     << gnuplot_quote("signature: residual of " + d.signature_output + " (measured - calibrated nominal) against " +
                      d.signature_variable)
     << "\n";
  gp << "set xlabel " << gnuplot_quote(axis_label(d, d.signature_variable)) << "\nset ylabel "
     << gnuplot_quote("residual of " + axis_label(d, d.signature_output)) << "\n";
  gp << "plot " << gnuplot_quote((s.dir / "signature.dat").string())
     << " using 1:2 with points pt 7 ps 0.3 lc rgb '#606060' title 'residual'";
  if (overlay) gp << ", '' using 1:3 with points pt 7 ps 0.3 lc rgb 'blue' title " << gnuplot_quote("fitted: augmented - nominal (" + effects + ")");
  gp << "\nunset title\n";
  s.pngs.push_back("signature.png");
}

// Runs the script and checks that every figure it should draw is there.
void draw_figures(const PlotScript& s) {
  {
    std::ofstream o(s.dir / "plots.gp");
    o << s.gp.str();
  }
  sets::app::run_gnuplot(s.dir / "plots.gp", s.dir / "gnuplot.log");
  for (const auto& p : s.pngs)
    if (!fs::exists(s.dir / p) || fs::file_size(s.dir / p) == 0) throw InputError("gnuplot did not write " + p);
}

}  // namespace

void write_report(const Diagnosis& d, const std::string& dir, const std::string& augmented_text) {
  AtomicDirectory out(dir);
  PlotScript s;
  s.dir = out.staging();
  s.gp << "set grid\nset key opaque\n";
  signals_figure(s, d, "estimation", d.time_estimation, d.measured_estimation, d.nominal_estimation, d.augmented_estimation,
                 true);
  if (d.has_validation)
    signals_figure(s, d, "validation", d.time_validation, d.measured_validation, d.nominal_validation,
                   d.augmented_validation, false);
  signature_figure(s, d);
  draw_figures(s);
  {
    std::ofstream o(s.dir / "report.txt");
    o << diagnosis_text(d);
    std::ofstream a(s.dir / "augmented_model.json");
    a << augmented_text;
    if (!o || !a) throw InputError(dir + ": cannot write the report");
  }
  write_html_page(d, s.dir, s.pngs);
  // Only the report's own files move into place.
  for (const auto& e : fs::directory_iterator(s.dir)) {
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
