// sets-diagnose: where a model and recordings differ, which physics is missing, the augmented
// model with its new parameters, and the fit before and after. See docs/methods/diagnosis.md.

#include <filesystem>
#include <iostream>

#include "common/cli.hpp"
#include "report.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/data/recording.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/examples/synthetic_plants.hpp"
#include "sets/models/model_file.hpp"

using namespace sets;

namespace {

// The augmented model is written beside the report, or beside the JSON as <name>.augmented_model.json.
std::string augmented_model_path(const std::string& report_dir, const std::string& json_path) {
  if (!report_dir.empty()) return (std::filesystem::path(report_dir) / "augmented_model.json").string();
  if (json_path.empty()) return {};
  std::string p = json_path;
  if (p.size() > 5 && p.substr(p.size() - 5) == ".json") p.resize(p.size() - 5);
  return p + ".augmented_model.json";
}

}  // namespace

int main(int argc, char** argv) {
  sets::app::Cli cli("sets-diagnose",
                     "sets-diagnose: locate where a model and recordings differ, name the missing physics, add it, "
                     "and show the fit improve");
  CLI::App& app = cli.app();
  std::string model_path, data_path, val_path, json_path, report_dir, plant, suite_kind;
  bool example = false, quiet = false, no_floor = false;
  int threads = 2, count = 40, seed = 1;
  app.add_option("--model", model_path, "model file (JSON, format version 1; see docs/model-format.md)");
  app.add_option("--data", data_path, "recording to calibrate and diagnose on (CSV with a header, or .mat)");
  app.add_option("--validation", val_path, "second recording, used to judge the hypotheses and the fit");
  cli.add_output_file("--json", json_path, "write the diagnosis as JSON here");
  cli.add_output_folder("--report", report_dir,
                        "write index.html, plots (PNG via gnuplot), report.txt and augmented_model.json here (the folder is "
                        "replaced as a whole)",
                        kReportFiles);
  app.add_flag("--example", example, "diagnose a built-in simulated example (no files needed)");
  app.add_flag("--no-noise-floor", no_floor,
               "never stop early because the misfit is at the noise level (hypotheses must fail on their own)");
  app.add_option("--plant", plant, "with --suite fixed: only this synthetic plant (prints its full report)");
  auto* suite = app.add_option("--suite", suite_kind,
                               "diagnose synthetic plants with known truth and print the scores (markdown): fixed "
                               "(the default) or random")
                    ->expected(0, 1);
  app.add_option("--count", count, "with --suite random: number of plants")->check(CLI::Range(1, 1000000));
  app.add_option("--seed", seed, "with --suite random: the first plant's seed")->check(CLI::Range(0, 2000000000));
  app.add_option("--threads", threads, "threads for the competing hypotheses (with --suite: plants at once)")
      ->check(CLI::Range(1, 64));
  app.add_flag("--quiet", quiet, "no progress messages on stderr");
  std::string intersample;
  app.add_option("--intersample", intersample,
                 "every input between samples: zoh (held), foh (linear) or bl (band-limited); overrides the model file");
  if (const auto code = cli.parse(argc, argv)) return *code;
  return cli.run([&] {
    DiagnosisOptions opt;
    opt.threads = threads;
    if (no_floor) opt.noise_floor_factor = 0;
    if (!intersample.empty()) opt.intersample = parse_intersample(intersample, "--intersample");
    if (suite->count() > 0) {
      if (suite_kind.empty()) suite_kind = "fixed";
      if (suite_kind != "fixed" && suite_kind != "random")
        throw InputError("--suite: fixed or random, not \"" + suite_kind + "\"");
      print_suite(suite_kind, plant, count, static_cast<unsigned>(seed), opt, quiet);
      return 0;
    }
    ModelFile model;
    Recording est, val;
    bool have_val = false;
    if (example) {
      SyntheticPlant p = synthetic_plant("coulomb_friction");
      std::cout << "Built-in example: a mass on a spring driven by a force u, position x measured with 1 % noise;\n"
                   "the data were simulated WITH Coulomb friction (0.3 N), the nominal model has viscous damping "
                   "only.\n\n";
      model = p.nominal;
      est = p.estimation;
      val = p.validation;
      have_val = true;
    } else {
      if (model_path.empty() || data_path.empty()) throw InputError("give --model and --data (or --example); see --help");
      model = load_model_file(model_path);
      est = read_recording(data_path);
      if (!val_path.empty()) {
        val = read_recording(val_path);
        have_val = true;
      }
    }
    if (!quiet) opt.progress = [](const std::string& s) { std::cerr << "[sets-diagnose] " << s << std::endl; };
    const Diagnosis d = diagnose(model, est, have_val ? &val : nullptr, opt);
    const std::string augmented_text = to_json_text(d.augmented);
    const std::string augmented_path = augmented_model_path(report_dir, json_path);
    if (!report_dir.empty())
      write_report(d, report_dir, augmented_text);
    else if (!augmented_path.empty())
      write_file_atomically(augmented_path, augmented_text);
    if (!json_path.empty()) write_file_atomically(json_path, diagnosis_json(d, augmented_path));
    std::cout << diagnosis_text(d);
    if (!augmented_path.empty()) std::cout << "Augmented model written to " << augmented_path << "\n";
    return 0;
  });
}
