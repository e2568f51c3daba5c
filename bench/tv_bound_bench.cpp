// Cost of the Salehpour–Johansson methods on the overhead crane (Section VII): the biaffine
// regression (3)-(4), the l-inf LP (8) and the sparse MILP (14) on a small single-step problem.
#include <benchmark/benchmark.h>

#include <random>

#include "sets/examples/crane.hpp"
#include "sets/methods/tv_bound/tv_bound.hpp"

namespace {

const Eigen::Vector3d kNominal(2.0, 3.3, 0.25);  // (b0, lambda0, kappa0)

sets::TimeVaryingModel crane() { return sets::crane::model(kNominal[1], kNominal[2], kNominal[0]); }

// The app's default input: a square wave of period 4 s.
Eigen::MatrixXd input(int N) { return sets::crane::input("square", N, 1); }

// Crane data: the perturbation pi, white noise of window norm `noise` (window w).
sets::TvBoundData crane_data(const Eigen::MatrixXd& pi, double noise, const sets::WindowNorm& w) {
  const int N = static_cast<int>(pi.rows());
  const auto m = crane();
  const Eigen::MatrixXd u = input(N);
  const Eigen::VectorXd x0 = Eigen::Vector3d::Zero();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd eta(N + 1);
  for (int k = 0; k <= N; ++k) eta[k] = U(rng);
  eta *= noise / w(eta);
  return {sets::biaffine_regression(m, x0, u), sets::simulate(m, x0, u, pi).y + eta, {w}};
}

// Table I, case 1 (as in the app): piecewise-constant steps in all three parameters.
Eigen::MatrixXd table1_case1(int N) { return sets::crane::perturbation(sets::crane::cases("I").front(), N); }

void BM_BiaffineRegression(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const auto m = crane();
  const Eigen::MatrixXd u = input(N);
  const Eigen::VectorXd x0 = Eigen::Vector3d::Zero();
  for (auto _ : state) benchmark::DoNotOptimize(sets::biaffine_regression(m, x0, u));
}
BENCHMARK(BM_BiaffineRegression)->ArgName("N")->Arg(60)->Arg(120)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_LinfBound(benchmark::State& state) {
  const int N = static_cast<int>(state.range(0));
  const auto data = crane_data(table1_case1(N), 0.1, sets::WindowNorm::pulse(36, 1.0 / 35));
  sets::LinfBoundOptions o;
  o.F = o.G = kNominal.cwiseInverse();
  for (auto _ : state) benchmark::DoNotOptimize(sets::linf_bound(data, o));
}
BENCHMARK(BM_LinfBound)->ArgName("N")->Arg(60)->Arg(120)->Arg(200)->Unit(benchmark::kMillisecond);

// One step of +50 % in lambda (pi2) at sample 12 of N = 30 (window 8, noise 0.01): GLPK proves
// optimality here (the same step in kappa was not proven optimal in 60 s); eps from (8) and the
// l-inf trajectory as warm start, as the app does.
void BM_SparseBoundSingleStep(benchmark::State& state) {
  const int N = 30;
  Eigen::MatrixXd pi = Eigen::MatrixXd::Zero(N, 3);
  pi.block(12, 1, N - 12, 1).setConstant(0.5 * kNominal[1]);
  const auto data = crane_data(pi, 0.01, sets::WindowNorm::pulse(8, 1.0 / 8));
  sets::LinfBoundOptions lo;
  lo.F = lo.G = kNominal.cwiseInverse();
  const auto lin = sets::linf_bound(data, lo);
  sets::SparseBoundOptions o;
  o.F = lo.F;
  o.mu = 1e-3 * kNominal;
  o.max_abs = 2 * kNominal;
  o.epsilon = lin.epsilon;
  o.start = lin.pi;
  o.milp.time_limit_s = 60;
  for (auto _ : state) {
    const auto r = sets::sparse_bound(data, o);
    if (r.status != sets::MilpStatus::optimal) {
      state.SkipWithError("the MILP was not solved to optimality within 60 s");
      break;
    }
    state.counters["jumps"] = static_cast<double>(r.changes.size());
    state.counters["first_jump_at"] = r.changes.empty() ? -1 : r.changes.front().sample;  // truth: 12
    state.counters["first_jump_in"] = r.changes.empty() ? -1 : r.changes.front().parameter;  // truth: 1
  }
}
BENCHMARK(BM_SparseBoundSingleStep)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
