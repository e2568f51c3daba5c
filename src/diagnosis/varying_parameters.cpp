// Stage 2 of the diagnosis, part: which parameter would have to vary over time, and when.

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>

#include "diagnosis/stages.hpp"
#include "sets/methods/tv_bound/tv_bound.hpp"
#include "sets/methods/tv_bound/window_norm.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets::diagnosis_stage {

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
  run_worker_threads(threads, [&] {
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
  });
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
  // One parameter's estimate (l-inf, then sparse): independent of the others' (its own LPs), so
  // one worker job each; collected in parameter order, so the result is the serial one.
  auto estimate = [&](int i) -> std::optional<VaryingParameter> {
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
      return std::nullopt;  // an estimate that cannot be computed is not reported
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
    return vp;
  };
  std::vector<std::optional<VaryingParameter>> found(static_cast<std::size_t>(q));
  run_jobs(threads, found.size(), [&](std::size_t i) { found[i] = estimate(static_cast<int>(i)); });
  for (auto& f : found)
    if (f) out.push_back(std::move(*f));
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.explained > y.explained; });
  return out;
}


}  // namespace sets::diagnosis_stage
