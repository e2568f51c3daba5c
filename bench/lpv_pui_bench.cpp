// PUIs of Cerone–Regruto's LPV example (Section IV, lambda uniform, Delta E = 4.8e-3) on one core:
// N = 1000 and N = 10^5 with the Remark-2 orthants, the same with every sample in every LP
// (no working set), each with the dense simplex (default) and with GLPK for every LP, and the
// interval regression (eqs. 18–34) on its own.
//
//   ./build/bench/lpv_pui_bench --benchmark_repetitions=7 --benchmark_report_aggregates_only=true
//
// With SETS_DUMP_LPV_POLYTOPE=<file> it first writes the H-polytope of the orthant piece that
// pui() visits (N = 1000: rows "a_1 ... a_p b" of a x <= b, then the PUI ends as
// "# pui lo hi" lines) for the scipy/HiGHS comparison, bench/pui_scipy_highs.py.

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <fstream>
#include <iomanip>
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
  opt.solver = state.range(2) != 0 ? sets::PuiLpSolver::dense : sets::PuiLpSolver::glpk;
  int lps = 0, orthants = 0, fallbacks = 0;
  for (auto _ : state) {
    const auto r = sets::pui(fps, opt);
    if (r.empty() || !r.guaranteed) state.SkipWithError("PUI empty or not certified");
    lps = r.lp_solves;
    fallbacks = r.lp_fallbacks;
    orthants = static_cast<int>(r.orthants.size());
    benchmark::DoNotOptimize(r.box.data());
  }
  state.counters["LPs"] = lps;
  state.counters["orthants"] = orthants;
  state.counters["to_GLPK"] = fallbacks;
}
BENCHMARK(BM_LpvPui)->ArgNames({"N", "working_set", "dense"})
    ->Args({1000, 1, 1})->Args({1000, 1, 0})->Args({1000, 0, 1})->Args({1000, 0, 0})
    ->Args({10000, 1, 1})->Args({10000, 1, 0})->Args({100000, 1, 1})->Args({100000, 1, 0})
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

void dump_polytope(const char* path) {
  const auto fps = paper_fps(1000);
  const auto r = sets::pui(fps);
  if (r.orthants.size() != 1) throw std::runtime_error("expected one orthant");
  const sets::HPolytope P = fps.orthant_polytope(r.orthants[0].signs);
  std::ofstream out(path);
  out << std::setprecision(17);
  for (int i = 0; i < P.num_constraints(); ++i) {
    for (int j = 0; j < P.dimension(); ++j) out << P.A()(i, j) << ' ';
    out << P.b()[i] << '\n';
  }
  for (Eigen::Index j = 0; j < r.box.size(); ++j) out << "# pui " << r.box[j].lower() << ' ' << r.box[j].upper() << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  if (const char* path = std::getenv("SETS_DUMP_LPV_POLYTOPE")) dump_polytope(path);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
