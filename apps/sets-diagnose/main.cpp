// sets-diagnose: where a model and recordings differ, which physics is missing, the augmented
// model with its new parameters, and the fit before and after. See docs/methods/diagnosis.md.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "sets/core/exit_code.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/core/error.hpp"
#include "sets/models/model_file.hpp"
#include "sets/data/recording.hpp"
#include "sets/examples/diagnosis_suite.hpp"
#include "sets/examples/synthetic_plants.hpp"

namespace fs = std::filesystem;
using namespace sets;

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

std::string quote(const std::string& s) {
  std::string r = "'";
  for (char c : s) r += c == '\'' ? std::string("''") : std::string(1, c);
  return r + "'";
}

// Plots through gnuplot into a temporary folder inside `dir`; files are moved into place only
// when every one of them was written.
void write_report(const Diagnosis& d, const std::string& dir, const std::string& augmented_text) {
  fs::create_directories(dir);
  const fs::path tmp = fs::path(dir) / ".sets-diagnose.tmp";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  try {
    std::vector<std::string> pngs;
    std::ostringstream gp;
    gp << "set terminal pngcairo size 1200,800 noenhanced\nset grid\n";
    const auto ny = static_cast<Eigen::Index>(d.outputs.size());
    auto signals = [&](const std::string& tag, const Eigen::VectorXd& t, const Eigen::MatrixXd& meas,
                       const Eigen::MatrixXd& nom, const Eigen::MatrixXd& aug, bool windows) {
      write_series((tmp / (tag + ".dat")).string(), t, {&meas, &nom, &aug});
      gp << "set output " << quote((tmp / ("signals_" + tag + ".png")).string()) << "\n";
      gp << "set multiplot layout " << ny << ",1 title " << quote("measured, nominal (calibrated) and augmented: " + tag + " record") << "\n";
      for (Eigen::Index j = 0; j < ny; ++j) {
        gp << "unset object\n";
        if (windows) {
          int id = 1;
          for (const auto& w : d.windows)
            if (w.output == d.outputs[static_cast<std::size_t>(j)])
              gp << "set object " << id++ << " rect from " << w.start << ", graph 0 to " << w.end
                 << ", graph 1 fc rgb '#ffd0d0' fs solid 0.5 noborder behind\n";
        }
        gp << "set xlabel 't [s]'\nset ylabel " << quote(d.outputs[static_cast<std::size_t>(j)]) << "\n";
        const auto c = [&](int block) { return 2 + block * ny + j; };
        gp << "plot " << quote((tmp / (tag + ".dat")).string()) << " using 1:" << c(0) << " with lines lw 2 lc rgb 'black' title 'measured', '' using 1:"
           << c(1) << " with lines lc rgb 'red' title 'nominal', '' using 1:" << c(2) << " with lines lc rgb 'blue' title 'augmented'\n";
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
      gp << "set output " << quote((tmp / "signature.png").string()) << "\n";
      gp << "set title " << quote("signature: residual of " + d.signature_output + " (measured - calibrated nominal) against " + d.signature_variable) << "\n";
      gp << "set xlabel " << quote(d.signature_variable) << "\nset ylabel " << quote("residual of " + d.signature_output) << "\n";
      gp << "plot " << quote((tmp / "signature.dat").string()) << " using 1:2 with points pt 7 ps 0.3 notitle\n";
      pngs.push_back("signature.png");
    }
    {
      std::ofstream o(tmp / "plots.gp");
      o << gp.str();
    }
    const std::string cmd = "gnuplot " + quote((tmp / "plots.gp").string()) + " 2>" + quote((tmp / "gnuplot.log").string());
    if (std::system(cmd.c_str()) != 0) throw InputError("gnuplot failed (see gnuplot's messages; is gnuplot installed?)");
    for (const auto& p : pngs)
      if (!fs::exists(tmp / p) || fs::file_size(tmp / p) == 0) throw InputError("gnuplot did not write " + p);
    {
      std::ofstream o(tmp / "report.txt");
      o << diagnosis_text(d);
      std::ofstream a(tmp / "augmented_model.json");
      a << augmented_text;
      if (!o || !a) throw InputError(dir + ": cannot write the report");
    }
    for (const auto& f : {std::string("report.txt"), std::string("augmented_model.json")}) pngs.push_back(f);
    for (const auto& p : pngs) fs::rename(tmp / p, fs::path(dir) / p);
    fs::remove_all(tmp);
  } catch (...) {
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sets-diagnose: locate where a model and recordings differ, name the missing physics, add it, "
               "and show the fit improve"};
  std::string model_path, data_path, val_path, json_path, report_dir;
  bool example = false, quiet = false;
  int threads = 2;
  app.add_option("--model", model_path, "model file (JSON, format version 1; see docs/model-format.md)");
  app.add_option("--data", data_path, "recording to calibrate and diagnose on (CSV with a header, or .mat)");
  app.add_option("--validation", val_path, "second recording, used to judge the hypotheses and the fit");
  app.add_option("--json", json_path, "write the diagnosis as JSON here");
  app.add_option("--report", report_dir, "write plots (PNG via gnuplot), report.txt and augmented_model.json here");
  app.add_flag("--example", example, "diagnose a built-in simulated example (no files needed)");
  std::string plant;
  bool no_floor = false;
  app.add_flag("--no-noise-floor", no_floor, "never stop early because the misfit is at the noise level (hypotheses must fail on their own)");
  app.add_option("--plant", plant, "with --suite fixed: only this synthetic plant (prints its full report)");
  std::string suite_kind;
  int count = 40, seed = 1;
  auto* suite_opt = app.add_option("--suite", suite_kind,
                                   "diagnose a suite of synthetic plants with known truth and print the scores (markdown): "
                                   "fixed (default) or random")
                        ->expected(0, 1);
  app.add_option("--count", count, "with --suite random: number of plants")->check(CLI::Range(1, 100000));
  app.add_option("--seed", seed, "with --suite random: the first plant's seed")->check(CLI::Range(0, 2000000000));
  app.add_option("--threads", threads, "threads for the competing hypotheses (with --suite: plants diagnosed at once)")->check(CLI::Range(1, 64));
  app.add_flag("--quiet", quiet, "no progress messages on stderr");
  CLI11_PARSE(app, argc, argv);
  try {
    if (suite_opt->count() > 0) {
      // Synthetic plants with known truth: the fixed suite, or `count` random plants from `seed`.
      if (suite_kind.empty()) suite_kind = "fixed";
      if (suite_kind != "fixed" && suite_kind != "random") {
        std::cerr << "sets-diagnose: --suite takes fixed or random, not \"" << suite_kind << "\"\n";
        return 1;
      }
      SuiteOptions so;
      so.threads = threads;
      if (no_floor) so.diagnosis.noise_floor_factor = 0;
      if (!quiet)
        so.on_plant = [](const SuitePlantResult& r, int done, int total) {
          std::string truth, named;
          for (const auto& t : r.truth) truth += (truth.empty() ? "" : ", ") + t.name;
          for (const auto& n : r.named) named += (named.empty() ? "" : ", ") + n;
          std::cerr << "[sets-diagnose] " << done << "/" << total << " " << r.name << " (" << r.family << "): true "
                    << (truth.empty() ? "none" : truth) << ", named " << (named.empty() ? "none" : named) << ", " << r.seconds << " s"
                    << (r.error.empty() ? "" : " ERROR " + r.error) << std::endl;
        };
      const auto results = suite_kind == "fixed" ? run_fixed_suite(plant, so)
                                                 : run_random_suite(static_cast<unsigned>(seed), count, so);
      if (suite_kind == "fixed" && !plant.empty()) {
        const SyntheticPlant p = synthetic_plant(plant);
        DiagnosisOptions opt;
        opt.threads = threads;
        if (no_floor) opt.noise_floor_factor = 0;
        std::cerr << diagnosis_text(diagnose(p.nominal, p.estimation, &p.validation, opt));
      }
      std::cout << suite_report(results);
      return 0;
    }
    ModelFile model;
    Recording est, val;
    bool have_val = false;
    if (example) {
      SyntheticPlant p = synthetic_plant("coulomb_friction");
      std::cout << "Built-in example: a mass on a spring driven by a force u, position x measured with 1 % noise;\n"
                   "the data were simulated WITH Coulomb friction (0.3 N), the nominal model has viscous damping only.\n\n";
      model = p.nominal;
      est = p.estimation;
      val = p.validation;
      have_val = true;
    } else {
      if (model_path.empty() || data_path.empty()) {
        std::cerr << "sets-diagnose: give --model and --data (or --example); see --help\n";
        return 1;
      }
      model = load_model_file(model_path);
      est = read_recording(data_path);
      if (!val_path.empty()) {
        val = read_recording(val_path);
        have_val = true;
      }
    }
    DiagnosisOptions opt;
    opt.threads = threads;
    if (no_floor) opt.noise_floor_factor = 0;
    if (!quiet) opt.progress = [](const std::string& s) { std::cerr << "[sets-diagnose] " << s << std::endl; };
    const Diagnosis d = diagnose(model, est, have_val ? &val : nullptr, opt);
    const std::string augmented_text = to_json_text(d.augmented);
    std::string augmented_path;
    if (!report_dir.empty())
      augmented_path = (fs::path(report_dir) / "augmented_model.json").string();
    else if (!json_path.empty()) {
      augmented_path = json_path;
      if (augmented_path.size() > 5 && augmented_path.substr(augmented_path.size() - 5) == ".json")
        augmented_path.resize(augmented_path.size() - 5);
      augmented_path += ".augmented_model.json";
    }
    if (!report_dir.empty()) write_report(d, report_dir, augmented_text);
    else if (!augmented_path.empty()) write_file_atomically(augmented_path, augmented_text);
    if (!json_path.empty()) write_file_atomically(json_path, diagnosis_json(d, augmented_path));
    std::cout << diagnosis_text(d);
    if (!augmented_path.empty()) std::cout << "Augmented model written to " << augmented_path << "\n";
    return 0;
  } catch (const std::exception& e) {
    return report_failure("sets-diagnose", e);
  }
}
