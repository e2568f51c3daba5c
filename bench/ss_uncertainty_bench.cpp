// Cost of one Monte Carlo run of sets-ss-uncertainty (Farah et al., Section V), by stage.
#include <benchmark/benchmark.h>

#include <random>

#include "sets/examples/farah.hpp"
#include "sets/methods/ss_uncertainty/level_set_uncertainty.hpp"
#include "sets/methods/ss_uncertainty/ss_uncertainty.hpp"
#include "sets/methods/ss_uncertainty/propagator_identification.hpp"
#include "sets/methods/ss_uncertainty/state_enclosure.hpp"

namespace {

struct Data {
  Eigen::MatrixXd u, y;
  std::vector<sets::ObservabilityRow> rows;
  Eigen::VectorXd truth;
  sets::GuaranteedSetAssumptions assumptions;  // uniform noise bound and the FIR tail, as the app
};

const Data& data() {
  static const Data d = [] {
    const sets::StateSpaceModel s = sets::farah::system();
    Data r;
    std::mt19937_64 rng(1);
    const auto d = sets::farah::simulate(s, 1000, 20.0, rng);  // random binary input, 20 dB output noise, as in the app
    r.assumptions.noise_bound = d.largest_noise * (1 + 1e-9);
    r.assumptions.tail_bound = sets::fir_tail_bound(s, 20, 1.0);
    r.u = d.u;
    r.y = d.y;
    r.rows = sets::select_rows(s.A, s.C, sets::RowSelection::output_major);
    r.truth = sets::CanonicalStructure(r.rows, 2, 2, false).to_parameters(sets::canonical_form(s, r.rows));
    return r;
  }();
  return d;
}

sets::PropagatorResult identify() {
  sets::PropagatorOptions o;
  o.order = 3;
  o.past = 20;
  o.rows = data().rows;
  return sets::identify_propagator(data().u, data().y, o);
}

void BM_Identify(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(identify());
}
BENCHMARK(BM_Identify)->Unit(benchmark::kMillisecond);

void BM_LevelSetAndPairs(benchmark::State& state) {
  const auto id = identify();
  for (auto _ : state) {
    const auto dom = sets::level_set_domain(id.regression);
    int out = sets::contains(dom.ellipsoid, data().truth) == sets::BoolInterval::no;
    for (int i = 0; i < 12; ++i)
      for (int j = i + 1; j < 12; ++j) {
        const auto v = sets::pair_view(dom.ellipsoid, i, j);
        const Eigen::Vector2d p(data().truth[i], data().truth[j]);
        out += sets::contains(v.projection, p) == sets::BoolInterval::no;
        out += v.slice && sets::contains(*v.slice, p) == sets::BoolInterval::no;
      }
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_LevelSetAndPairs)->Unit(benchmark::kMillisecond);

void BM_FpsContains(benchmark::State& state) {
  const auto id = identify();
  const auto dom = sets::level_set_domain(id.regression);
  for (auto _ : state) {
    const auto fps = sets::regression_fps(id.regression, dom.ell);
    benchmark::DoNotOptimize(fps.contains(data().truth));
  }
}
BENCHMARK(BM_FpsContains)->Unit(benchmark::kMillisecond);

void BM_FpsPui(benchmark::State& state) {
  const auto id = identify();
  const auto dom = sets::level_set_domain(id.regression);
  const auto fps = sets::regression_fps(id.regression, dom.ell);
  for (auto _ : state) benchmark::DoNotOptimize(sets::pui(fps));
}
BENCHMARK(BM_FpsPui)->Unit(benchmark::kMillisecond);

// The guaranteed set: state enclosures (verified Gram matrix, Markov ellipsoids, functionals),
// the interval-regressor FPS and the membership of the truth; then its PUIs.
void BM_GuaranteedFps(benchmark::State& state) {
  const auto id = identify();
  for (auto _ : state) {
    const auto X = sets::enclose_states(id, data().u, data().y, data().assumptions);
    const auto fps = sets::guaranteed_fps(id, data().u, data().y, X, data().assumptions.noise_bound);
    benchmark::DoNotOptimize(fps.contains(data().truth));
  }
}
BENCHMARK(BM_GuaranteedFps)->Unit(benchmark::kMillisecond);

void BM_GuaranteedPui(benchmark::State& state) {
  const auto id = identify();
  const auto X = sets::enclose_states(id, data().u, data().y, data().assumptions);
  const auto fps = sets::guaranteed_fps(id, data().u, data().y, X, data().assumptions.noise_bound);
  for (auto _ : state) benchmark::DoNotOptimize(sets::pui(fps));
}
BENCHMARK(BM_GuaranteedPui)->Unit(benchmark::kMillisecond);

// One whole run of the library call as the app's default campaign makes it (identification,
// ellipsoid, estimate FPS with its PUIs, state enclosures and the guaranteed FPS, no guaranteed
// PUIs); the app adds the simulation and the membership tests of the truth.
void BM_SsUncertaintyRun(benchmark::State& state) {
  sets::SsUncertaintyOptions o;
  o.identification.order = 3;
  o.identification.past = 20;
  o.identification.rows = data().rows;
  o.guaranteed = data().assumptions;
  o.guaranteed_pui = false;
  for (auto _ : state) benchmark::DoNotOptimize(sets::ss_uncertainty(data().u, data().y, o));
}
BENCHMARK(BM_SsUncertaintyRun)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
