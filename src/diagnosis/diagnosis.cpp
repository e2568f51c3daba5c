#include "sets/diagnosis/diagnosis.hpp"

#include <Eigen/QR>
#include <unsupported/Eigen/FFT>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <complex>
#include <iomanip>
#include <map>
#include <mutex>
#include <numeric>
#include <sstream>
#include <thread>

#include "sets/diagnosis/calibration.hpp"
#include "sets/diagnosis/equation_error.hpp"
#include "sets/core/error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/interval.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/diagnosis/physics_catalogue.hpp"
#include "sets/data/simulation.hpp"
#include "sets/methods/tv_bound/tv_bound.hpp"
#include "sets/methods/tv_bound/window_norm.hpp"

namespace sets {

namespace {

double cost_of(const std::vector<double>& fit) {
  double c = 0;
  for (double f : fit) c += (1 - f / 100) * (1 - f / 100);
  return c;
}

Eigen::VectorXd values_of(const ModelFile& m) {
  Eigen::VectorXd p(static_cast<Eigen::Index>(m.parameters.size()));
  for (std::size_t i = 0; i < m.parameters.size(); ++i) p[static_cast<Eigen::Index>(i)] = m.parameters[i].value;
  return p;
}

void store_values(ModelFile& m, const Eigen::VectorXd& p) {
  for (std::size_t i = 0; i < m.parameters.size(); ++i) m.parameters[i].value = p[static_cast<Eigen::Index>(i)];
}

std::vector<double> scales_for(const ModelFile& m, const std::vector<int>& free,
                               const std::vector<std::pair<std::string, double>>& known) {
  std::vector<double> s;
  for (int i : free) {
    const auto& p = m.parameters[static_cast<std::size_t>(i)];
    double v = std::abs(p.value);
    for (const auto& [n, sc] : known)
      if (n == p.name) v = sc;
    s.push_back(v > 0 ? v : 1.0);
  }
  return s;
}

struct Trial {
  Candidate cand;
  ModelFile model;  // calibrated
  double cost = 1e300, cost_val = 1e300;
  ModelFile neutral_model;           // the calibrated model with the effect switched off
  double cost_neutral = 1e300, cost_neutral_val = 1e300;
  std::vector<double> fit, fit_val;
  bool ok = false;
};

// Jacobian of the outputs (output units) with respect to the free parameters, forward differences.
Eigen::MatrixXd output_jacobian(const Simulator& sim, const Eigen::VectorXd& p, const std::vector<int>& free,
                                const std::vector<double>& scale, const Eigen::MatrixXd& y0) {
  const Eigen::Index N = y0.rows(), ny = y0.cols();
  Eigen::MatrixXd J(N * ny, static_cast<Eigen::Index>(free.size()));
  for (std::size_t i = 0; i < free.size(); ++i) {
    Eigen::VectorXd q = p;
    const double h = 1e-4 * scale[i];
    q[free[i]] += h;
    Eigen::MatrixXd y1;
    if (!sim.simulate_outputs(q, y1)) {
      q[free[i]] = p[free[i]] - h;
      if (!sim.simulate_outputs(q, y1)) throw NumericalError("sensitivity simulation blew up");
      y1 = 2 * y0 - y1;
    }
    for (Eigen::Index j = 0; j < ny; ++j) J.col(static_cast<Eigen::Index>(i)).segment(j * N, N) = (y1.col(j) - y0.col(j)) / h;
  }
  return J;
}

std::string fmt(double x, int prec = 3) {
  std::ostringstream os;
  os << std::setprecision(prec) << x;
  return os.str();
}
std::string fixed1(double x) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << x;
  return os.str();
}


// Which parameter would have to vary over time, and when: the Salehpour–Johansson estimates of
// sets/tv_bound.hpp on the calibrated model. Each free parameter is perturbed piecewise constant
// over S segments; the sensitivity of the outputs to each segment's perturbation comes from
// finite differences of the simulation (S x q runs). The biaffine regression is indexed by
// segment: its "sample" k + 1 stacks m residual samples per output taken inside segment k (sample
// 0 is an empty block: the model is nominal before the record), its columns are the segments,
// so Xi is block lower triangular as in (4). The residual ball is the window norm with the
// one-sample window: |residual| <= eps per (output, sub-sample) over all segments.
std::vector<VaryingParameter> varying_parameters(const ModelFile& model, const Recording& est, int substeps,
                                                 const Eigen::VectorXd& p, const std::vector<int>& free,
                                                 const std::vector<double>& scale, const Eigen::MatrixXd& R,
                                                 const std::vector<double>& time, int segments, int threads) {
  std::vector<VaryingParameter> out;
  const Eigen::Index N = R.rows(), ny = R.cols();
  const int q = static_cast<int>(free.size());
  const int S = segments > 0 ? segments : static_cast<int>(std::clamp<Eigen::Index>(N / 500, 10, 30));
  if (q == 0 || N < 4 * S) return out;
  std::vector<Eigen::Index> a(static_cast<std::size_t>(S + 1));
  for (int s = 0; s <= S; ++s) a[static_cast<std::size_t>(s)] = N * s / S;
  Eigen::Index shortest = N;
  for (int s = 0; s < S; ++s) shortest = std::min(shortest, a[static_cast<std::size_t>(s + 1)] - a[static_cast<std::size_t>(s)]);
  const Eigen::Index m = std::min<Eigen::Index>(shortest, 25);
  // Feature j of segment s: the mean over the j-th of m equal parts of the segment (averaging
  // keeps isolated spikes and noise from setting the l-inf fit).
  auto part = [&](int s, Eigen::Index j) {
    const Eigen::Index lo = a[static_cast<std::size_t>(s)], len = a[static_cast<std::size_t>(s + 1)] - lo;
    return std::pair<Eigen::Index, Eigen::Index>(lo + len * j / m, lo + len * (j + 1) / m);
  };
  auto mean_over = [&](const Eigen::MatrixXd& x, Eigen::Index o, int s, Eigen::Index j) {
    const auto [b0, b1] = part(s, j);
    return x.col(o).segment(b0, b1 - b0).mean();
  };
  const Eigen::Index l = ny * m;  // "outputs" of the regression: (output, sub-sample) pairs
  Eigen::VectorXd sigma(ny);
  for (Eigen::Index o = 0; o < ny; ++o) {
    const double rms = std::sqrt(R.col(o).squaredNorm() / static_cast<double>(N));
    sigma[o] = rms > 0 ? rms : 1.0;
  }
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(S + 1, l);
  for (int s = 0; s < S; ++s)
    for (Eigen::Index o = 0; o < ny; ++o)
      for (Eigen::Index j = 0; j < m; ++j) Y(s + 1, o * m + j) = mean_over(R, o, s, j) / sigma[o];

  // Sensitivities: column (i, s) holds d(features)/d(pi_i over segment s), pi in units of scale_i.
  std::vector<Eigen::MatrixXd> xi(static_cast<std::size_t>(q), Eigen::MatrixXd::Zero((S + 1) * l, S));
  Eigen::MatrixXd y0;
  {
    Simulator sim(model, est, {substeps});
    if (!sim.simulate_outputs(p, y0)) return out;
  }
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  auto worker = [&] {
    Simulator sim(model, est, {substeps});
    Eigen::MatrixXd sched(N, p.size()), y1;
    for (int job; (job = next++) < q * S;) {
      const int i = job / S, s = job % S;
      const double h = 1e-2 * scale[static_cast<std::size_t>(i)];
      sched = p.transpose().replicate(N, 1);
      sched.col(free[static_cast<std::size_t>(i)]).segment(a[static_cast<std::size_t>(s)],
                                                           a[static_cast<std::size_t>(s + 1)] - a[static_cast<std::size_t>(s)])
          .array() += h;
      if (!sim.simulate_outputs_scheduled(sched, y1)) {
        failed = true;
        continue;
      }
      y1 -= y0;
      for (int k = s; k < S; ++k)  // causal: segment s acts on segments s, s + 1, ...
        for (Eigen::Index o = 0; o < ny; ++o)
          for (Eigen::Index j = 0; j < m; ++j)
            xi[static_cast<std::size_t>(i)]((k + 1) * l + o * m + j, s) =
                mean_over(y1, o, k, j) / h * scale[static_cast<std::size_t>(i)] / sigma[o];
    }
  };
  {
    std::vector<std::thread> pool;
    for (int k = 0; k < std::max(1, threads); ++k) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
  }
  if (failed) return out;

  const Eigen::VectorXd offset = stack_samples(Y);
  const double total = std::max(offset.squaredNorm(), 1e-300);
  // eps weights: the fit dominates the objective (10 x the perturbation terms when nothing is
  // explained), so the estimate is the smallest perturbation that fits about as well as any can.
  Eigen::VectorXd h(l);
  for (Eigen::Index o = 0; o < ny; ++o) {
    const double peak = std::max(Y.middleCols(o * m, m).cwiseAbs().maxCoeff(), 1e-12);
    h.segment(o * m, m).setConstant(10.0 / (static_cast<double>(l) * peak));
  }
  const double eps0 = std::max(h.dot(Y.cwiseAbs().colwise().maxCoeff().transpose()), 1e-300);
  for (int i = 0; i < q; ++i) {
    const double sc = scale[static_cast<std::size_t>(i)];
    TvBoundData data;
    data.regression.zeta = Eigen::MatrixXd::Zero(S + 1, 1);
    data.regression.upsilon = Eigen::VectorXd::Zero((S + 1) * l);
    data.regression.xi = xi[static_cast<std::size_t>(i)];
    data.y = Y;
    data.windows = {WindowNorm::pulse(1, 1.0)};
    LinfBoundOptions lo;
    lo.h = h;
    lo.initial_difference = false;  // the calibrated value may be off from the start
    TvBoundResult lin;
    try {
      lin = linf_bound(data, lo);
    } catch (const std::exception&) {
      continue;  // an estimate that cannot be computed is not reported
    }
    VaryingParameter vp;
    vp.name = model.parameters[static_cast<std::size_t>(free[static_cast<std::size_t>(i)])].name;
    vp.value = p[free[static_cast<std::size_t>(i)]];
    vp.bound = sc * lin.bound[0];
    Eigen::VectorXd pi = lin.pi.col(0);
    vp.method = "linf_bound";
    const double mu = std::max(0.1 * lin.bound[0], 1e-9);
    if (lin.bound[0] > 0) {
      // The sparse "when": fewest jumps above 10 % of the l-inf peak that keep the residual inside
      // the l-inf eps widened by 10 %, warm-started from the l-inf trajectory.
      SparseBoundOptions so;
      so.mu = Eigen::VectorXd::Constant(1, mu);
      so.max_abs = Eigen::VectorXd::Constant(1, 2 * lin.bound[0] + mu);
      so.epsilon = lin.epsilon * 1.1 + Eigen::VectorXd::Constant(l, 1e-9);
      so.initial_difference = false;
      // A node limit, not a short time limit, so the answer does not depend on the machine's load;
      // the 10 s is only a guard.
      so.milp = MilpOptions{10.0, 1e-4, false, 3000};
      so.start = lin.pi;
      try {
        const TvBoundResult sp = sparse_bound(data, so);
        pi = sp.pi.col(0);
        vp.method = "sparse_bound";
      } catch (const std::exception&) {
      }
    }
    // Explained: the share of the weighted residual bound h^T eps (what (8) minimises, eps_j the
    // largest |feature j| over the segments) that the trajectory removes; and of the squared residual.
    const Eigen::VectorXd rest = offset - xi[static_cast<std::size_t>(i)] * pi;
    const Eigen::MatrixXd rest_m = unstack_samples(rest, static_cast<int>(l));
    vp.explained = std::max(0.0, 1.0 - h.dot(rest_m.cwiseAbs().colwise().maxCoeff().transpose()) / eps0);
    vp.explained_squared = std::max(0.0, 1.0 - rest.squaredNorm() / total);
    vp.lo = vp.hi = vp.value;
    for (int s = 0; s < S; ++s) {
      const double v = vp.value + sc * pi[s];
      vp.lo = std::min(vp.lo, v);
      vp.hi = std::max(vp.hi, v);
      vp.trajectory.push_back({time[static_cast<std::size_t>(a[static_cast<std::size_t>(s)])],
                               time[static_cast<std::size_t>(a[static_cast<std::size_t>(s + 1)] - 1)], v});
    }
    // Jumps above mu; neighbouring jumps of the same sign are one step, whose window runs from the
    // start of the segment before the first jump to the end of the last (a step inside segment j
    // shows as jumps at j and/or j + 1). Steps are ranked by their total size.
    std::vector<std::pair<double, std::pair<int, int>>> events;  // (signed size, (first, last))
    for (int s = 1; s < S; ++s) {
      const double dlt = pi[s] - pi[s - 1];
      if (std::abs(dlt) <= mu * (1 + 1e-6)) continue;
      vp.jumps.emplace_back(time[static_cast<std::size_t>(a[static_cast<std::size_t>(s)])], sc * dlt);
      if (!events.empty() && events.back().second.second == s - 1 && (events.back().first > 0) == (dlt > 0)) {
        events.back().first += dlt;
        events.back().second.second = s;
      } else {
        events.push_back({dlt, {s, s}});
      }
    }
    std::sort(events.begin(), events.end(), [](const auto& x, const auto& y) { return std::abs(x.first) > std::abs(y.first); });
    for (std::size_t e = 0; e < std::min<std::size_t>(3, events.size()); ++e)
      vp.when.emplace_back(time[static_cast<std::size_t>(a[static_cast<std::size_t>(events[e].second.first - 1)])],
                           time[static_cast<std::size_t>(a[static_cast<std::size_t>(events[e].second.second + 1)] - 1)]);
    out.push_back(vp);
  }
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.explained > y.explained; });
  return out;
}

}  // namespace

Diagnosis diagnose(const ModelFile& model, const Recording& est, const Recording* val, const DiagnosisOptions& options) {
  const auto t_start = std::chrono::steady_clock::now();
  auto say = [&](const std::string& s) {
    if (!options.progress) return;
    std::ostringstream os;
    os << std::fixed << std::setprecision(1)
       << std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count() << " s: " << s;
    options.progress(os.str());
  };
  Diagnosis d;
  d.has_validation = val != nullptr;
  DiagnosisOptions opt = options;
  Simulator exact(model, est, {opt.final_substeps});
  if (opt.screening_substeps <= 0) {
    // Screening runs thousands of simulations: use the coarsest step that gives the same fits.
    const auto ref = evaluate(exact, exact.parameter_values());
    opt.screening_substeps = opt.final_substeps;
    for (int sub : {1, 2, 5}) {
      if (sub >= opt.final_substeps || !ref.ok) break;
      Simulator s(model, est, {sub});
      const auto r = evaluate(s, s.parameter_values());
      bool same = r.ok;
      for (std::size_t j = 0; same && j < r.fit.size(); ++j) same = std::abs(r.fit[j] - ref.fit[j]) < 0.2;
      if (same) {
        opt.screening_substeps = sub;
        break;
      }
    }
  }
  Simulator fast(model, est, {opt.screening_substeps});
  std::unique_ptr<Simulator> exact_val;
  if (val) exact_val = std::make_unique<Simulator>(model, *val, SimulationOptions{opt.final_substeps});
  d.outputs = exact.output_columns();
  const Eigen::MatrixXd& Y = exact.measured();
  const Eigen::Index N = Y.rows(), ny = Y.cols();

  // 1. Start and calibrated nominal.
  say("simulating the nominal model");
  Eigen::VectorXd p0 = values_of(model);
  {
    SimulationResult r = exact.simulate(p0);  // throws with the time if it blows up
    d.fit_start_estimation = fits(Y, r.outputs);
    if (val) d.fit_start_validation = fits(exact_val->measured(), exact_val->simulate(p0).outputs);
  }
  const std::vector<int> free0 = fast.free_parameters();
  for (int i : free0) d.free_nominal.push_back(model.parameters[static_cast<std::size_t>(i)].name);
  say("calibrating the nominal model's free parameters (" + std::to_string(opt.screening_substeps) +
      " RK4 substeps while screening, " + std::to_string(opt.final_substeps) + " for reported fits)");
  CalibrationOptions copt;
  copt.scale = scales_for(model, free0, {});
  // Calibrated with the screening step; the reported fits below use the full substeps.
  const CalibrationResult cal = calibrate(fast, p0, free0, copt);
  d.nominal = model;
  store_values(d.nominal, cal.parameters);
  SimulationResult nominal_sim = exact.simulate(cal.parameters);
  d.fit_nominal_estimation = fits(Y, nominal_sim.outputs);
  Eigen::MatrixXd nominal_val_out;
  if (val) {
    nominal_val_out = exact_val->simulate(cal.parameters).outputs;
    d.fit_nominal_validation = fits(exact_val->measured(), nominal_val_out);
  }

  // Noise floor and error bounds.
  std::vector<double> sigma(static_cast<std::size_t>(ny));
  double floor_cost = 0;
  for (Eigen::Index j = 0; j < ny; ++j) {
    sigma[static_cast<std::size_t>(j)] = noise_sigma(Y.col(j));
    const double den = (Y.col(j).array() - Y.col(j).mean()).matrix().squaredNorm();
    if (den > 0) floor_cost += sigma[static_cast<std::size_t>(j)] * sigma[static_cast<std::size_t>(j)] * static_cast<double>(N) / den;
  }
  const double nominal_cost = cost_of(d.fit_nominal_estimation);

  // 2. Locate the mismatch on the calibrated nominal model.
  say("locating the mismatch (windows, regions, frequency band, varying parameters)");
  const Eigen::MatrixXd R = Y - nominal_sim.outputs;
  std::vector<double> norm(static_cast<std::size_t>(ny));
  for (Eigen::Index j = 0; j < ny; ++j) {
    const double den = (Y.col(j).array() - Y.col(j).mean()).matrix().norm();
    norm[static_cast<std::size_t>(j)] = den > 0 ? den : 1.0;
  }
  Eigen::Index main = 0;
  for (Eigen::Index j = 1; j < ny; ++j)
    if (d.fit_nominal_estimation[static_cast<std::size_t>(j)] < d.fit_nominal_estimation[static_cast<std::size_t>(main)]) main = j;
  Eigen::VectorXd energy = Eigen::VectorXd::Zero(N);
  for (Eigen::Index j = 0; j < ny; ++j) energy += (R.col(j) / norm[static_cast<std::size_t>(j)]).cwiseAbs2();
  const double total_energy = std::max(energy.sum(), 1e-300);
  for (Eigen::Index j = 0; j < ny; ++j) d.error_bound.push_back(3 * sigma[static_cast<std::size_t>(j)]);
  d.bound_note =
      "error bound per output = 3 x noise sigma, sigma = MAD of the measured second difference / 0.6745 / sqrt(6)";
  {
    // Windows: moving RMS of the residual above the bound; falsified when no parameter change of
    // the linearised nominal model keeps every residual inside the bound (FPS of strips).
    const std::vector<double> sc = scales_for(d.nominal, free0, {});
    Eigen::MatrixXd J;
    try {
      J = free0.empty() ? Eigen::MatrixXd(N * ny, 0) : output_jacobian(exact, cal.parameters, free0, sc, nominal_sim.outputs);
    } catch (const NumericalError&) {
      J = Eigen::MatrixXd::Zero(N * ny, static_cast<Eigen::Index>(free0.size()));
    }
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
      for (auto& x : ws) d.windows.push_back(x);
    }
    // Which parameter would have to vary over time, and when (Salehpour–Johansson, issue 7).
    say("time-varying parameter estimates (linf_bound, sparse_bound)");
    d.varying = varying_parameters(d.nominal, est, opt.screening_substeps, cal.parameters, free0, sc, R, exact.time(),
                                   opt.varying_segments, opt.threads);
  }
  {
    // Operating regions where the residual concentrates.
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
    d.signature_residual = R.col(main);
    d.signature_output = d.outputs[static_cast<std::size_t>(main)];
  }
  {
    // Frequency band of the residual of the worst output.
    const Eigen::Index M = N;
    std::vector<double> r(static_cast<std::size_t>(M));
    for (Eigen::Index k = 0; k < M; ++k) r[static_cast<std::size_t>(k)] = R(k, main) - R.col(main).mean();
    Eigen::FFT<double> fft;
    std::vector<std::complex<double>> spec;
    fft.fwd(spec, r);
    const double Ts = exact.sample_time();
    std::vector<double> p(static_cast<std::size_t>(M / 2));
    for (std::size_t k = 1; k < p.size(); ++k) p[k] = std::norm(spec[k]);
    const double tot = std::accumulate(p.begin(), p.end(), 0.0);
    FrequencyBand b;
    b.output = d.outputs[static_cast<std::size_t>(main)];
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

  // 3. Competing hypotheses, added greedily (fewest terms that explain the data).
  ModelFile current = d.nominal;
  double cost_cur = cost_of(evaluate(fast, cal.parameters).fit);
  double cost_cur_val = 0;
  std::unique_ptr<Simulator> fast_val;
  if (val) {
    fast_val = std::make_unique<Simulator>(model, *val, SimulationOptions{opt.screening_substeps});
    cost_cur_val = cost_of(evaluate(*fast_val, cal.parameters).fit);
  }
  std::vector<std::string> chosen;
  std::vector<std::pair<std::string, double>> known_scales;
  std::vector<Candidate> chosen_candidates;
  d.nothing_missing = nominal_cost <= opt.noise_floor_factor * floor_cost;
  for (int round = 0; round < opt.max_effects && !d.nothing_missing; ++round) {
    if (cost_cur <= opt.noise_floor_factor * floor_cost) break;
    Simulator cur_sim(current, est, {opt.screening_substeps});
    const SimulationResult cur_res = cur_sim.simulate(values_of(current));
    std::vector<std::string> exclude = chosen;
    for (const auto& c : chosen) {  // one friction law at a time
      if (c == "coulomb_friction") exclude.push_back("stribeck_friction");
      if (c == "stribeck_friction") exclude.push_back("coulomb_friction");
    }
    std::vector<Candidate> cands = generate_candidates(current, cur_res, est, exclude);
    // Time delay: rank the delays per actuator by simulation alone; the best four compete
    // (calibrated like the others), the calibrated nominal may prefer a shorter one uncalibrated.
    {
      // Ranked by a short calibration on the first fifth of the record (a delay shifts the
      // optimum of the other parameters, so an uncalibrated ranking prefers too short a delay).
      Recording head = est;
      const std::size_t rows = static_cast<std::size_t>(std::max<Eigen::Index>(std::min<Eigen::Index>(N, 200), N / 5));
      for (auto& c : head.columns) c.resize(rows);
      std::vector<Candidate> kept;
      std::map<std::string, std::vector<std::pair<double, std::size_t>>> ranked;
      for (std::size_t i = 0; i < cands.size(); ++i) {
        if (cands[i].effect != "time_delay") continue;
        if (cands[i].delay_samples >= static_cast<int>(rows) / 10) continue;
        Simulator s(cands[i].model, head, {opt.screening_substeps});
        CalibrationOptions o;
        const auto fr = s.free_parameters();
        o.scale = scales_for(cands[i].model, fr, known_scales);
        o.max_evaluations = 10 * static_cast<int>(fr.size() + 1);
        const auto r = calibrate(s, s.parameter_values(), fr, o);
        ranked[cands[i].equation].push_back({r.ok ? r.cost : 1e300, i});
      }
      for (auto& [a, list] : ranked) {
        std::sort(list.begin(), list.end());
        for (std::size_t k = 0; k < std::min<std::size_t>(2, list.size()); ++k) kept.push_back(cands[list[k].second]);
      }
      for (auto& c : cands)
        if (c.effect != "time_delay") kept.push_back(std::move(c));
      cands = std::move(kept);
    }
    // The null hypothesis: the current model calibrated with the same budget. A hypothesis must
    // beat it, so that a better optimum of the old parameters is not credited to a new effect.
    {
      Candidate null;
      null.model = current;
      cands.insert(cands.begin(), null);
    }
    say("round " + std::to_string(round + 1) + ": calibrating " + std::to_string(cands.size()) + " competing hypotheses");
    std::vector<Trial> trials(cands.size());
    std::atomic<std::size_t> next{0};
    std::mutex mu;
    auto worker = [&] {
      for (std::size_t i; (i = next++) < cands.size();) {
        Trial t;
        t.cand = cands[i];
        try {
          if (t.cand.restart)
            for (auto& q : t.cand.model.parameters)
              if (const auto* orig = model.parameter(q.name); orig && !q.fixed) q.value = orig->value;
          Simulator s(t.cand.model, est, {opt.screening_substeps});
          const std::vector<int> fr = s.free_parameters();
          auto ks = known_scales;
          for (std::size_t k = 0; k < t.cand.parameters.size(); ++k) ks.emplace_back(t.cand.parameters[k], t.cand.scales[k]);
          CalibrationOptions o;
          o.scale = scales_for(t.cand.model, fr, ks);
          o.max_evaluations = 40 * static_cast<int>(fr.size() + 1);
          const auto r = calibrate(s, s.parameter_values(), fr, o);
          if (r.ok) {
            t.ok = true;
            t.cost = r.cost;
            t.fit = r.fit;
            t.model = t.cand.model;
            store_values(t.model, r.parameters);
            if (val) {
              Simulator sv(t.model, *val, {opt.screening_substeps});
              const auto rv = evaluate(sv, r.parameters);
              t.cost_val = rv.ok ? rv.cost : 1e300;
              t.fit_val = rv.fit;
            }
            // The same parameters with the effect switched off: what the effect itself contributes.
            if (!t.cand.parameters.empty()) {
              t.neutral_model = t.model;
              for (std::size_t k = 0; k < t.cand.parameters.size(); ++k)
                if (!std::isnan(t.cand.neutral[k])) t.neutral_model.parameter(t.cand.parameters[k])->value = t.cand.neutral[k];
              const auto rn = evaluate(s, values_of(t.neutral_model));
              t.cost_neutral = rn.ok ? rn.cost : 1e300;
              if (val && rn.ok) {
                Simulator sv(t.neutral_model, *val, {opt.screening_substeps});
                const auto rv = evaluate(sv, values_of(t.neutral_model));
                t.cost_neutral_val = rv.ok ? rv.cost : 1e300;
              }
            }
          }
        } catch (const std::exception&) {
          t.ok = false;  // a hypothesis that cannot be simulated loses
        }
        std::lock_guard<std::mutex> lock(mu);
        trials[i] = std::move(t);
      }
    };
    std::vector<std::thread> pool;
    for (int k = 0; k < std::max(1, opt.threads); ++k) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
    // Acceptance: removes enough of the misfit, more than noise could, and (with a validation
    // record) also helps there.
    if (trials.front().ok && trials.front().cost < cost_cur) {
      cost_cur = trials.front().cost;
      cost_cur_val = trials.front().cost_val;
      current = trials.front().model;
    }
    // A hypothesis whose calibration merely found a better optimum of the old parameters (its own
    // term switched off fits as well) shows a better baseline, not an effect.
    for (std::size_t i = 1; i < trials.size(); ++i) {
      const auto& t = trials[i];
      if (t.ok && t.cost_neutral < cost_cur && (!val || t.cost_neutral_val < 1e299)) {
        cost_cur = t.cost_neutral;
        cost_cur_val = val ? t.cost_neutral_val : 0;
        // Keep the current structure (the switched-off term is dropped), take the better values.
        for (auto& q : current.parameters)
          if (const auto* nq = t.neutral_model.parameter(q.name)) q.value = nq->value;
      }
    }
    std::vector<std::size_t> ok;
    for (std::size_t i = 1; i < trials.size(); ++i) {
      const auto& t = trials[i];
      if (!t.ok) continue;
      const double gain = (cost_cur - t.cost) / cost_cur;
      if (gain < opt.min_cost_reduction || cost_cur - t.cost < floor_cost) continue;
      if (t.cost_neutral < 1e299 && (t.cost_neutral - t.cost) / t.cost_neutral < opt.min_cost_reduction) continue;
      if (val && (cost_cur_val - t.cost_val) / cost_cur_val < 0.5 * opt.min_cost_reduction) continue;
      ok.push_back(i);
    }
    if (ok.empty()) break;
    auto judged = [&](std::size_t i) { return val ? trials[i].cost_val : trials[i].cost; };
    std::size_t best = ok.front();
    for (std::size_t i : ok)
      if (judged(i) < judged(best)) best = i;
    std::size_t pick = best;
    for (std::size_t i : ok)
      if (judged(i) <= opt.sparsity_tolerance * judged(best) &&
          (trials[i].cand.parameters.size() < trials[pick].cand.parameters.size() ||
           (trials[i].cand.parameters.size() == trials[pick].cand.parameters.size() && judged(i) < judged(pick))))
        pick = i;
    if (trials[pick].cand.effect == "time_delay") {
      // The grid is coarse: try every whole number of samples between the chosen one's neighbours.
      static const std::vector<int> grid = {1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64};
      Trial& t = trials[pick];
      const int n0 = t.cand.delay_samples;
      const auto it = std::find(grid.begin(), grid.end(), n0);
      const int lo = it == grid.begin() ? 1 : *(it - 1) + 1;
      const int hi = (it == grid.end() || it + 1 == grid.end()) ? n0 : *(it + 1) - 1;
      for (int n = lo; n <= hi; ++n) {
        if (n == n0 || n >= N / 10) continue;
        Candidate c = delay_candidate(current, t.cand.equation, n);
        for (auto& q : c.model.parameters) q.value = t.model.parameter(q.name)->value;
        Simulator s(c.model, est, {opt.screening_substeps});
        CalibrationOptions o;
        const auto fr = s.free_parameters();
        o.scale = scales_for(c.model, fr, known_scales);
        o.max_evaluations = 10 * static_cast<int>(fr.size() + 1);
        const auto r = calibrate(s, s.parameter_values(), fr, o);
        if (r.ok && r.cost < t.cost) {
          t.cand = c;
          t.model = c.model;
          store_values(t.model, r.parameters);
          t.cost = r.cost;
          t.fit = r.fit;
          if (val) {
            Simulator sv(t.model, *val, {opt.screening_substeps});
            const auto rv = evaluate(sv, r.parameters);
            t.cost_val = rv.ok ? rv.cost : 1e300;
          }
        }
      }
    }
    const Trial& t = trials[pick];
    DiagnosedEffect e;
    e.name = t.cand.effect;
    e.equation = t.cand.equation;
    e.term = t.cand.term;
    e.cost_reduction_estimation = (cost_cur - t.cost) / cost_cur;
    e.cost_reduction_validation = val ? (cost_cur_val - t.cost_val) / cost_cur_val : 0;
    std::ostringstream ev;
    ev << "adding " << t.cand.term << " to " << t.cand.equation << " removes " << fixed1(100 * e.cost_reduction_estimation)
       << " % of the squared misfit on the estimation record";
    if (val) ev << " and " << fixed1(100 * e.cost_reduction_validation) << " % on validation";
    ev << " (best of " << trials.size() - 1 << " competing hypotheses";
    if (pick != best) ev << "; preferred to " << trials[best].cand.effect << " as the simpler explanation";
    ev << ")";
    if (round == 0 && !d.regions.empty()) ev << "; nominal residual concentrated " << d.regions.front().description;
    e.evidence = ev.str();
    say("  found " + e.name + " in " + e.equation);
    for (std::size_t k = 0; k < t.cand.parameters.size(); ++k) known_scales.emplace_back(t.cand.parameters[k], t.cand.scales[k]);
    d.effects.push_back(e);
    chosen.push_back(t.cand.effect);
    chosen_candidates.push_back(t.cand);
    current = t.model;
    cost_cur = t.cost;
    cost_cur_val = t.cost_val;
  }

  // 4. Final augmented model: refined with the full substeps; PUIs of the new parameters.
  if (!d.effects.empty()) {
    say("refining the augmented model and computing parameter uncertainty intervals");
    Simulator aug(current, est, {opt.final_substeps});
    const std::vector<int> fr = aug.free_parameters();
    CalibrationOptions o;
    o.scale = scales_for(current, fr, known_scales);
    const auto r = evaluate(aug, aug.parameter_values());
    if (!r.ok) throw NumericalError("the augmented model blows up with the full substeps");
    d.augmented = current;
    d.fit_augmented_estimation = r.fit;
    d.augmented_estimation = r.outputs;
    if (val) {
      Simulator av(current, *val, {opt.final_substeps});
      d.augmented_validation = av.simulate(r.parameters).outputs;
      d.fit_augmented_validation = fits(av.measured(), d.augmented_validation);
    }
    // Linearised output error around the estimate, strips |r_t - J_t dtheta| <= delta_j with
    // delta_j = the largest residual of output j at the estimate (the smallest bound under which
    // the calibrated model itself is consistent with every used sample).
    const Eigen::MatrixXd J = output_jacobian(aug, r.parameters, fr, o.scale, r.outputs);
    const Eigen::MatrixXd Ra = Y - r.outputs;
    const Eigen::Index stride = std::max<Eigen::Index>(1, N / 1500);
    const Eigen::Index m = (N + stride - 1) / stride;
    Eigen::MatrixXd Phi(m * ny, J.cols());
    Eigen::VectorXd yy(m * ny), dd(m * ny);
    Eigen::MatrixXd Jw(m * ny, J.cols());
    Eigen::VectorXd rw(m * ny);
    for (Eigen::Index j = 0; j < ny; ++j) {
      double delta = 0;
      for (Eigen::Index i = 0; i < m; ++i) delta = std::max(delta, std::abs(Ra(i * stride, j)));
      // 1.5 x the largest residual at the estimate: the true parameters see the noise itself, whose
      // largest value is about as large as the estimate's; the margin keeps them inside.
      delta = 1.5 * delta + 1e-300;
      // Rows in units of the bound and columns in units of each parameter's scale keep the LP
      // well conditioned (position residuals of 1e-6 m next to forces of 1e2 N otherwise).
      for (Eigen::Index i = 0; i < m; ++i) {
        for (Eigen::Index c = 0; c < J.cols(); ++c)
          Phi(j * m + i, c) = J(j * N + i * stride, c) * o.scale[static_cast<std::size_t>(c)] / delta;
        yy[j * m + i] = Ra(i * stride, j) / delta;
        dd[j * m + i] = 1.0;
        Jw.row(j * m + i) = J.row(j * N + i * stride) / norm[static_cast<std::size_t>(j)];
        rw[j * m + i] = Ra(i * stride, j) / norm[static_cast<std::size_t>(j)];
      }
    }
    d.bound_note +=
        "; PUIs: strips of the output error linearised at the estimate (every " + std::to_string(stride) +
        "th sample), bound per output = 1.5 x the largest |residual| of the augmented model there";
    PuiResult pr;
    bool have_pui = false;
    try {
      pr = pui(FeasibleParameterSet::from_data(Phi, yy, dd));
      have_pui = !pr.empty();
    } catch (const std::exception& e) {
      have_pui = false;
      d.bound_note += std::string("; PUI computation failed: ") + e.what();
    }
    if (!have_pui) d.bound_note += "; the linearised strips were found inconsistent, no PUI";
    if (have_pui) d.bound_note += pr.guaranteed ? "; every finite PUI end certified by a safe bound" : "; some PUI ends not certified";
    // Equation-error PUIs where the effect's equation allows them (linear parameters, measured or
    // differentiable states): much less sensitive to what the model leaves out at high frequency.
    std::map<std::string, EquationErrorResult> ee_results;
    for (const auto& c : chosen_candidates) {
      if (ee_results.count(c.equation)) continue;
      try {
        ee_results[c.equation] = equation_error_pui(current, est, c.equation);
      } catch (const std::exception& e) {
        ee_results[c.equation].note = std::string("equation-error PUI failed: ") + e.what();
      }
      d.bound_note += "; " + ee_results[c.equation].note;
    }
    const double dof = std::max<double>(1.0, static_cast<double>(rw.size() - Jw.cols()));
    const double s2 = rw.squaredNorm() / dof;
    Eigen::MatrixXd cov = (Jw.transpose() * Jw).completeOrthogonalDecomposition().pseudoInverse() * s2;
    for (std::size_t k = 0; k < chosen_candidates.size(); ++k) {
      for (const auto& pn : chosen_candidates[k].parameters) {
        EffectParameter ep;
        ep.name = pn;
        for (std::size_t i = 0; i < fr.size(); ++i) {
          if (current.parameters[static_cast<std::size_t>(fr[i])].name != pn) continue;
          const auto ii = static_cast<Eigen::Index>(i);
          ep.estimate = r.parameters[fr[i]];
          // The parameter's own bounds (min/max) hold too, so the interval is cut to them.
          const auto& mp = current.parameters[static_cast<std::size_t>(fr[i])];
          const Interval theta = Interval(ep.estimate) + pr.box[ii] * o.scale[i];  // outward rounded
          ep.lo = ep.oe_lo = std::max(have_pui ? theta.lower() : -inf, mp.min);
          ep.hi = ep.oe_hi = std::min(have_pui ? theta.upper() : inf, mp.max);
          const auto ee = ee_results.find(chosen_candidates[k].equation);
          if (ee != ee_results.end() && ee->second.built)
            for (Eigen::Index c = 0; c < ee->second.box.size(); ++c)
              if (ee->second.parameters[static_cast<std::size_t>(c)] == pn) {
                ep.has_ee = true;
                ep.ee_lo = std::max(ee->second.box[c].lower(), mp.min);
                ep.ee_hi = std::min(ee->second.box[c].upper(), mp.max);
                // Each set holds the truth under its own bound, so under both the truth lies in
                // their intersection. Disjoint sets mean one bound is violated: then the hull.
                const bool meet = ep.ee_lo <= ep.oe_hi && ep.oe_lo <= ep.ee_hi;
                ep.lo = meet ? std::max(ep.ee_lo, ep.oe_lo) : std::min(ep.ee_lo, ep.oe_lo);
                ep.hi = meet ? std::min(ep.ee_hi, ep.oe_hi) : std::max(ep.ee_hi, ep.oe_hi);
                if (!meet) d.bound_note += "; the equation-error and output-error intervals of " + pn + " are disjoint (one bound is violated): their hull is reported";
              }
          const double sd = std::sqrt(std::max(0.0, cov(ii, ii)));
          ep.stat_lo = ep.estimate - 1.96 * sd;
          ep.stat_hi = ep.estimate + 1.96 * sd;
        }
        d.effects[k].parameters.push_back(ep);
      }
    }
  } else {
    d.augmented = d.nominal;
    d.fit_augmented_estimation = d.fit_nominal_estimation;
    d.fit_augmented_validation = d.fit_nominal_validation;
    d.augmented_estimation = nominal_sim.outputs;
    d.augmented_validation = nominal_val_out;
  }
  if (d.effects.empty()) {
    if (nominal_cost <= opt.noise_floor_factor * floor_cost || !d.nothing_missing) {
      // Either within the noise, or no catalogue effect helps: never invent one.
      d.nothing_missing = nominal_cost <= opt.noise_floor_factor * floor_cost;
    }
    d.verdict = d.nothing_missing
                    ? "No physics is missing: the calibrated nominal model explains the data to within the noise."
                    : "No effect of the catalogue explains the remaining mismatch; no physics is added.";
    if (!d.nothing_missing) {
      // Is what remains distinguishable from noise at all? A small relative misfit means the model is fine.
      bool all_good = true;
      for (double f : d.fit_nominal_estimation) all_good = all_good && f > 90;
      if (all_good) {
        d.nothing_missing = true;
        d.verdict = "No physics is missing: no catalogue effect improves the calibrated nominal model beyond the noise.";
      }
    }
  } else {
    d.verdict = "Missing physics: ";
    for (std::size_t k = 0; k < d.effects.size(); ++k) d.verdict += (k ? ", " : "") + d.effects[k].name + " (" + d.effects[k].equation + ")";
    d.verdict += ".";
  }
  d.time_estimation = Eigen::Map<const Eigen::VectorXd>(exact.time().data(), N);
  d.measured_estimation = Y;
  d.nominal_estimation = nominal_sim.outputs;
  if (val) {
    d.time_validation = Eigen::Map<const Eigen::VectorXd>(exact_val->time().data(), exact_val->samples());
    d.measured_validation = exact_val->measured();
    d.nominal_validation = nominal_val_out;
  }
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  return d;
}

namespace {
nlohmann::ordered_json num(double x) { return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr); }
nlohmann::ordered_json fit_obj(const std::vector<std::string>& outs, const std::vector<double>& f) {
  nlohmann::ordered_json o = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < f.size() && i < outs.size(); ++i) o[outs[i]] = num(f[i]);
  return o;
}
}  // namespace

std::string diagnosis_json(const Diagnosis& d, const std::string& augmented_path) {
  using J = nlohmann::ordered_json;
  J j;
  J params = J::object();
  for (const auto& n : d.free_nominal) params[n] = num(d.nominal.parameter(n)->value);
  j["nominal"]["parameters"] = params;
  j["nominal"]["fit"]["estimation"] = fit_obj(d.outputs, d.fit_nominal_estimation);
  j["nominal"]["fit"]["validation"] = fit_obj(d.outputs, d.fit_nominal_validation);
  j["nominal"]["fit_before_calibration"]["estimation"] = fit_obj(d.outputs, d.fit_start_estimation);
  j["nominal"]["fit_before_calibration"]["validation"] = fit_obj(d.outputs, d.fit_start_validation);
  J windows = J::array();
  for (const auto& w : d.windows)
    windows.push_back({{"output", w.output}, {"start", w.start}, {"end", w.end}, {"rms", w.rms}, {"falsified", w.falsified}});
  J regions = J::array();
  for (const auto& r : d.regions)
    regions.push_back({{"description", r.description}, {"variable", r.variable}, {"residual_share", r.residual_share},
                       {"sample_share", r.sample_share}});
  J varying = J::array();
  for (const auto& v : d.varying) {
    J when = J::array();
    for (const auto& w : v.when) when.push_back({w.first, w.second});
    J traj = J::array();
    for (const auto& sv : v.trajectory) traj.push_back({{"start", sv.start}, {"end", sv.end}, {"value", sv.value}});
    J jumps = J::array();
    for (const auto& jp : v.jumps) jumps.push_back({{"time", jp.first}, {"size", jp.second}});
    varying.push_back({{"name", v.name}, {"value", v.value}, {"range", {v.lo, v.hi}}, {"explained", v.explained}, {"when", when},
                       {"explained_squared", v.explained_squared}, {"bound", v.bound}, {"method", v.method}, {"jumps", jumps}, {"trajectory", traj}});
  }
  J bands = J::array();
  for (const auto& b : d.bands) bands.push_back({{"output", b.output}, {"band_hz", {b.lo_hz, b.hi_hz}}, {"peak_hz", b.peak_hz}});
  j["mismatch"]["windows"] = windows;
  j["mismatch"]["regions"] = regions;
  j["mismatch"]["varying_parameters"] = varying;
  j["mismatch"]["frequency_band"] = bands;
  J bounds = J::object();
  for (std::size_t i = 0; i < d.error_bound.size(); ++i) bounds[d.outputs[i]] = d.error_bound[i];
  j["mismatch"]["error_bound"] = bounds;
  J effects = J::array();
  for (const auto& e : d.effects) {
    J ps = J::object();
    for (const auto& p : e.parameters)
      ps[p.name] = {{"estimate", num(p.estimate)}, {"interval", {num(p.lo), num(p.hi)}},
                    {"statistical_95", {num(p.stat_lo), num(p.stat_hi)}},
                    {"interval_output_error", {num(p.oe_lo), num(p.oe_hi)}},
                    {"interval_equation_error", p.has_ee ? J{num(p.ee_lo), num(p.ee_hi)} : J(nullptr)}};
    effects.push_back({{"name", e.name}, {"equation", e.equation}, {"term", e.term}, {"parameters", ps}, {"evidence", e.evidence}});
  }
  j["effects"] = effects;
  j["augmented"]["model"] = augmented_path.empty() ? J(nullptr) : J(augmented_path);
  j["augmented"]["fit"]["estimation"] = fit_obj(d.outputs, d.fit_augmented_estimation);
  j["augmented"]["fit"]["validation"] = fit_obj(d.outputs, d.fit_augmented_validation);
  j["verdict"] = d.verdict;
  j["nothing_missing"] = d.nothing_missing;
  j["bound_note"] = d.bound_note;
  j["seconds"] = d.seconds;
  return j.dump(2) + "\n";
}

std::string diagnosis_text(const Diagnosis& d) {
  std::ostringstream o;
  auto fitline = [&](const char* label, const std::vector<double>& f) {
    o << "  " << std::left << std::setw(34) << label;
    for (std::size_t i = 0; i < f.size(); ++i) o << "  " << d.outputs[i] << " " << fixed1(f[i]) << " %";
    o << "\n";
  };
  o << "Fit per output (100 (1 - |y - yhat| / |y - mean y|)):\n";
  fitline("nominal, file values, estimation", d.fit_start_estimation);
  fitline("nominal, calibrated, estimation", d.fit_nominal_estimation);
  if (d.has_validation) fitline("nominal, calibrated, validation", d.fit_nominal_validation);
  o << "Calibrated nominal parameters:";
  for (const auto& n : d.free_nominal) o << " " << n << " = " << fmt(d.nominal.parameter(n)->value, 5);
  o << "\nWhere the nominal model fails:\n";
  int shown = 0;
  for (const auto& w : d.windows) {
    if (shown++ == 4) break;
    o << "  " << w.output << ": t = " << fmt(w.start, 4) << " .. " << fmt(w.end, 4) << " s, residual RMS " << fmt(w.rms)
      << (w.falsified ? " (falsified: no parameter value fits inside the bound)" : "") << "\n";
  }
  if (d.windows.size() > 4) o << "  ... " << d.windows.size() << " windows in all\n";
  for (std::size_t i = 0; i < std::min<std::size_t>(3, d.regions.size()); ++i)
    o << "  residual concentrated " << d.regions[i].description << ": " << fixed1(100 * d.regions[i].residual_share)
      << " % of it in " << fixed1(100 * d.regions[i].sample_share) << " % of the samples\n";
  for (const auto& b : d.bands)
    o << "  frequency band of the " << b.output << " residual: " << fmt(b.lo_hz) << " .. " << fmt(b.hi_hz) << " Hz (peak "
      << fmt(b.peak_hz) << " Hz)\n";
  if (!d.varying.empty()) {
    const auto& v = d.varying.front();
    o << "  parameter that would have to vary most: " << v.name << " between " << fmt(v.lo, 4) << " and " << fmt(v.hi, 4)
      << " (removes " << fixed1(100 * v.explained) << " % of the residual's window-norm bound";
    if (!v.when.empty()) {
      o << "; it jumps in t = ";
      for (std::size_t w = 0; w < v.when.size(); ++w) o << (w ? ", " : "") << fmt(v.when[w].first, 4) << " .. " << fmt(v.when[w].second, 4);
      o << " s";
    }
    o << ")\n";
  }
  o << "Verdict: " << d.verdict << "\n";
  for (std::size_t k = 0; k < d.effects.size(); ++k) {
    const auto& e = d.effects[k];
    o << "  " << k + 1 << ". " << e.name << " in " << e.equation << ": " << e.term << "\n";
    for (const auto& p : e.parameters)
      o << "     " << p.name << " = " << fmt(p.estimate, 5) << ", guaranteed interval [" << fmt(p.lo, 5) << ", "
        << fmt(p.hi, 5) << "]"
        << (p.has_ee ? " (equation error [" + fmt(p.ee_lo, 5) + ", " + fmt(p.ee_hi, 5) + "], output error [" + fmt(p.oe_lo, 5) + ", " + fmt(p.oe_hi, 5) + "])"
                     : " (output error)")
        << ", statistical 95 % [" << fmt(p.stat_lo, 5) << ", " << fmt(p.stat_hi, 5) << "]\n";
    o << "     evidence: " << e.evidence << "\n";
  }
  if (!d.effects.empty()) {
    fitline("augmented, estimation", d.fit_augmented_estimation);
    if (d.has_validation) fitline("augmented, validation", d.fit_augmented_validation);
  }
  o << "(" << fixed1(d.seconds) << " s)\n";
  return o.str();
}

}  // namespace sets
