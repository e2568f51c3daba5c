// Stage 2 of the diagnosis: where the calibrated nominal model fails (time windows, operating
// regions, frequency band) and which parameter would have to vary (varying_parameters.cpp).

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>

#include "diagnosis/stages.hpp"
#include "sets/core/error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"

namespace sets::diagnosis_stage {

namespace {

// Windows: moving RMS of the residual above the bound; falsified when no parameter change of the
// linearised nominal model keeps every residual inside the bound (FPS of strips). J: the output
// Jacobian at the calibrated parameters.
std::vector<MismatchWindow> mismatch_windows(const Simulator& exact, const Eigen::MatrixXd& R, const Eigen::MatrixXd& J,
                                             const std::vector<double>& norm, const Diagnosis& d) {
  std::vector<MismatchWindow> out;
  const Eigen::Index N = R.rows(), ny = R.cols();
  const Eigen::Index w = std::max<Eigen::Index>(5, N / 200);
  for (Eigen::Index j = 0; j < ny; ++j) {
    const double bound = std::max(d.error_bound[static_cast<std::size_t>(j)], 1e-12 * norm[static_cast<std::size_t>(j)]);
    // Where the residual exceeds the bound everywhere, show where it is largest (1.5 x its RMS).
    const double level = std::max(bound, 1.5 * std::sqrt(R.col(j).squaredNorm() / static_cast<double>(N)));
    std::vector<char> hot(static_cast<std::size_t>(N), 0);
    double acc = 0;
    for (Eigen::Index k = 0; k < N; ++k) {
      acc += R(k, j) * R(k, j);
      if (k >= w) acc -= R(k - w, j) * R(k - w, j);
      const double r = std::sqrt(std::max(acc, 0.0) / static_cast<double>(std::min(k + 1, w)));
      if (r > level) for (Eigen::Index i = std::max<Eigen::Index>(0, k - w + 1); i <= k; ++i) hot[static_cast<std::size_t>(i)] = 1;
    }
    std::vector<MismatchWindow> ws;
    for (Eigen::Index k = 0; k < N;) {
      if (!hot[static_cast<std::size_t>(k)]) { ++k; continue; }
      Eigen::Index e = k;
      while (e + 1 < N && (hot[static_cast<std::size_t>(e + 1)] || (e + w < N && hot[static_cast<std::size_t>(e + w)]))) ++e;
      MismatchWindow mw;
      mw.output = d.outputs[static_cast<std::size_t>(j)];
      mw.start = exact.time()[static_cast<std::size_t>(k)];
      mw.end = exact.time()[static_cast<std::size_t>(e)];
      mw.rms = std::sqrt(R.col(j).segment(k, e - k + 1).squaredNorm() / static_cast<double>(e - k + 1));
      // Set-membership falsification inside the window (decimated to <= 300 samples).
      const Eigen::Index len = e - k + 1, stride = std::max<Eigen::Index>(1, len / 300);
      const Eigen::Index m = (len + stride - 1) / stride;
      Eigen::MatrixXd Phi(m, J.cols());
      Eigen::VectorXd yy(m), dd(m);
      for (Eigen::Index i = 0; i < m; ++i) {
        const Eigen::Index t = k + i * stride;
        Phi.row(i) = J.row(j * N + t);
        yy[i] = R(t, j);
        dd[i] = bound;
      }
      if (J.cols() == 0) {
        mw.falsified = yy.cwiseAbs().maxCoeff() > bound;
      } else if (m < J.cols()) {
        // Fewer strips than parameters (a window of a sample or two at the record's start, where
        // the moving RMS has seen only those): no FPS to test; "falsified" is only ever claimed
        // when certified, so the window is reported as not falsified (held-out 5 001 816 threw).
        mw.falsified = false;
      } else {
        auto fps = FeasibleParameterSet::from_data(Phi, yy, dd);
        mw.falsified = check_consistency(fps).certified_falsified();  // certified only
      }
      ws.push_back(mw);
      k = e + 1;
    }
    std::sort(ws.begin(), ws.end(), [](const auto& a, const auto& b) { return a.rms * (a.end - a.start + 1e-9) > b.rms * (b.end - b.start + 1e-9); });
    if (ws.size() > 8) ws.resize(8);
    std::sort(ws.begin(), ws.end(), [](const auto& a, const auto& b) { return a.start < b.start; });
    for (auto& x : ws) out.push_back(x);
  }
  return out;
}

// Operating regions where the residual concentrates (energy: the squared normalised residual per
// sample); also chooses the signature plot's variable.
void operating_regions(const SimulationResult& nominal_sim, const Eigen::VectorXd& energy, Diagnosis& d) {
  const Eigen::Index N = energy.size();
  const double total_energy = std::max(energy.sum(), 1e-300);
  const ModelStructure st = analyse_structure(d.nominal);
  std::vector<MismatchRegion> regs;
  double best_conc = 0;
  auto region = [&](const std::string& var, const std::string& desc, const std::vector<char>& in) {
    double e = 0;
    Eigen::Index n = 0;
    for (Eigen::Index k = 0; k < N; ++k)
      if (in[static_cast<std::size_t>(k)]) e += energy[k], ++n;
    const double share = static_cast<double>(n) / static_cast<double>(N);
    if (share < 0.01 || share > 0.6) return;
    MismatchRegion r{var, desc, e / total_energy, share};
    if (r.residual_share / r.sample_share >= 1.5) regs.push_back(r);
    if (r.residual_share / r.sample_share > best_conc) {
      best_conc = r.residual_share / r.sample_share;
      d.signature_variable = var;
    }
  };
  for (std::size_t v = 0; v < nominal_sim.names.size(); ++v) {
    const std::string& name = nominal_sim.names[v];
    const Eigen::VectorXd x = nominal_sim.values.col(static_cast<Eigen::Index>(v));
    const double mx = x.cwiseAbs().maxCoeff(), lo = x.minCoeff(), hi = x.maxCoeff(), range = hi - lo;
    if (!(range > 1e-12 * std::max(1.0, mx))) continue;
    std::vector<char> in(static_cast<std::size_t>(N));
    if (lo < 0.05 * mx) {
      for (Eigen::Index k = 0; k < N; ++k) in[static_cast<std::size_t>(k)] = std::abs(x[k]) < 0.05 * mx;
      region(name, "near zero " + name, in);
    }
    for (Eigen::Index k = 0; k < N; ++k) in[static_cast<std::size_t>(k)] = std::abs(x[k]) > 0.8 * mx;
    region(name, "at large |" + name + "|", in);
    for (Eigen::Index k = 0; k < N; ++k) in[static_cast<std::size_t>(k)] = x[k] > hi - 0.05 * range;
    region(name, "near the upper level/limit of " + name, in);
    for (Eigen::Index k = 0; k < N; ++k) in[static_cast<std::size_t>(k)] = x[k] < lo + 0.05 * range;
    region(name, "near the lower level/limit of " + name, in);
    bool is_state = false;
    for (const auto& s : d.nominal.states) is_state = is_state || s.name == name;
    if (is_state) {
      // Reversals: sign changes of the rate, with a margin of N/500 samples.
      std::fill(in.begin(), in.end(), 0);
      const Eigen::Index margin = std::max<Eigen::Index>(2, N / 500);
      int last = 0;
      for (Eigen::Index k = 1; k < N; ++k) {
        const double dx = x[k] - x[k - 1];
        const int sg = std::abs(dx) <= 1e-12 * range ? 0 : (dx > 0 ? 1 : -1);
        if (sg != 0 && last != 0 && sg != last)
          for (Eigen::Index i = std::max<Eigen::Index>(0, k - margin); i < std::min(N, k + margin); ++i) in[static_cast<std::size_t>(i)] = 1;
        if (sg != 0) last = sg;
      }
      region(name, "at reversals of " + name, in);
    }
  }
  std::sort(regs.begin(), regs.end(), [](const auto& a, const auto& b) {
    return a.residual_share / a.sample_share > b.residual_share / b.sample_share;
  });
  if (regs.size() > 6) regs.resize(6);
  d.regions = regs;
  // Prefer the velocity of a mechanical pair for the signature plot when one exists.
  if (!st.mechanical.empty()) d.signature_variable = st.mechanical.front().second;
  if (d.signature_variable.empty() && !nominal_sim.names.empty()) d.signature_variable = nominal_sim.names.front();
  d.signature_x = nominal_sim.series(d.signature_variable);
}

// Frequency band of the residual r of the worst output.
void frequency_band(const Eigen::VectorXd& R_main, double Ts, const std::string& output, Diagnosis& d) {
  const Eigen::Index M = R_main.size();
  std::vector<double> r(static_cast<std::size_t>(M));
  for (Eigen::Index k = 0; k < M; ++k) r[static_cast<std::size_t>(k)] = R_main[k] - R_main.mean();
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spec;
  fft.fwd(spec, r);
  std::vector<double> p(static_cast<std::size_t>(M / 2));
  for (std::size_t k = 1; k < p.size(); ++k) p[k] = std::norm(spec[k]);
  const double tot = std::accumulate(p.begin(), p.end(), 0.0);
  FrequencyBand b;
  b.output = output;
  double c = 0;
  std::size_t peak = 1;
  bool lo_set = false;
  for (std::size_t k = 1; k < p.size(); ++k) {
    c += p[k];
    const double f = static_cast<double>(k) / (static_cast<double>(M) * Ts);
    if (!lo_set && c >= 0.1 * tot) b.lo_hz = f, lo_set = true;
    if (c <= 0.9 * tot) b.hi_hz = f;
    if (p[k] > p[peak]) peak = k;
  }
  if (b.hi_hz < b.lo_hz) b.hi_hz = b.lo_hz;
  b.peak_hz = static_cast<double>(peak) / (static_cast<double>(M) * Ts);
  if (tot > 0) d.bands.push_back(b);
}

}  // namespace

std::vector<double> output_norms(const Eigen::MatrixXd& Y) {
  std::vector<double> norm(static_cast<std::size_t>(Y.cols()));
  for (Eigen::Index j = 0; j < Y.cols(); ++j) {
    const double den = (Y.col(j).array() - Y.col(j).mean()).matrix().norm();
    norm[static_cast<std::size_t>(j)] = den > 0 ? den : 1.0;
  }
  return norm;
}

void locate_mismatch(const Context& c, const NominalFit& nominal, const NoiseFloor& noise, Diagnosis& d) {
  c.say("locating the mismatch (windows, regions, frequency band, varying parameters)");
  const Eigen::MatrixXd& Y = c.exact.measured();
  const Eigen::Index N = Y.rows(), ny = Y.cols();
  const Eigen::MatrixXd R = Y - nominal.simulation.outputs;
  const std::vector<double> norm = output_norms(Y);
  Eigen::Index main = 0;
  for (Eigen::Index j = 1; j < ny; ++j)
    if (d.fit_nominal_estimation[static_cast<std::size_t>(j)] < d.fit_nominal_estimation[static_cast<std::size_t>(main)]) main = j;
  Eigen::VectorXd energy = Eigen::VectorXd::Zero(N);
  for (Eigen::Index j = 0; j < ny; ++j) energy += (R.col(j) / norm[static_cast<std::size_t>(j)]).cwiseAbs2();
  for (Eigen::Index j = 0; j < ny; ++j) d.error_bound.push_back(3 * noise.sigma[static_cast<std::size_t>(j)]);
  d.bound_note = "error bound per output = 3 x the estimated noise sigma (";
  for (std::size_t j = 0; j < d.noise.size(); ++j)
    d.bound_note += (j ? "; " : "") + d.noise[j].output + ": " + noise_method_name(d.noise[j].estimate.method) + " on the " +
                    d.noise[j].record + " record";
  d.bound_note += ")";
  const std::vector<double> sc = scales_for(d.nominal, nominal.free, {});
  Eigen::MatrixXd J;
  try {
    J = nominal.free.empty() ? Eigen::MatrixXd(N * ny, 0)
                             : output_jacobian(c.exact, nominal.calibration.parameters, nominal.free, sc, nominal.simulation.outputs);
  } catch (const NumericalError&) {
    J = Eigen::MatrixXd::Zero(N * ny, static_cast<Eigen::Index>(nominal.free.size()));
  }
  d.windows = mismatch_windows(c.exact, R, J, norm, d);
  // Which parameter would have to vary over time, and when (Salehpour–Johansson, issue 7).
  c.say("time-varying parameter estimates (linf_bound, sparse_bound)");
  d.varying = varying_parameters(d.nominal, c.estimation, c.options.screening_substeps, nominal.calibration.parameters,
                                 nominal.free, sc, R, c.exact.time(), c.options.varying_segments, c.options.threads);
  operating_regions(nominal.simulation, energy, d);
  d.signature_residual = R.col(main);
  d.signature_output = d.outputs[static_cast<std::size_t>(main)];
  frequency_band(R.col(main), c.exact.sample_time(), d.outputs[static_cast<std::size_t>(main)], d);
}

}  // namespace sets::diagnosis_stage
