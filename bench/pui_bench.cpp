// PUIs of a p = 6 bounded-error problem with N = 10^3, 10^4, 10^5 strips: cold versus warm
// start, with and without safe bounds, the dense simplex (default) versus GLPK for every LP.
//   ./build/bench/pui_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <random>

#include "sets/fps/feasible_parameter_set.hpp"

namespace {

sets::FeasibleParameterSet make_fps(int N) {
  const int p = 6;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd theta(p);
  theta << 0.5, -0.2, 0.3, 0.1, 1.0, 0.2;
  Eigen::MatrixXd Phi = Eigen::MatrixXd::NullaryExpr(N, p, [&] { return U(rng); });
  Eigen::VectorXd delta = Eigen::VectorXd::Constant(N, 0.05);
  Eigen::VectorXd y = Phi * theta + Eigen::VectorXd::NullaryExpr(N, [&] { return 0.05 * U(rng); });
  return sets::FeasibleParameterSet::from_data(Phi, y, delta);
}

void BM_Pui(benchmark::State& state) {
  const auto fps = make_fps(static_cast<int>(state.range(0)));
  sets::PuiOptions options;
  options.warm_start = state.range(1) != 0;
  options.safe = state.range(2) != 0;
  options.solver = state.range(3) != 0 ? sets::PuiLpSolver::dense : sets::PuiLpSolver::glpk;
  int lps = 0, fallbacks = 0;
  for (auto _ : state) {
    auto r = sets::pui(fps, options);
    if (options.safe && !r.guaranteed) state.SkipWithError("PUI not certified");
    lps = r.lp_solves;
    fallbacks = r.lp_fallbacks;
    benchmark::DoNotOptimize(r.box);
  }
  state.counters["LPs"] = lps;
  state.counters["to_GLPK"] = fallbacks;
  state.SetLabel(std::string(options.warm_start ? "warm" : "cold") + (options.safe ? ",safe" : ",float") +
                 (state.range(3) != 0 ? ",dense" : ",glpk"));
}

}  // namespace

BENCHMARK(BM_Pui)
    ->ArgsProduct({{1000, 10000, 100000}, {0, 1}, {0, 1}, {0, 1}})
    ->ArgNames({"N", "warm", "safe", "dense"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

namespace {

// Building the set strip by strip (add_strip), as a recursive estimator would.
void BM_AddStrip(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const auto src = make_fps(N);
  const Eigen::MatrixXd Phi = sets::midpoint(sets::IntervalMatrix(src.regressors()));
  const Eigen::VectorXd y = sets::midpoint(sets::IntervalVector(src.outputs()));
  for (auto _ : state) {
    sets::FeasibleParameterSet fps(6);
    for (int t = 0; t < N; ++t) fps.add_strip(Phi.row(t).transpose(), y[t], 0.05);
    benchmark::DoNotOptimize(fps.size());
  }
}

}  // namespace

BENCHMARK(BM_AddStrip)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
