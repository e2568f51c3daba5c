#include "sets/examples/bounded_error_regression.hpp"

#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>

#include "sets/core/error.hpp"

namespace sets {

namespace {

// Portable draws (the <random> distributions differ between standard libraries).
class Draw {
 public:
  explicit Draw(unsigned long seed) : rng_(0x9e3779b97f4a7c15ull ^ seed) {}
  double uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  int integer(int a, int b) { return a + static_cast<int>(uniform() * (b - a + 1)); }  // a..b
  double normal() {  // Box–Muller
    const double u = 1 - uniform(), v = uniform();
    return std::sqrt(-2 * std::log(u)) * std::cos(6.283185307179586 * v);
  }

 private:
  std::mt19937_64 rng_;
};

struct Exact {  // exact regressors, before the FPS is built
  Eigen::MatrixXd Phi;
  Eigen::VectorXd theta;
};

Exact normal_regressors(Draw& d, int p, int N) {
  Exact e;
  e.Phi = Eigen::MatrixXd::NullaryExpr(N, p, [&] { return d.uniform(-1, 1); });
  e.theta = Eigen::VectorXd::NullaryExpr(p, [&] { return d.uniform(-2, 2); });
  return e;
}

Exact badly_scaled(Draw& d, int p, int N) {
  Exact e = normal_regressors(d, p, N);
  for (int j = 0; j < p; ++j) {
    const double s = std::pow(10.0, d.integer(-10, 10));
    e.Phi.col(j) *= s;
    e.theta[j] /= s;
  }
  return e;
}

Exact near_collinear(Draw& d, int p, int N) {
  Exact e;
  const Eigen::VectorXd c = Eigen::VectorXd::NullaryExpr(N, [&] { return d.uniform(-1, 1); });
  e.Phi.resize(N, p);
  for (int j = 0; j < p; ++j) {
    const double a = d.uniform(0.5, 1.5) * (d.uniform() < 0.5 ? -1 : 1);
    const double eps = std::pow(10.0, -d.uniform(4, 10));
    for (int t = 0; t < N; ++t) e.Phi(t, j) = a * c[t] + eps * d.normal();
  }
  e.theta = Eigen::VectorXd::NullaryExpr(p, [&] { return d.uniform(-2, 2); });
  return e;
}

// Outputs phi^T theta + e with |e| <= 0.9 delta and a bound delta relative to the output scale.
FeasibleParameterSet exact_fps(Draw& d, const Exact& e) {
  const Eigen::Index N = e.Phi.rows();
  const Eigen::VectorXd clean = e.Phi * e.theta;
  // The bound is relative to the size of the terms phi_j theta_j, not of their (possibly
  // cancelling) sum, so the rounding of `clean` stays far inside the 10 % margin.
  const double scale = std::max((e.Phi.cwiseAbs() * e.theta.cwiseAbs()).maxCoeff(), 1e-300);
  const double level = std::pow(10.0, -d.uniform(1, 4));  // bound = 1e-1 .. 1e-4 of the output scale
  Eigen::VectorXd y(N), delta(N);
  for (Eigen::Index t = 0; t < N; ++t) {
    delta[t] = level * scale * d.uniform(0.5, 1.5);
    y[t] = clean[t] + 0.9 * delta[t] * d.uniform(-1, 1);
  }
  return FeasibleParameterSet::from_data(e.Phi, y, delta);
}

FeasibleParameterSet errors_in_variables(Draw& d, int p, int N, Eigen::VectorXd& theta) {
  const Exact e = normal_regressors(d, p, N);
  theta = e.theta;
  const double rel = std::pow(10.0, -d.uniform(1.3, 3));  // 5 % .. 0.1 % of the regressor range
  IntervalMatrix Phi(N, p);
  for (int t = 0; t < N; ++t)
    for (int j = 0; j < p; ++j) {
      const double measured = e.Phi(t, j) + rel * d.uniform(-1, 1);
      Phi(t, j) = interval_around(measured, rel);  // contains the true regressor
    }
  const Eigen::VectorXd clean = e.Phi * e.theta;
  const double level =
      std::pow(10.0, -d.uniform(1, 3)) * std::max((e.Phi.cwiseAbs() * e.theta.cwiseAbs()).maxCoeff(), 1e-300);
  IntervalVector Y(N);
  for (int t = 0; t < N; ++t) {
    const double delta = level * d.uniform(0.5, 1.5);
    Y[t] = interval_around(clean[t] + 0.9 * delta * d.uniform(-1, 1), delta);
  }
  return FeasibleParameterSet::from_interval_data(Phi, Y);
}

}  // namespace

RegressionKind regression_kind_of_seed(unsigned long seed) {
  return static_cast<RegressionKind>((seed + regression_kind_count - 1) % regression_kind_count);
}

BoundedErrorRegression bounded_error_regression(unsigned long seed) {
  Draw d(seed);
  BoundedErrorRegression r;
  r.seed = seed;
  r.kind = regression_kind_of_seed(seed);
  switch (r.kind) {
    case RegressionKind::normal: {
      const int p = d.integer(1, 7);
      const Exact e = normal_regressors(d, p, d.integer(2 * p, 120));
      r.fps = exact_fps(d, e);
      r.theta = e.theta;
      break;
    }
    case RegressionKind::badly_scaled: {
      const int p = d.integer(1, 7);
      const Exact e = badly_scaled(d, p, d.integer(2 * p, 120));
      r.fps = exact_fps(d, e);
      r.theta = e.theta;
      break;
    }
    case RegressionKind::near_collinear: {
      const Exact e = near_collinear(d, d.integer(2, 7), 80);
      r.fps = exact_fps(d, e);
      r.theta = e.theta;
      break;
    }
    case RegressionKind::errors_in_variables: {
      const int p = d.integer(1, 4);
      r.fps = errors_in_variables(d, p, d.integer(2 * p + 2, 60), r.theta);
      r.options.orthants = OrthantSelection::all;  // the set may not be connected across orthants
      break;
    }
    case RegressionKind::tiny_n: {
      const int p = d.integer(1, 7);
      const Exact e = normal_regressors(d, p, p + d.integer(0, 1));
      r.fps = exact_fps(d, e);
      r.theta = e.theta;
      break;
    }
  }
  if (r.fps.contains(r.theta) != BoolInterval::yes)
    throw std::logic_error("bounded_error_regression: seed " + std::to_string(seed) +
                           ": the true parameter is not proven to lie in the set (generator bug)");
  return r;
}

const char* to_string(RegressionKind kind) {
  switch (kind) {
    case RegressionKind::normal: return "normal";
    case RegressionKind::badly_scaled: return "badly scaled";
    case RegressionKind::near_collinear: return "near-collinear";
    case RegressionKind::errors_in_variables: return "errors in variables";
    default: return "tiny N";
  }
}

SoundnessOutcome run_soundness_problem(const BoundedErrorRegression& problem) {
  SoundnessOutcome o;
  o.kind = problem.kind;
  o.seed = problem.seed;
  o.parameters = problem.fps.dimension();
  o.samples = problem.fps.size();
  const auto t0 = std::chrono::steady_clock::now();
  try {
    const PuiResult r = pui(problem.fps, problem.options);
    o.verdict = r.consistency.falsified;
    o.guaranteed = r.guaranteed;
    o.lp_solves = r.lp_solves;
    if (!r.empty()) {
      o.theta_in_box = contains(r.box, problem.theta);
      o.box_finite = lower(r.box).allFinite() && upper(r.box).allFinite();
    }
  } catch (const NumericalError& e) {
    o.numerical_error = true;
    o.error = e.what();
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return o;
}

}  // namespace sets
