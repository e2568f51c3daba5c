// Set types: zonotope order reduction and Minkowski sums (dimension 10-50, 100-1000 generators),
// point containment, H->V in 2-D/3-D (CGAL exact), ellipsoid strip updates.
//   ./build/bench/set_types_bench --benchmark_min_time=0.1 --benchmark_repetitions=3 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>

#include "sets/domains/conversions.hpp"
#include "sets/domains/ellipsoid.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/domains/vpolytope.hpp"
#include "sets/domains/zonotope.hpp"

namespace {

sets::Zonotope random_zonotope(int n, int m, std::uint64_t seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  return sets::Zonotope(Eigen::VectorXd::NullaryExpr(n, [&] { return U(g); }),
                        Eigen::MatrixXd::NullaryExpr(n, m, [&] { return U(g); }));
}

void ReduceOrder(benchmark::State& st, sets::ReductionMethod method) {
  const int n = static_cast<int>(st.range(0)), m = static_cast<int>(st.range(1));
  const auto Z = random_zonotope(n, m, 1);
  for (auto _ : st) benchmark::DoNotOptimize(sets::reduce_order(Z, 5.0, method));
  // Tightness: mean over random directions of support(reduced) / support(original), both
  // about the centre (1 = no loss).
  const auto R = sets::reduce_order(Z, 5.0, method);
  std::mt19937_64 g(9);
  std::normal_distribution<double> N;
  double ratio = 0;
  for (int k = 0; k < 200; ++k) {
    const Eigen::VectorXd d = Eigen::VectorXd::NullaryExpr(n, [&] { return N(g); });
    ratio += (sets::support(R, d) - d.dot(Z.center())) / (sets::support(Z, d) - d.dot(Z.center()));
  }
  st.counters["support_ratio"] = ratio / 200;
}
void Args(benchmark::internal::Benchmark* b) {
  for (int n : {10, 50})
    for (int m : {100, 1000}) b->Args({n, m});
  b->Unit(benchmark::kMicrosecond);
}
BENCHMARK_CAPTURE(ReduceOrder, girard, sets::ReductionMethod::girard)->Apply(Args);
BENCHMARK_CAPTURE(ReduceOrder, combastel, sets::ReductionMethod::combastel)->Apply(Args);
BENCHMARK_CAPTURE(ReduceOrder, pca, sets::ReductionMethod::pca)->Apply(Args);

void MinkowskiSum(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0)), m = static_cast<int>(st.range(1));
  const auto A = random_zonotope(n, m, 2), B = random_zonotope(n, m, 3);
  for (auto _ : st) benchmark::DoNotOptimize(sets::minkowski_sum(A, B));
}
BENCHMARK(MinkowskiSum)->Apply(Args);

void LinearMap(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0)), m = static_cast<int>(st.range(1));
  const auto Z = random_zonotope(n, m, 4);
  const Eigen::MatrixXd A = random_zonotope(n, n, 5).generators();
  for (auto _ : st) benchmark::DoNotOptimize(sets::linear_map(A, Z));
}
BENCHMARK(LinearMap)->Apply(Args);

void ZonotopeContains(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0)), m = static_cast<int>(st.range(1));
  const auto Z = random_zonotope(n, m, 6);
  const Eigen::VectorXd x = Z.center() + 0.5 * Z.generators().col(0);
  for (auto _ : st) benchmark::DoNotOptimize(sets::contains(Z, x));
}
BENCHMARK(ZonotopeContains)->Args({10, 100})->Args({10, 1000})->Args({50, 100})->Unit(benchmark::kMicrosecond);

void HPolytopeContains(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const auto H = sets::to_hpolytope(random_zonotope(n, 8, 7));
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  for (auto _ : st) benchmark::DoNotOptimize(sets::contains(H, x));
  st.counters["rows"] = H.num_constraints();
}
BENCHMARK(HPolytopeContains)->Arg(2)->Arg(3)->Unit(benchmark::kMicrosecond);

// Polytope with k facets tangent to the unit circle (2-D) or on a Fibonacci sphere (3-D).
sets::HPolytope tangent_polytope(int n, int k) {
  Eigen::MatrixXd A(k, n);
  for (int i = 0; i < k; ++i) {
    if (n == 2) {
      const double t = 2 * std::numbers::pi * i / k;
      A.row(i) << std::cos(t), std::sin(t);
    } else {
      const double z = 1 - 2 * (i + 0.5) / k, r = std::sqrt(1 - z * z);
      const double t = std::numbers::pi * (3 - std::sqrt(5.0)) * i;
      A.row(i) << r * std::cos(t), r * std::sin(t), z;
    }
  }
  return sets::HPolytope(A, Eigen::VectorXd::Ones(k));
}

void HToV(benchmark::State& st) {
  const auto P = tangent_polytope(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  for (auto _ : st) benchmark::DoNotOptimize(sets::to_vpolytope(P));
}
BENCHMARK(HToV)->Args({2, 32})->Args({2, 256})->Args({3, 32})->Args({3, 256})->Unit(benchmark::kMillisecond);

void VToH(benchmark::State& st) {
  const auto V = sets::to_vpolytope(tangent_polytope(static_cast<int>(st.range(0)), static_cast<int>(st.range(1))));
  for (auto _ : st) benchmark::DoNotOptimize(sets::to_hpolytope(V));
}
BENCHMARK(VToH)->Args({2, 256})->Args({3, 256})->Unit(benchmark::kMillisecond);

void HOuterBox(benchmark::State& st) {
  const auto P = tangent_polytope(static_cast<int>(st.range(0)), static_cast<int>(st.range(1)));
  for (auto _ : st) benchmark::DoNotOptimize(sets::outer_box(P));
}
BENCHMARK(HOuterBox)->Args({3, 256})->Unit(benchmark::kMillisecond);

void EllipsoidStrip(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  std::mt19937_64 g(8);
  std::uniform_real_distribution<double> U(-1, 1);
  const auto E = sets::Ellipsoid::ball(Eigen::VectorXd::Zero(n), 10.0);
  const Eigen::VectorXd a = Eigen::VectorXd::NullaryExpr(n, [&] { return U(g); });
  for (auto _ : st) benchmark::DoNotOptimize(sets::intersect_strip(E, a, 0.3, 0.1));
}
BENCHMARK(EllipsoidStrip)->Arg(4)->Arg(10)->Arg(50)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
