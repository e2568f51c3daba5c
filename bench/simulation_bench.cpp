// One simulation of a Silverbox-sized record (86 845 samples, what the diagnosis repeats a few
// thousand times): the linear oscillator with a cubic stiffness, 2 RK4 substeps (the diagnosis'
// screening step) and 10 (its reported fits), input held or band-limited; and a finite-difference
// Jacobian's four columns, one simulation at a time or side by side (Simulator::simulate_outputs_each).
//   ./build/bench/simulation_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"

namespace {

const char* kDuffing = R"json({"time": "t", "inputs": {"u": "V1"},
  "parameters": {"g": 188000, "c": 43, "k": 198000, "k3": 7.3e5},
  "states": {"y": "V2", "v": 0.0},
  "derivatives": {"y": "v", "v": "g*u - c*v - k*y - k3*y^3"}, "outputs": {"y": "V2"}})json";

sets::Recording record(int n) {
  const double Ts = 0.0016384;
  std::vector<double> t(static_cast<std::size_t>(n)), u(t.size()), y(t.size(), 0.0);
  for (std::size_t k = 0; k < t.size(); ++k) {
    t[k] = static_cast<double>(k) * Ts;
    for (int l = 1; l <= 40; ++l) u[k] += 0.005 * std::sin(2 * M_PI * 5.0 * l * t[k] + l * l);
  }
  sets::Recording r;
  r.source = "bench";
  r.add("t", t);
  r.add("V1", u);
  r.add("V2", y);
  return r;
}

void BM_Simulate(benchmark::State& state) {
  static const sets::Recording data = record(86845);
  sets::ModelFile m = sets::parse_model(kDuffing, "duffing.json");
  if (state.range(1)) m.intersample = {{"u", "bl"}};
  const sets::Simulator sim(m, data, {static_cast<int>(state.range(0))});
  const Eigen::VectorXd p = sim.parameter_values();
  Eigen::MatrixXd y;
  for (auto _ : state) {
    if (!sim.simulate_outputs(p, y)) state.SkipWithError("blew up");
    benchmark::DoNotOptimize(y.data());
  }
  state.SetLabel(std::string(state.range(1) ? "bl" : "zoh") + ", " + std::to_string(state.range(0)) + " substeps");
}

// The four columns of a Jacobian (g, c, k, k3 each moved by 1e-3), 2 substeps, input held: one
// at a time (range 0 = 0) or side by side (1). The outputs are the same bit for bit.
void BM_SimulateJacobianColumns(benchmark::State& state) {
  static const sets::Recording data = record(86845);
  const sets::Simulator sim(sets::parse_model(kDuffing, "duffing.json"), data, {2});
  Eigen::MatrixXd columns = sim.parameter_values().replicate(1, 4);
  for (Eigen::Index j = 0; j < 4; ++j) columns(j, j) *= 1.001;
  Eigen::MatrixXd y;
  std::vector<Eigen::MatrixXd> ys;
  std::vector<bool> ok;
  for (auto _ : state) {
    if (state.range(0)) {
      sim.simulate_outputs_each(columns, ys, ok);
      benchmark::DoNotOptimize(ys.data());
    } else {
      for (Eigen::Index j = 0; j < 4; ++j) sim.simulate_outputs(columns.col(j), y);
      benchmark::DoNotOptimize(y.data());
    }
  }
  state.SetLabel(state.range(0) ? "side by side" : "one at a time");
}

}  // namespace

BENCHMARK(BM_SimulateJacobianColumns)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Simulate)->ArgsProduct({{2, 10}, {0, 1}})->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
