// PUIs of Cerone–Regruto's LPV example (Section IV, lambda uniform, Delta E = 4.8e-3) on one core:
// N = 1000 and N = 10^5 with the Remark-2 orthants, the same with every sample in every LP
// (no working set), and the interval regression (eqs. 18–34) on its own.
//
//   ./build/bench/lpv_pui_bench --benchmark_repetitions=7 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <random>

#include "sets/examples/cerone_regruto.hpp"
#include "sets/methods/lpv_pui/lpv_pui.hpp"

namespace {

sets::LpvMeasurements paper_data(int N, std::uint64_t seed, double delta) {
  std::mt19937_64 rng(seed);
  return sets::cerone_regruto::simulate(N, true, delta, rng).data;
}

sets::FeasibleParameterSet paper_fps(int N) {
  const auto reg = sets::lpv_regression(sets::cerone_regruto::structure(), paper_data(N, 1, 4.8e-3));
  return sets::FeasibleParameterSet::from_interval_data(reg.Phi, reg.Y);
}

void BM_LpvPui(benchmark::State& state) {
  const auto fps = paper_fps(static_cast<int>(state.range(0)));
  sets::PuiOptions opt;
  opt.working_set = state.range(1) != 0;
  int lps = 0, orthants = 0;
  for (auto _ : state) {
    const auto r = sets::pui(fps, opt);
    if (r.empty() || !r.guaranteed) state.SkipWithError("PUI empty or not certified");
    lps = r.lp_solves;
    orthants = static_cast<int>(r.orthants.size());
    benchmark::DoNotOptimize(r.box.data());
  }
  state.counters["LPs"] = lps;
  state.counters["orthants"] = orthants;
}
BENCHMARK(BM_LpvPui)->ArgNames({"N", "working_set"})
    ->Args({1000, 1})->Args({1000, 0})->Args({100000, 1})
    ->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

void BM_LpvRegression(benchmark::State& state) {
  const auto m = sets::cerone_regruto::structure();
  const auto d = paper_data(static_cast<int>(state.range(0)), 1, 4.8e-3);
  for (auto _ : state) {
    const auto reg = sets::lpv_regression(m, d);
    benchmark::DoNotOptimize(reg.Phi.data());
  }
}
BENCHMARK(BM_LpvRegression)->Arg(1000)->Arg(100000)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
