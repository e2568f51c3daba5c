// Stage 2 of the diagnosis, part: which parameter would have to vary over time, and when.

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "diagnosis/stages.hpp"
#include "sets/methods/tv_bound/tv_bound.hpp"
#include "sets/methods/tv_bound/window_norm.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets::diagnosis_stage {

namespace {

// The record cut into S segments; feature j of segment s is the mean over the j-th of m equal
// parts of the segment (averaging keeps isolated spikes and noise from setting the l-inf fit).
class SegmentFeatures {
 public:
  SegmentFeatures(Eigen::Index N, int S) : S_(S), a_(static_cast<std::size_t>(S + 1)) {
    for (int s = 0; s <= S; ++s) a_[static_cast<std::size_t>(s)] = N * s / S;
    Eigen::Index shortest = N;
    for (int s = 0; s < S; ++s) shortest = std::min(shortest, start(s + 1) - start(s));
    m_ = std::min<Eigen::Index>(shortest, 25);
  }

  int segments() const { return S_; }
  Eigen::Index parts() const { return m_; }
  Eigen::Index start(int s) const { return a_[static_cast<std::size_t>(s)]; }  // start(S) = N

  double mean(const Eigen::MatrixXd& x, Eigen::Index o, int s, Eigen::Index j) const {
    const Eigen::Index lo = start(s), len = start(s + 1) - lo;
    const Eigen::Index b0 = lo + len * j / m_, b1 = lo + len * (j + 1) / m_;
    return x.col(o).segment(b0, b1 - b0).mean();
  }

 private:
  int S_;
  std::vector<Eigen::Index> a_;
  Eigen::Index m_ = 0;
};

// The Salehpour–Johansson problem of one calibrated model: residual features Y ("sample" k + 1
// stacks the m features per output of segment k, sample 0 is an empty block: the model is nominal
// before the record) and, per free parameter, the sensitivities Xi of the features to a
// piecewise-constant perturbation, one column per segment (block lower triangular as in (4)).
class VaryingParameterSearch {
 public:
  VaryingParameterSearch(const ModelFile& model, const Eigen::VectorXd& p, const std::vector<int>& free,
                         const std::vector<double>& scale, const Eigen::MatrixXd& R, const std::vector<double>& time,
                         int S)
      : model_(model), p_(p), free_(free), scale_(scale), time_(time), seg_(R.rows(), S), ny_(R.cols()),
        l_(ny_ * seg_.parts()) {
    residual_features(R);
    fit_weights();
  }

  // Column (i, s) of xi_[i]: d(features)/d(pi_i over segment s), pi in units of scale_i, by finite
  // differences of the simulation (S x q runs, side by side in groups of up to 8). False when a
  // simulation fails.
  bool sensitivities(const Recording& est, int substeps, int threads) {
    const int q = static_cast<int>(free_.size()), S = seg_.segments();
    xi_.assign(static_cast<std::size_t>(q), Eigen::MatrixXd::Zero((S + 1) * l_, S));
    Eigen::MatrixXd y0;
    if (!Simulator(model_, est, {substeps}).simulate_outputs(p_, y0)) return false;
    // As many groups as fill every thread, each of at most 8 runs.
    const auto columns = static_cast<std::size_t>(q * S), per_thread = static_cast<std::size_t>(std::max(1, threads));
    const std::size_t groups = std::min(columns, (columns + 8 * per_thread - 1) / (8 * per_thread) * per_thread);
    std::vector<char> simulated(groups, 0);
    run_jobs_with(
        threads, groups, [&] { return std::make_unique<Simulator>(model_, est, SimulationOptions{substeps}); },
        [&](const std::unique_ptr<Simulator>& sim, std::size_t g) {
          const std::size_t from = columns * g / groups, to = columns * (g + 1) / groups;
          std::vector<Eigen::MatrixXd> schedules, y1;
          for (std::size_t c = from; c < to; ++c) schedules.push_back(schedule_of(static_cast<int>(c) / S, static_cast<int>(c) % S));
          std::vector<bool> ok;
          sim->simulate_outputs_scheduled_each(schedules, y1, ok);
          simulated[g] = std::all_of(ok.begin(), ok.end(), [](bool b) { return b; });
          for (std::size_t c = from; c < to && simulated[g]; ++c)
            sensitivity_column(y1[c - from], y0, static_cast<int>(c) / S, static_cast<int>(c) % S);
        });
    return std::all_of(simulated.begin(), simulated.end(), [](char c) { return c != 0; });
  }

  // The calibrated values with parameter i moved by step(i) over segment s only.
  Eigen::MatrixXd schedule_of(int i, int s) const {
    const int S = seg_.segments();
    Eigen::MatrixXd sched = p_.transpose().replicate(seg_.start(S), 1);
    sched.col(free_[static_cast<std::size_t>(i)]).segment(seg_.start(s), seg_.start(s + 1) - seg_.start(s)).array() += step(i);
    return sched;
  }
  double step(int i) const { return 1e-2 * scale_[static_cast<std::size_t>(i)]; }  // 1 % of the scale

  // Column s of xi_[i] from the outputs y1 of schedule_of(i, s).
  void sensitivity_column(Eigen::MatrixXd& y1, const Eigen::MatrixXd& y0, int i, int s) {
    const int S = seg_.segments();
    const Eigen::Index m = seg_.parts();
    const double h = step(i);
    y1 -= y0;
    for (int k = s; k < S; ++k)  // causal: segment s acts on segments s, s + 1, ...
      for (Eigen::Index o = 0; o < ny_; ++o)
        for (Eigen::Index j = 0; j < m; ++j)
          xi_[static_cast<std::size_t>(i)]((k + 1) * l_ + o * m + j, s) =
              seg_.mean(y1, o, k, j) / h * scale_[static_cast<std::size_t>(i)] / sigma_[o];
  }

  // One parameter's estimate (l-inf, then sparse); nothing when it cannot be computed.
  std::optional<VaryingParameter> estimate(int i) const {
    TvBoundData data;
    data.regression.zeta = Eigen::MatrixXd::Zero(seg_.segments() + 1, 1);
    data.regression.upsilon = Eigen::VectorXd::Zero((seg_.segments() + 1) * l_);
    data.regression.xi = xi_[static_cast<std::size_t>(i)];
    data.y = Y_;
    data.windows = {WindowNorm::pulse(1, 1.0)};
    LinfBoundOptions lo;
    lo.h = h_;
    lo.initial_difference = false;  // the calibrated value may be off from the start
    TvBoundResult lin;
    try {
      lin = linf_bound(data, lo);
    } catch (const std::exception&) {
      return std::nullopt;  // an estimate that cannot be computed is not reported
    }
    const double sc = scale_[static_cast<std::size_t>(i)];
    VaryingParameter vp;
    vp.name = model_.parameters[static_cast<std::size_t>(free_[static_cast<std::size_t>(i)])].name;
    vp.value = p_[free_[static_cast<std::size_t>(i)]];
    vp.bound = sc * lin.bound[0];
    vp.method = "linf_bound";
    const double mu = std::max(0.1 * lin.bound[0], 1e-9);
    Eigen::VectorXd pi = lin.pi.col(0);
    if (lin.bound[0] > 0 && sparse_when(data, lin, mu, pi)) vp.method = "sparse_bound";
    // Explained: the share of the weighted residual bound h^T eps (what (8) minimises, eps_j the
    // largest |feature j| over the segments) that the trajectory removes; and of the squared residual.
    const Eigen::VectorXd rest = offset_ - xi_[static_cast<std::size_t>(i)] * pi;
    const Eigen::MatrixXd rest_m = unstack_samples(rest, static_cast<int>(l_));
    vp.explained = std::max(0.0, 1.0 - h_.dot(rest_m.cwiseAbs().colwise().maxCoeff().transpose()) / eps0_);
    vp.explained_squared = std::max(0.0, 1.0 - rest.squaredNorm() / total_);
    describe_trajectory(pi, sc, mu, vp);
    return vp;
  }

 private:
  // Y scaled per output by the residual's rms, so every output weighs the same.
  void residual_features(const Eigen::MatrixXd& R) {
    const Eigen::Index N = R.rows(), m = seg_.parts();
    sigma_.resize(ny_);
    for (Eigen::Index o = 0; o < ny_; ++o) {
      const double rms = std::sqrt(R.col(o).squaredNorm() / static_cast<double>(N));
      sigma_[o] = rms > 0 ? rms : 1.0;
    }
    Y_ = Eigen::MatrixXd::Zero(seg_.segments() + 1, l_);
    for (int s = 0; s < seg_.segments(); ++s)
      for (Eigen::Index o = 0; o < ny_; ++o)
        for (Eigen::Index j = 0; j < m; ++j) Y_(s + 1, o * m + j) = seg_.mean(R, o, s, j) / sigma_[o];
    offset_ = stack_samples(Y_);
    total_ = std::max(offset_.squaredNorm(), 1e-300);
  }

  // eps weights: the fit dominates the objective (10 x the perturbation terms when nothing is
  // explained), so the estimate is the smallest perturbation that fits about as well as any can.
  void fit_weights() {
    const Eigen::Index m = seg_.parts();
    h_.resize(l_);
    for (Eigen::Index o = 0; o < ny_; ++o) {
      const double peak = std::max(Y_.middleCols(o * m, m).cwiseAbs().maxCoeff(), 1e-12);
      h_.segment(o * m, m).setConstant(10.0 / (static_cast<double>(l_) * peak));
    }
    eps0_ = std::max(h_.dot(Y_.cwiseAbs().colwise().maxCoeff().transpose()), 1e-300);
  }

  // The sparse "when": fewest jumps above mu (10 % of the l-inf peak) that keep the residual inside
  // the l-inf eps widened by 10 %, warm-started from the l-inf trajectory. False if not solved.
  bool sparse_when(const TvBoundData& data, const TvBoundResult& lin, double mu, Eigen::VectorXd& pi) const {
    SparseBoundOptions so;
    so.mu = Eigen::VectorXd::Constant(1, mu);
    so.max_abs = Eigen::VectorXd::Constant(1, 2 * lin.bound[0] + mu);
    so.epsilon = lin.epsilon * 1.1 + Eigen::VectorXd::Constant(l_, 1e-9);
    so.initial_difference = false;
    // A node limit, not a short time limit, so the answer does not depend on the machine's load;
    // the 10 s is only a guard.
    so.milp = MilpOptions{10.0, 1e-4, false, 3000};
    so.start = lin.pi;
    try {
      pi = sparse_bound(data, so).pi.col(0);
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }

  // The trajectory in parameter units, its jumps above mu and the windows of the largest steps:
  // neighbouring jumps of the same sign are one step, whose window runs from the start of the
  // segment before the first jump to the end of the last (a step inside segment j shows as jumps
  // at j and/or j + 1). Steps are ranked by their total size.
  void describe_trajectory(const Eigen::VectorXd& pi, double sc, double mu, VaryingParameter& vp) const {
    const int S = seg_.segments();
    auto t = [&](Eigen::Index k) { return time_[static_cast<std::size_t>(k)]; };
    vp.lo = vp.hi = vp.value;
    for (int s = 0; s < S; ++s) {
      const double v = vp.value + sc * pi[s];
      vp.lo = std::min(vp.lo, v);
      vp.hi = std::max(vp.hi, v);
      vp.trajectory.push_back({t(seg_.start(s)), t(seg_.start(s + 1) - 1), v});
    }
    std::vector<std::pair<double, std::pair<int, int>>> events;  // (signed size, (first, last))
    for (int s = 1; s < S; ++s) {
      const double dlt = pi[s] - pi[s - 1];
      if (std::abs(dlt) <= mu * (1 + 1e-6)) continue;
      vp.jumps.emplace_back(t(seg_.start(s)), sc * dlt);
      if (!events.empty() && events.back().second.second == s - 1 && (events.back().first > 0) == (dlt > 0)) {
        events.back().first += dlt;
        events.back().second.second = s;
      } else {
        events.push_back({dlt, {s, s}});
      }
    }
    std::sort(events.begin(), events.end(), [](const auto& x, const auto& y) { return std::abs(x.first) > std::abs(y.first); });
    for (std::size_t e = 0; e < std::min<std::size_t>(3, events.size()); ++e)
      vp.when.emplace_back(t(seg_.start(events[e].second.first - 1)), t(seg_.start(events[e].second.second + 1) - 1));
  }

  const ModelFile& model_;
  const Eigen::VectorXd& p_;
  const std::vector<int>& free_;
  const std::vector<double>& scale_;
  const std::vector<double>& time_;
  const SegmentFeatures seg_;
  const Eigen::Index ny_, l_;  // l_: "outputs" of the regression, (output, sub-sample) pairs
  Eigen::VectorXd sigma_, offset_, h_;
  Eigen::MatrixXd Y_;
  double total_ = 0, eps0_ = 0;
  std::vector<Eigen::MatrixXd> xi_;
};

}  // namespace

// Which parameter would have to vary over time, and when: the Salehpour–Johansson estimates of
// sets/tv_bound.hpp on the calibrated model. Each free parameter is perturbed piecewise constant
// over S segments; the residual ball is the window norm with the one-sample window: |residual| <=
// eps per (output, sub-sample) over all segments.
std::vector<VaryingParameter> varying_parameters(const ModelFile& model, const Recording& est, int substeps,
                                                 const Eigen::VectorXd& p, const std::vector<int>& free,
                                                 const std::vector<double>& scale, const Eigen::MatrixXd& R,
                                                 const std::vector<double>& time, int segments, int threads) {
  const Eigen::Index N = R.rows();
  const int q = static_cast<int>(free.size());
  const int S = segments > 0 ? segments : static_cast<int>(std::clamp<Eigen::Index>(N / 500, 10, 30));
  if (q == 0 || N < 4 * S) return {};
  VaryingParameterSearch search(model, p, free, scale, R, time, S);
  if (!search.sensitivities(est, substeps, threads)) return {};
  // One parameter's estimate is independent of the others' (its own LPs), so one worker job each;
  // collected in parameter order, so the result is the serial one.
  std::vector<std::optional<VaryingParameter>> found(static_cast<std::size_t>(q));
  run_jobs(threads, found.size(), [&](std::size_t i) { found[i] = search.estimate(static_cast<int>(i)); });
  std::vector<VaryingParameter> out;
  for (auto& f : found)
    if (f) out.push_back(std::move(*f));
  std::sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.explained > y.explained; });
  return out;
}

}  // namespace sets::diagnosis_stage
