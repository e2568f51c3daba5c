#pragma once
// The example of Cerone & Regruto, Section IV: an LPV system with bounded errors on the output and
// on the scheduling signal, the paper's Tables I-IV, and the simulated experiment behind them
// (used by sets-lpv-pui, its benchmark and its tests).

#include <Eigen/Core>

#include <array>
#include <random>

#include "sets/models/lpv_model.hpp"

namespace sets::cerone_regruto {

/// Section IV's system: a1 = a11 l; a2 = a21 + a22 l^2; b1 = b11; b2 = b21 l + b22 l^2.
LpvModelStructure structure();
/// Its true parameters (0.5, -0.2, 0.3, 0.1, 1.0, 0.2) in the order of structure().
Eigen::VectorXd true_theta();

/// A diagnostic reading of eqs. (2)-(4): coefficient i taken at lambda_{t-i} (the shift acting on
/// the coefficient too) instead of at lambda_t (eq. 13). The same system with alpha = 2 and the
/// scheduling columns [lambda_{t-1}, lambda_{t-2}] (lagged()).
LpvModelStructure lagged_structure();
/// [x_{t-1}, x_{t-2}] (zero before the first sample).
Eigen::MatrixXd lagged(const Eigen::Ref<const Eigen::VectorXd>& x);

/// One noise level of a table as printed: SNRs (dB), theta_c and Delta theta per parameter.
struct PaperLevel {
  double snr_w, snr_lambda;
  double theta_c[6];
  double delta_theta[6];
};

struct PaperTable {
  const char* name;   // "I" .. "IV"
  bool uniform;       // lambda uniform in [-1, 1]; otherwise sin(0.1 t)
  int N;
  double delta_e[4];  // the noise bounds per level (they give the tables' SNRs to ~1 dB)
  PaperLevel paper[4];
};

/// Tables I-IV transcribed from the paper (Table II's stray "0.2" in the true-value column of
/// level 2 is a misprint and not part of theta_c).
const std::array<PaperTable, 4>& paper_tables();

/// The simulated experiment of Section IV.
struct Experiment {
  LpvMeasurements data;       // what the method sees (bounds delta on y and lambda)
  Eigen::VectorXd w, eta;     // noise-free output and its measurement error
  Eigen::MatrixXd lambda, eps;
};

/// N regressions: T = N + 2 samples from zero initial conditions, u uniform in [-1, 1], lambda
/// uniform in [-1, 1] or sin(0.1 t) (t from 1), errors eta on y and eps on lambda uniform in
/// [-delta, delta]; draws every u, then lambda, eta, eps from `rng`. With `lagged_coefficients`
/// the system is lagged_structure() and the scheduling data are lagged.
Experiment simulate(int N, bool uniform_lambda, double delta, std::mt19937_64& rng,
                    bool lagged_coefficients = false);

}  // namespace sets::cerone_regruto
