#include "sets/diagnosis/residual_tests.hpp"

#include <boost/math/distributions/normal.hpp>
#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>

#include "sets/data/bursts.hpp"
#include "sets/fps/feasible_parameter_set.hpp"

namespace sets {

double noise_bound_factor(Eigen::Index samples) {
  return 1.2 * std::sqrt(2 * std::log(2.0 * static_cast<double>(std::max<Eigen::Index>(samples, 2))));
}

std::string ResidualTests::summary() const {
  std::ostringstream o;
  o.precision(3);
  o << (falsified ? "the linearised output error is falsified under |e| <= " : "the linearised output error is consistent with |e| <= ");
  for (std::size_t j = 0; j < bound.size(); ++j) o << (j ? ", " : "") << bound[j];
  const bool whitened = any_whitened();
  o << "; residual " << (whitened ? "whitened by its noise's AR(1) pole (" : "");
  for (std::size_t j = 0; whitened && j < whitened_by.size(); ++j) o << (j ? ", " : "a = ") << whitened_by[j];
  o << (whitened ? ") " : "") << (white ? "white" : "not white") << " (autocorrelation " << worst_autocorrelation_z
    << " standard deviations at lag " << worst_lag << ", threshold " << white_threshold << ")";
  o << "; " << (bursty ? "bursts" : "no bursts") << " in the residual's fast part (RMS / clipped RMS of its differences " << worst_burst_ratio
    << (bound.size() > 1 ? " on output " + std::to_string(worst_burst_output + 1) : std::string()) << ", limit " << kBurstRatioLimit << ")";
  o << "; largest correlation with the model's signals " << worst_z << " standard deviations (threshold " << z_threshold << ", decisive beyond "
    << kIndependenceMargin * z_threshold << ")";
  if (!worst_signal.empty()) o << ", " << worst_signal;
  return o.str();
}

namespace {

// Autocorrelation (biased, normalised to 1 at lag 0) up to lag K, by FFT.
Eigen::VectorXd autocorrelation(const Eigen::VectorXd& x, Eigen::Index K) {
  const Eigen::Index N = x.size();
  Eigen::Index M = 1;
  while (M < 2 * N) M *= 2;
  std::vector<double> buf(static_cast<std::size_t>(M), 0.0);
  for (Eigen::Index t = 0; t < N; ++t) buf[static_cast<std::size_t>(t)] = x[t];
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spec;
  fft.fwd(spec, buf);
  for (auto& c : spec) c = std::norm(c);
  std::vector<double> ac;
  fft.inv(ac, spec);
  Eigen::VectorXd r(K + 1);
  const double r0 = ac[0] > 0 ? ac[0] : 1.0;
  for (Eigen::Index k = 0; k <= K; ++k) r[k] = ac[static_cast<std::size_t>(k)] / r0;
  return r;
}

Eigen::VectorXd centred(const Eigen::VectorXd& x) { return (x.array() - x.mean()).matrix(); }

// r_t - a r_{t-1}, t = 1 .. N-1: white when r is AR(1) noise of pole a (r itself when a = 0).
Eigen::VectorXd whitened(const Eigen::VectorXd& r, double a) {
  if (a == 0 || r.size() < 2) return r;
  return r.tail(r.size() - 1) - a * r.head(r.size() - 1);
}

}  // namespace

ResidualTests test_residual(const Simulator& sim, const Eigen::Ref<const Eigen::VectorXd>& p, const SimulationResult& at, const std::vector<double>& sigma,
                            const std::vector<double>& noise_pole) {
  ResidualTests t;
  const Eigen::MatrixXd& Y = sim.measured();
  const Eigen::Index N = Y.rows(), ny = Y.cols();
  const Eigen::MatrixXd R = Y - at.outputs;
  const double c = noise_bound_factor(N);
  for (Eigen::Index j = 0; j < ny; ++j) t.bound.push_back(c * sigma[static_cast<std::size_t>(j)]);
  // Falsification of the linearised output error (decimated to <= 1500 samples per output).
  {
    const std::vector<int> free = sim.free_parameters();
    const Eigen::Index stride = std::max<Eigen::Index>(1, N / 1500), m = (N + stride - 1) / stride;
    Eigen::MatrixXd J(N * ny, static_cast<Eigen::Index>(free.size()));
    Eigen::MatrixXd y1;
    bool ok = true;
    for (std::size_t k = 0; k < free.size() && ok; ++k) {
      Eigen::VectorXd q = p;
      const double h = 1e-5 * (std::abs(p[free[k]]) > 0 ? std::abs(p[free[k]]) : 1.0);
      q[free[k]] += h;
      ok = sim.simulate_outputs(q, y1) && y1.allFinite();
      for (Eigen::Index j = 0; ok && j < ny; ++j) J.col(static_cast<Eigen::Index>(k)).segment(j * N, N) = (y1.col(j) - at.outputs.col(j)) / h;
    }
    Eigen::MatrixXd Phi(m * ny, J.cols());
    Eigen::VectorXd yy(m * ny), dd = Eigen::VectorXd::Ones(m * ny);
    for (Eigen::Index j = 0; j < ny; ++j)
      for (Eigen::Index i = 0; i < m; ++i) {
        const double b = std::max(t.bound[static_cast<std::size_t>(j)], 1e-300);
        Phi.row(j * m + i) = ok ? Eigen::RowVectorXd(J.row(j * N + i * stride) / b) : Eigen::RowVectorXd::Zero(J.cols());
        yy[j * m + i] = R(i * stride, j) / b;
      }
    for (Eigen::Index col = 0; col < Phi.cols(); ++col)
      if (Phi.col(col).norm() > 0) Phi.col(col) /= Phi.col(col).norm();
    if (Phi.cols() == 0) t.falsified = yy.cwiseAbs().maxCoeff() > 1;
    else t.falsified = !find_conflict(FeasibleParameterSet::from_data(Phi, yy, dd)).samples.empty();
  }
  // Independence of the residual from the model's signals.
  std::vector<std::pair<std::string, Eigen::VectorXd>> signals;
  for (std::size_t v = 0; v < at.names.size(); ++v) {
    const Eigen::VectorXd x = at.values.col(static_cast<Eigen::Index>(v));
    if (!(x.maxCoeff() - x.minCoeff() > 1e-12 * std::max(1.0, x.cwiseAbs().maxCoeff()))) continue;
    signals.emplace_back(at.names[v], centred(x));
    signals.emplace_back("|" + at.names[v] + "|", centred(x.cwiseAbs()));
  }
  std::vector<Eigen::Index> lags{0};
  for (Eigen::Index l = 1; l <= std::max<Eigen::Index>(1, N / 20); l *= 2) lags.push_back(l), lags.push_back(-l);
  const Eigen::Index K = std::max<Eigen::Index>(1, N / 4);
  // Whiteness: rho_rr(k) sqrt(N) at lags 1, 2, 4, ... N/20.
  {
    std::vector<Eigen::Index> pos;
    for (Eigen::Index l = 1; l <= std::max<Eigen::Index>(1, N / 20); l *= 2) pos.push_back(l);
    t.white_threshold = boost::math::quantile(
        boost::math::complement(boost::math::normal(), 0.01 / (2.0 * static_cast<double>(pos.size() * static_cast<std::size_t>(ny)))));
    for (Eigen::Index j = 0; j < ny; ++j) {
      const double a = static_cast<std::size_t>(j) < noise_pole.size() ? noise_pole[static_cast<std::size_t>(j)] : 0.0;
      t.whitened_by.push_back(a);
      const Eigen::VectorXd r = centred(whitened(R.col(j), a));
      if (!(r.norm() > 0)) continue;
      const Eigen::VectorXd rr = autocorrelation(r, std::min(K, pos.back()));
      for (Eigen::Index l : pos) {
        const double z = std::abs(rr[l]) * std::sqrt(static_cast<double>(r.size()));
        if (z > t.worst_autocorrelation_z) t.worst_autocorrelation_z = z, t.worst_lag = static_cast<int>(l);
      }
    }
    t.white = t.worst_autocorrelation_z <= t.white_threshold;
  }
  for (Eigen::Index j = 0; j < ny; ++j) {
    const double b = burst_ratio(R.col(j));
    if (b > t.worst_burst_ratio) t.worst_burst_ratio = b, t.worst_burst_output = static_cast<int>(j);
  }
  t.bursty = t.worst_burst_ratio > kBurstRatioLimit;
  const double tests = static_cast<double>(std::max<std::size_t>(1, signals.size() * lags.size() * static_cast<std::size_t>(ny)));
  t.z_threshold = boost::math::quantile(boost::math::complement(boost::math::normal(), 0.01 / (2 * tests)));
  for (Eigen::Index j = 0; j < ny; ++j) {
    const Eigen::VectorXd r = centred(R.col(j));
    const double rn = r.norm();
    if (!(rn > 0)) continue;
    const Eigen::VectorXd rr = autocorrelation(r, K);
    for (const auto& [name, s] : signals) {
      const double sn = s.norm();
      if (!(sn > 0)) continue;
      const Eigen::VectorXd ss = autocorrelation(s, K);
      // Bartlett: var(rho_rs) = (1/N) sum_k rho_rr(k) rho_ss(k), tapered over |k| <= K.
      double sum = 1;
      for (Eigen::Index k = 1; k <= K; ++k) sum += 2 * (1 - static_cast<double>(k) / static_cast<double>(K + 1)) * rr[k] * ss[k];
      const double sd = std::sqrt(std::max(sum, 1.0) / static_cast<double>(N));
      for (Eigen::Index lag : lags) {
        double acc = 0;
        for (Eigen::Index i = std::max<Eigen::Index>(0, lag); i < std::min(N, N + lag); ++i) acc += r[i] * s[i - lag];
        const double z = std::abs(acc / (rn * sn)) / sd;
        if (z > t.worst_z) {
          t.worst_z = z;
          t.worst_signal = name + " at lag " + std::to_string(lag) + (ny > 1 ? " (output " + std::to_string(j + 1) + ")" : "");
        }
      }
    }
  }
  t.independent = t.worst_z <= t.z_threshold;
  return t;
}

}  // namespace sets
