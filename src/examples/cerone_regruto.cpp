#include "sets/examples/cerone_regruto.hpp"

#include <cmath>

namespace sets::cerone_regruto {

LpvModelStructure structure() {
  LpvModelStructure m;
  m.alpha = 1;
  m.a = {{BasisFunction::power(0, 1)}, {BasisFunction(), BasisFunction::power(0, 2)}};
  m.b = {{}, {BasisFunction()}, {BasisFunction::power(0, 1), BasisFunction::power(0, 2)}};
  return m;
}

Eigen::VectorXd true_theta() {
  Eigen::VectorXd theta(6);
  theta << 0.5, -0.2, 0.3, 0.1, 1.0, 0.2;
  return theta;
}

LpvModelStructure lagged_structure() {
  LpvModelStructure m;
  m.alpha = 2;
  m.a = {{BasisFunction::power(0, 1)}, {BasisFunction(), BasisFunction::power(1, 2)}};
  m.b = {{}, {BasisFunction()}, {BasisFunction::power(1, 1), BasisFunction::power(1, 2)}};
  return m;
}

Eigen::MatrixXd lagged(const Eigen::Ref<const Eigen::VectorXd>& x) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(x.size(), 2);
  for (Eigen::Index t = 1; t < x.size(); ++t) m(t, 0) = x[t - 1];
  for (Eigen::Index t = 2; t < x.size(); ++t) m(t, 1) = x[t - 2];
  return m;
}

const std::array<PaperTable, 4>& paper_tables() {
  static const std::array<PaperTable, 4> tables = {{
      {"I", true, 100, {7.5e-4, 3.75e-3, 7.9e-3, 3.8e-2},
       {{58.9, 61.3, {0.500, -0.200, 0.299, 0.100, 1.000, 0.201}, {1.6e-3, 2.7e-3, 3.8e-3, 9.4e-4, 2.5e-3, 2.8e-3}},
         {44.2, 48.1, {0.501, -0.197, 0.295, 0.102, 0.999, 0.198}, {8.9e-3, 1.5e-2, 2.0e-2, 6.4e-3, 1.1e-2, 1.3e-2}},
         {38.6, 40.8, {0.501, -0.185, 0.278, 0.100, 1.001, 0.202}, {2.2e-2, 3.5e-2, 4.8e-2, 1.1e-2, 2.8e-2, 3.3e-2}},
         {24.5, 27.5, {0.513, -0.188, 0.268, 0.106, 1.020, 0.178}, {8.1e-2, 1.5e-1, 1.8e-1, 5.0e-2, 1.1e-1, 1.1e-1}}}},
      {"II", true, 1000, {9.7e-4, 4.8e-3, 9.6e-3, 4.8e-2},
       {{56.0, 60.0, {0.500, -0.200, 0.300, 0.100, 1.000, 0.200}, {1.1e-3, 6.6e-4, 1.3e-3, 4.3e-4, 1.2e-3, 1.2e-3}},
         {41.9, 46.2, {0.502, -0.201, 0.301, 0.100, 0.999, 0.199}, {8.5e-3, 4.5e-3, 9.2e-3, 2.5e-3, 6.7e-3, 6.7e-3}},
         {36.0, 40.2, {0.498, -0.202, 0.306, 0.098, 0.999, 0.203}, {1.2e-2, 6.5e-3, 1.1e-2, 2.6e-3, 1.1e-2, 1.1e-2}},
         {22.1, 26.1, {0.521, -0.192, 0.281, 0.093, 0.996, 0.218}, {7.6e-2, 3.1e-2, 7.7e-2, 2.4e-2, 7.9e-2, 8.7e-2}}}},
      {"III", false, 100, {1.0e-3, 5.0e-3, 1.06e-2, 5.2e-2},
       {{57.8, 61.3, {0.499, -0.200, 0.299, 0.100, 1.000, 0.200}, {1.9e-3, 3.4e-3, 5.0e-3, 1.3e-3, 2.2e-3, 2.4e-3}},
         {43.1, 48.1, {0.499, -0.204, 0.304, 0.101, 1.001, 0.197}, {1.2e-2, 1.7e-2, 2.6e-2, 4.3e-3, 1.4e-2, 1.6e-2}},
         {37.5, 40.8, {0.498, -0.199, 0.292, 0.101, 1.003, 0.198}, {2.5e-2, 3.5e-2, 5.8e-2, 1.0e-2, 2.8e-2, 3.2e-2}},
         {23.3, 27.5, {0.504, -0.186, 0.244, 0.096, 1.003, 0.229}, {1.1e-1, 1.4e-1, 2.0e-1, 5.5e-2, 1.1e-1, 1.1e-1}}}},
      {"IV", false, 1000, {1.0e-3, 5.0e-3, 1.0e-2, 5.0e-2},
       {{57.4, 61.9, {0.500, -0.200, 0.301, 0.100, 1.000, 0.200}, {2.0e-4, 2.9e-4, 3.1e-4, 7.0e-5, 3.4e-4, 3.6e-4}},
         {43.5, 48.0, {0.503, -0.201, 0.300, 0.099, 1.000, 0.201}, {7.5e-4, 6.0e-4, 7.6e-4, 1.0e-4, 1.9e-3, 7.8e-4}},
         {37.7, 41.8, {0.496, -0.199, 0.296, 0.101, 0.997, 0.202}, {6.5e-3, 1.3e-2, 1.4e-2, 5.3e-3, 9.1e-3, 1.2e-2}},
         {23.5, 28.0, {0.492, -0.159, 0.247, 0.114, 1.002, 0.209}, {3.0e-2, 4.9e-2, 5.3e-2, 1.4e-2, 5.0e-2, 5.6e-2}}}},
  }};
  return tables;
}

Experiment simulate(int N, bool uniform_lambda, double delta, std::mt19937_64& rng, bool lagged_coefficients) {
  std::uniform_real_distribution<double> U(-1, 1);
  const int T = N + 2;  // zero initial conditions; regressions t = 3..N+2 (1-based)
  Experiment e;
  Eigen::VectorXd u(T);
  e.lambda.resize(T, 1);
  for (int t = 0; t < T; ++t) u[t] = U(rng);
  for (int t = 0; t < T; ++t) e.lambda(t, 0) = uniform_lambda ? U(rng) : std::sin(0.1 * (t + 1));
  e.w = lagged_coefficients ? simulate_lpv(lagged_structure(), true_theta(), u, lagged(e.lambda.col(0)))
                            : simulate_lpv(structure(), true_theta(), u, e.lambda);
  e.eta.resize(T);
  e.eps.resize(T, 1);
  for (int t = 0; t < T; ++t) e.eta[t] = delta * U(rng);
  for (int t = 0; t < T; ++t) e.eps(t, 0) = delta * U(rng);
  e.data.u = u;
  e.data.y = e.w + e.eta;
  e.data.r = e.lambda + e.eps;
  e.data.delta_eta = Eigen::VectorXd::Constant(1, delta);
  e.data.delta_eps = Eigen::MatrixXd::Constant(1, 1, delta);
  if (lagged_coefficients) {
    e.data.r = lagged(e.data.r.col(0));
    e.data.delta_eps = Eigen::MatrixXd::Constant(1, 2, delta);
  }
  return e;
}

}  // namespace sets::cerone_regruto
