// sets-hinf-bound: a nominal model, a weighting W and a bound b with
// ||W (Ghat - G0)||_inf <= b, from time-domain data (Hakvoort & Van den Hof).
// Built-in example (no --data): Monte Carlo over simulated data; with --data: one real data set.

#include <ctime>
#include <iostream>
#include <string>

#include "common/cli.hpp"
#include "flags.hpp"
#include "runs.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/examples/hakvoort.hpp"

int main(int argc, char** argv) {
  sets::app::Cli cli("sets-hinf-bound", "sets-hinf-bound: nominal model + weighted H-infinity error bound from "
                                        "time-domain data (Hakvoort & Van den Hof)");
  Settings s;
  auto& p = s.structure.priors;
  p.rho = 0.88, p.M = -1, p.M_ic = -1, p.rho_ic = -1, s.structure.order = 40;
  Flags f;
  add_flags(cli, s, f);
  if (const auto code = cli.parse(argc, argv)) return *code;

  return cli.run([&] {
    const sets::TransferFunction G0 = sets::hakvoort::system();
    const std::string prior_note = configure(s, f, G0);
    print_header(s, f, prior_note);
    const sets::HinfData data = load_data(s, f, G0);
    const std::clock_t cpu0 = std::clock();
    const Runs runs = run_all(s, data, G0);
    if (runs.first.set.empty()) {
      std::cout << "\nThe data falsify the priors (bounded noise): " << runs.first.set.consistency.message() << "\n";
      return int(sets::exit_falsified);
    }
    const double cpu_per_run = double(std::clock() - cpu0) / CLOCKS_PER_SEC / s.runs;  // includes simulation
    print_results(s, runs, cpu_per_run);
    sets::app::write_json(f.json_path, results_json(s, runs, s.builtin ? s.N : int(data.u.size()), cpu_per_run), 1);
    if (!f.plot_path.empty()) plot(f.plot_path, runs.first, s.builtin ? &G0 : nullptr);
    return int(sets::exit_success);
  });
}
