#include "sets/examples/farah.hpp"

#include <algorithm>
#include <cmath>

namespace sets::farah {

StateSpaceModel system() {
  StateSpaceModel s;
  s.A.resize(3, 3);
  s.A << 0.2, 0, -1, 1, 0.3, 5, -2, -0.4, -0.6;
  s.B.resize(3, 2);
  s.B << 1, 0, 0, 2, 1, -1;
  s.C.resize(2, 3);
  s.C << 5, 0, 1, -3, 1, 1;
  s.D = Eigen::MatrixXd::Zero(2, 2);
  return s;
}

Data simulate(const StateSpaceModel& sys, int samples, double snr_db, std::mt19937_64& rng, Noise noise) {
  std::bernoulli_distribution coin(0.5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const int N = samples;
  const auto nu = sys.B.cols(), ny = sys.C.rows();
  Data d;
  d.u.resize(N, nu);
  for (int t = 0; t < N; ++t)
    for (Eigen::Index m = 0; m < nu; ++m) d.u(t, m) = coin(rng) ? 1.0 : -1.0;
  d.y = sets::simulate(sys, d.u);
  d.sigma.resize(ny);
  d.largest_noise = Eigen::VectorXd::Zero(ny);
  for (Eigen::Index j = 0; j < ny; ++j) {
    const double var = (d.y.col(j).array() - d.y.col(j).mean()).square().mean();
    const double sigma = std::sqrt(var / std::pow(10.0, snr_db / 10.0));
    d.sigma[j] = sigma;
    for (int t = 0; t < N; ++t) {
      const double clean = d.y(t, j);
      d.y(t, j) += noise == Noise::gaussian ? sigma * gauss(rng) : std::sqrt(3.0) * sigma * uniform(rng);
      d.largest_noise[j] = std::max(d.largest_noise[j], std::abs(d.y(t, j) - clean));
    }
  }
  return d;
}

}  // namespace sets::farah
