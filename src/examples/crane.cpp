#include "sets/examples/crane.hpp"

#include <cmath>
#include <iterator>
#include <numbers>
#include <random>
#include <sstream>

#include "sets/core/error.hpp"

namespace sets::crane {

Eigen::MatrixXd input(const std::string& kind, int N, unsigned seed) {
  Eigen::MatrixXd u(N, 1);
  if (kind == "square") {
    for (int k = 0; k < N; ++k) u(k, 0) = (static_cast<int>(k * kStep / 2.0) % 2 == 0) ? 1.0 : -1.0;
  } else if (kind == "prbs") {
    const int hold = static_cast<int>(std::lround(kPrbsHold / kStep));
    std::mt19937_64 rng(seed);
    std::bernoulli_distribution flip(0.5);
    double level = 1.0;
    for (int k = 0; k < N; ++k) {
      if (k > 0 && k % hold == 0 && flip(rng)) level = -level;
      u(k, 0) = level;
    }
  } else if (kind == "multisine") {
    const int m = static_cast<int>(std::size(kMultisineFreq));
    const double pi = 3.141592653589793;
    for (int k = 0; k < N; ++k) {
      double v = 0;
      for (int i = 0; i < m; ++i)  // Schroeder phase phi_i = -pi i (i + 1) / m
        v += std::sin(kMultisineFreq[i] * k * kStep - pi * i * (i + 1) / m);
      u(k, 0) = v;
    }
    const double peak = u.cwiseAbs().maxCoeff();
    if (peak > 0) u /= peak;
  } else {
    throw InputError("crane input '" + kind + "': expected square, prbs or multisine");
  }
  return u;
}

Eigen::MatrixXd perturbation(const Case& c, int N) {
  Eigen::MatrixXd pi(N, 3);
  const double two_pi = 6.283185307179586;
  for (int k = 0; k < N; ++k) {
    const double s = static_cast<double>(k) / N;
    if (c.sine) {
      pi(k, 0) = std::sin(two_pi * s);
      pi(k, 1) = std::sin(two_pi * 1.5 * s);
      pi(k, 2) = std::sin(two_pi * 2.0 * s);
    } else {
      pi(k, 0) = s < 0.2 ? 0.0 : (s < 0.6 ? 1.0 : 0.5);
      pi(k, 1) = s < 0.3 ? 0.0 : (s < 0.7 ? 1.0 : 0.4);
      pi(k, 2) = s < 0.1 ? 0.0 : (s < 0.45 ? 0.5 : (s < 0.8 ? 1.0 : 0.0));
    }
  }
  return pi * c.amplitude.asDiagonal();
}

std::vector<Case> cases(const std::string& which) {
  std::vector<Case> out;
  auto want = [&](const char* t) { return which == "all" || which == t; };
  if (want("I")) {
    const Eigen::Vector3d amps[] = {{0.2, 1.0, 0.5}, {0.4, 1.0, 0.5}, {0.2, 2.0, 0.5}, {0.2, 1.0, 1.0}};
    for (const auto& a : amps) {
      Case c;
      c.table = "I";
      c.amplitude = a;
      std::ostringstream s;
      s << "A = [" << a[0] << ", " << a[1] << ", " << a[2] << "]";
      c.label = s.str();
      out.push_back(c);
    }
    Case c;
    c.table = "I";
    c.sine = true;
    c.label = "sinusoid (Fig. 7), A = [0.2, 1, 0.5]";
    out.push_back(c);
  }
  if (want("II")) {
    const double nominal[][3] = {{3.0, 0.25, 2.0}, {3.7, 0.25, 2.0}, {3.3, 0.20, 2.0},
                                 {3.3, 0.15, 2.0}, {3.3, 0.25, 1.5}, {3.3, 0.25, 2.5}};
    for (const auto& n : nominal) {
      Case c;
      c.table = "II";
      c.lambda0 = n[0];
      c.kappa0 = n[1];
      c.b0 = n[2];
      std::ostringstream s;
      s << "[l0,k0,b0] = [" << n[0] << ", " << n[1] << ", " << n[2] << "]";
      c.label = s.str();
      out.push_back(c);
    }
  }
  if (want("III")) {
    for (double e : {0.05, 0.10, 0.20, 0.30}) {
      Case c;
      c.table = "III";
      c.noise = e;
      std::ostringstream s;
      s << "eps = " << e;
      c.label = s.str();
      out.push_back(c);
    }
  }
  return out;
}

WindowNorm window() { return WindowNorm::pulse(36, 1.0 / 35); }

Eigen::VectorXd noise(int N, double level, const WindowNorm& w, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0, 1);
  Eigen::VectorXd eta(N + 1);
  for (int k = 0; k <= N; ++k) eta[k] = normal(rng);
  eta *= level / w(eta);
  return eta;
}

}  // namespace sets::crane
