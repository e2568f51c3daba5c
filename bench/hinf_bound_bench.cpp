// The four steps of the Hakvoort–Van den Hof procedure on the app's built-in example (order-4
// system with a lightly damped resonance, Kautz basis n = 40, nominal order 2, |W^-1|^2 of
// degree 12): step 1 for stochastic and bounded noise, then steps 2–4 and the dense check.
//   ./build/bench/hinf_bound_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>

#include "sets/examples/hakvoort.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"

namespace {

constexpr double pi = std::numbers::pi;

sets::TransferFunction true_system() { return sets::hakvoort::system(); }

// u uniform in [-1, 1] from 3000 samples before the record; noise e (Gaussian, or uniform with
// |e| <= 0.02) through 1/(1 - 0.7 q^-1), as in the app.
sets::hakvoort::Data simulate(int N, bool bounded) {
  std::mt19937_64 rng(1);
  return sets::hakvoort::simulate(true_system(), N, 0.02, bounded, rng);
}

Eigen::VectorXd grid(int points) {
  Eigen::VectorXd g(points);
  for (int j = 0; j < points; ++j) g[j] = pi * (j + 0.5) / points;
  return g;
}

const sets::OrthonormalBasis& basis() {
  static const sets::OrthonormalBasis B = sets::OrthonormalBasis::kautz(std::polar(0.93, 0.66));
  return B;
}

// The app's priors for this basis (its "priors:" line, rounded up): 1.2 x max_k |g0(k)| / 0.88^k
// and 1.2 x the impulse-response envelope with rate 0.975.
sets::HinfPriors priors() {
  sets::HinfPriors p;
  p.M = 0.992;
  p.rho = 0.88;
  p.u_bar = 1;
  p.M_ic = 0.414;
  p.rho_ic = 0.975;
  return p;
}

sets::UncertaintyOptions uncertainty_options(bool bounded) {
  sets::UncertaintyOptions o;
  o.noise = bounded ? sets::NoiseModel::bounded : sets::NoiseModel::stochastic;
  o.v_bar = 0.02 / 0.3;
  return o;
}

void BM_UncertaintySet(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const bool bounded = state.range(1) != 0;
  const int points = bounded ? 100 : 150;
  const auto d = simulate(N, bounded);
  const Eigen::VectorXd w = grid(points);
  int lps = 0;
  for (auto _ : state) {
    const sets::UncertaintySet S = sets::uncertainty_set(d.u, d.y, basis(), 40, w, priors(), uncertainty_options(bounded));
    if (S.empty()) state.SkipWithError("the priors are falsified");
    lps = S.lp_solves;
    benchmark::DoNotOptimize(S.regions.data());
  }
  state.counters["lp_solves"] = lps;
  state.SetLabel(bounded ? "bounded noise, 100 frequencies" : "stochastic, 150 frequencies");
}

// Steps 2-4 on one stochastic uncertainty set (N = 2000, 150 frequencies).
const sets::UncertaintySet& stochastic_set() {
  static const sets::UncertaintySet S = [] {
    const auto d = simulate(2000, false);
    return sets::uncertainty_set(d.u, d.y, basis(), 40, grid(150), priors(), uncertainty_options(false));
  }();
  return S;
}

void BM_FitNominal(benchmark::State& state) {
  const auto& S = stochastic_set();
  sets::NominalOptions o;
  o.polygon_sides = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const sets::NominalFit f = sets::fit_nominal(S, o);
    benchmark::DoNotOptimize(f.max_error);
  }
}

void BM_FitWeight(benchmark::State& state) {
  const auto& S = stochastic_set();
  const sets::NominalFit f = sets::fit_nominal(S);
  const Eigen::VectorXd delta = sets::additive_error(S, f.model);
  sets::WeightOptions o;
  o.degree = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const sets::WeightFit W = sets::fit_weight(S.frequencies, delta, o);
    benchmark::DoNotOptimize(W.max_gap);
  }
}

void BM_ErrorBound(benchmark::State& state) {
  const auto& S = stochastic_set();
  const sets::NominalFit f = sets::fit_nominal(S);
  const sets::WeightFit W = sets::fit_weight(S.frequencies, sets::additive_error(S, f.model));
  for (auto _ : state) {
    const sets::BoundResult b = sets::error_bound(S, f.model, W.h);
    benchmark::DoNotOptimize(b.b);
  }
}

// The app's Monte Carlo check of one run: ||W (G0 - Ghat)|| on 4096 frequencies.
void BM_WeightedErrorCheck(benchmark::State& state) {
  const auto& S = stochastic_set();
  const sets::NominalFit f = sets::fit_nominal(S);
  const sets::WeightFit W = sets::fit_weight(S.frequencies, sets::additive_error(S, f.model));
  const sets::TransferFunction G0 = true_system();
  for (auto _ : state) {
    const double e = sets::weighted_error([&](double w) { return G0(w); }, f.model, W.h);
    benchmark::DoNotOptimize(e);
  }
}

}  // namespace

BENCHMARK(BM_UncertaintySet)
    ->Args({1000, 0})
    ->Args({2000, 0})
    ->Args({10000, 0})
    ->Args({1000, 1})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime();
BENCHMARK(BM_FitNominal)->Arg(16)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(BM_FitWeight)->Arg(12)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(BM_ErrorBound)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK(BM_WeightedErrorCheck)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

BENCHMARK_MAIN();
