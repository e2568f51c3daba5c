#include "sets/diagnosis/equation_error.hpp"

#include <boost/algorithm/string/classification.hpp>
#include <boost/algorithm/string/trim.hpp>
#include <Eigen/QR>
#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "models/expression.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/interval.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/data/intersample.hpp"
#include "sets/data/noise_level.hpp"
#include "sets/data/simulation.hpp"

namespace sets {

namespace {

std::string trimmed(const std::string& s) { return boost::algorithm::trim_copy_if(s, boost::is_any_of(" \t")); }

}  // namespace

namespace {

Eigen::VectorXd column_of(const Recording& data, const std::string& c) {
  const auto& v = data.column(c);
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())).eval();
}

}  // namespace

ColumnNoise measured_noise(const ModelFile& model, const Recording& data) {
  ColumnNoise out;
  for (const auto& [sym, col] : model.outputs)
    if (!out.count(col)) out[col] = estimate_noise(column_of(data, col)).sigma;
  return out;
}

namespace {

// The equation-error regression of one state equation, built in stages: what is measured, which
// symbols the equation needs, its right-hand side compiled over those values (constructor); then,
// per integration window, the integrated derivative, the differentiated states' estimates, which
// free parameters act and enter linearly, the interval regressors per sample interval and their
// integrals over the window (build).
class EquationRegression {
 public:
  EquationRegression(const ModelFile& model, const Recording& data, const std::string& state, const ColumnNoise& noise)
      : model_(model), state_(state), sim_(model, data, {1}), N_(sim_.samples()), Ts_(sim_.sample_time()) {
    const std::string* f_text = model.derivative(state);
    if (!f_text) {
      problem_ = "not a state equation";
      return;
    }
    find_measured(data);
    if (!choose_order()) return;
    if (!resolve_symbols(*f_text)) return;
    compile(*f_text);
    estimate_noise_of_integrals(noise);
  }
  EquationRegression(const EquationRegression&) = delete;  // the parsers point into vars_
  EquationRegression& operator=(const EquationRegression&) = delete;

  int samples() const { return N_; }
  const std::string& problem() const { return problem_; }  // empty: the equation can be regressed
  EquationErrorRegression build(int w);

 private:
  struct Measured {  // where a measured symbol's value goes, looked up once
    double* at;
    const Eigen::VectorXd* v;
    bool is_state;
  };
  struct Differentiated {  // a differentiated state: its estimate and the estimate's radius
    double* at;
    Eigen::VectorXd zhat;
    double rho;
  };
  struct Regressors {  // per sample interval: each linear parameter's regressor and the known part
    Eigen::MatrixXd lo, hi, mid;
  };

  void find_measured(const Recording& data);
  bool choose_order();
  bool resolve_symbols(const std::string& f_text);
  bool resolve_one(const std::string& text, bool sampled, std::vector<std::pair<std::string, bool>>& todo);
  void compile(const std::string& f_text);
  void evaluate_sampled();
  void set_prevs(int k);
  std::string sampled_note() const;
  void estimate_noise_of_integrals(const ColumnNoise& noise);
  Eigen::VectorXd integrated_derivative(int w) const;
  void bind_sample_values(int w);
  void set_sample(int j, int combo);
  double eval(const Eigen::VectorXd& theta);
  std::vector<int> acting_parameters();
  int inertia_parameter(const std::vector<int>& acting);
  Regressors interval_regressors(int inertia, const std::vector<int>& linear, std::string& problem);
  void integrate(int w, int inertia, const std::vector<int>& linear, const Regressors& g, const Eigen::VectorXd& D,
                 EquationErrorRegression& res);

  const ModelFile& model_;
  const std::string state_;
  Simulator sim_;  // time, sample time and the same input errors as everywhere
  const int N_;
  const double Ts_;
  std::string problem_;
  std::map<std::string, Eigen::VectorXd> measured_;
  std::map<std::string, std::string> column_name_;    // measured output symbol -> its column
  std::map<std::string, std::string> derivative_of_;  // z -> measured p with p' = z
  int order_ = 0;
  const Eigen::VectorXd* integrated_ = nullptr;  // x (order 1) or p with p' = x (order 2)
  std::map<std::string, int> kind_;  // 0 time, 1 parameter, 2 measured, 3 differentiated, 5 sampled
  std::set<std::string> needed_signals_, needed_sampled_, differentiated_;
  std::map<std::string, Eigen::VectorXd> at_sample_;  // measured symbols at the samples, then sampled signals
  std::set<std::string> known_at_start_;              // inputs and states: prev() at sample 0 is their value
  std::vector<Prev_reference> prevs_;                 // prev(x, n) of the equation, its signals and sampled signals
  std::vector<std::pair<double*, mu::Parser>> sampled_;  // needed sampled signals, model order
  std::map<std::string, double> vars_;  // node addresses are stable
  std::vector<std::pair<double*, mu::Parser>> signals_;
  mu::Parser f_;
  std::map<std::string, double> sigma_of_;
  Eigen::VectorXd theta_hat_;
  std::vector<double> scale_;
  int combos_ = 1;  // 3^(differentiated states): low, centre and high of each estimate
  int wv_ = 1;      // half-width of the central difference (samples)
  std::vector<Measured> measured_at_;
  std::vector<std::pair<double*, const Eigen::VectorXd*>> sampled_at_;  // held over each interval
  struct PastAt {  // prev(x, n): where it goes, x at the samples, n, and whether x is known at sample 0
    double* at;
    const Eigen::VectorXd* x;
    int lag;
    bool known_at_start;
  };
  std::vector<PastAt> prev_at_;
  std::vector<Differentiated> dz_at_;
  std::vector<double*> parameter_at_;
  double* t_at_ = nullptr;
  double* ts_at_ = nullptr;
};

// Measured symbols: inputs, and every model symbol compared with a column; unmeasured states that
// are the derivative of a measured one (q' = v, q measured) are estimated by central differences.
void EquationRegression::find_measured(const Recording& data) {
  for (const auto& [sym, col] : model_.inputs) {
    // An input that is not held enters each interval at its midpoint value (the midpoint rule, as the states).
    const Intersample mode = declared_intersample(model_, sym);
    const std::vector<double> mid = input_between_samples(data.column(col), mode, 0.5);
    measured_[sym] = Eigen::Map<const Eigen::VectorXd>(mid.data(), static_cast<Eigen::Index>(mid.size()));
    const std::vector<double> at = input_between_samples(data.column(col), mode, 0.0);
    at_sample_[sym] = Eigen::Map<const Eigen::VectorXd>(at.data(), static_cast<Eigen::Index>(at.size()));
    known_at_start_.insert(sym);
  }
  for (const auto& [sym, col] : model_.outputs)
    measured_[sym] = at_sample_[sym] = column_of(data, col), column_name_[sym] = col;
  for (const auto& s : model_.states) known_at_start_.insert(s.name);
  for (const auto& s : model_.states)
    if (measured_.count(s.name))
      if (const std::string* d = model_.derivative(s.name)) {
        const std::string z = trimmed(*d);
        bool is_state = false;
        for (const auto& s2 : model_.states) is_state = is_state || s2.name == z;
        if (is_state && !measured_.count(z)) derivative_of_[z] = s.name;
      }
}

bool EquationRegression::choose_order() {
  if (measured_.count(state_)) {
    order_ = 1;
    integrated_ = &measured_[state_];
  } else if (derivative_of_.count(state_)) {
    order_ = 2;
    integrated_ = &measured_[derivative_of_[state_]];
  } else {
    problem_ = "the state is neither measured nor the derivative of a measured state";
    return false;
  }
  return true;
}

// Which symbols the equation needs (through its signals and sampled signals), and whether each
// one is available.
bool EquationRegression::resolve_symbols(const std::string& f_text) {
  kind_["t"] = 0;
  kind_["Ts"] = 0;
  for (const auto& p : model_.parameters) kind_[p.name] = 1;
  for (const auto& [sym, v] : measured_) kind_[sym] = 2;
  for (const auto& [z, p] : derivative_of_) kind_[z] = 3;
  std::vector<std::pair<std::string, bool>> todo{{f_text, false}};  // text, is a sampled signal's
  while (!todo.empty()) {
    const auto [text, sampled] = todo.back();
    todo.pop_back();
    if (!resolve_one(text, sampled, todo)) return false;
  }
  if (differentiated_.size() > 3) {
    problem_ = "more than three differentiated states";
    return false;
  }
  return true;
}

// One text: a past (prev) must be measured or a sampled signal's; a sampled signal is evaluated
// once, sample by sample, so it may use only what is known at the samples (measured symbols,
// other sampled signals, fixed parameters): a free parameter would change its whole history.
bool EquationRegression::resolve_one(const std::string& text, bool sampled, std::vector<std::pair<std::string, bool>>& todo) {
  const auto e = check_expression(text, [](const std::string&) { return true; }, "equation");
  auto is_sampled = [&](const std::string& s) {
    for (const auto& [name, expr] : model_.sampled)
      if (name == s) return true;
    return false;
  };
  auto need_sampled = [&](const std::string& s) {
    kind_[s] = 5;
    if (!needed_sampled_.insert(s).second) return;
    for (const auto& [name, expr] : model_.sampled)
      if (name == s) todo.emplace_back(expr, true);
  };
  for (const auto& pr : e.prevs) {
    const auto k = kind_.find(pr.symbol);
    const bool known = k != kind_.end() && (k->second == 2 || k->second == 5);
    if (!known && !is_sampled(pr.symbol)) {
      problem_ = "the past prev(" + pr.symbol + ", " + std::to_string(pr.lag) + ") is neither measured nor computable from measurements";
      return false;
    }
    if (!known) need_sampled(pr.symbol);
    if (std::none_of(prevs_.begin(), prevs_.end(), [&](const Prev_reference& q) { return q.variable == pr.variable; }))
      prevs_.push_back(pr);
  }
  for (const auto& s : e.symbols) {
    const auto k = kind_.find(s);
    if (k != kind_.end()) {
      if (sampled && (k->second == 3 || k->second == 4)) {
        problem_ = "a sampled signal uses \"" + s + "\", which is not measured at the samples";
        return false;
      }
      if (sampled && k->second == 1 && !model_.parameter(s)->fixed) {
        problem_ = "a sampled signal depends on the free parameter \"" + s + "\" through its history";
        return false;
      }
      if (k->second == 3) differentiated_.insert(s);
      continue;
    }
    if (is_sampled(s)) {
      need_sampled(s);
      continue;
    }
    bool found = false;
    for (const auto& [name, expr] : model_.signals)
      if (name == s && !sampled) {
        found = true;
        kind_[s] = 4;
        if (needed_signals_.insert(s).second) todo.emplace_back(expr, false);
      }
    if (!found) {
      problem_ = "\"" + s + "\" is neither measured nor computable from measurements";
      return false;
    }
  }
  return true;
}

// The right-hand side evaluated from measured values (muparser, like the simulator).
void EquationRegression::compile(const std::string& f_text) {
  for (const auto& [s, k] : kind_) vars_[s] = 0;
  for (const auto& s : needed_signals_) vars_[s] = 0;
  auto compile_one = [&](mu::Parser& p, const std::string& text) {
    compile_expression(p, check_expression(text, [](const std::string&) { return true; }, "equation"),
                       [&](const std::string& s) { return &vars_[s]; });
  };
  signals_.reserve(model_.signals.size());  // compiled parsers are not moved afterwards
  for (const auto& [name, expr] : model_.signals)
    if (needed_signals_.count(name)) {
      signals_.emplace_back(&vars_[name], mu::Parser());
      compile_one(signals_.back().second, expr);
    }
  sampled_.reserve(model_.sampled.size());
  for (const auto& [name, expr] : model_.sampled)
    if (needed_sampled_.count(name)) {
      sampled_.emplace_back(&vars_[name], mu::Parser());
      compile_one(sampled_.back().second, expr);
    }
  compile_one(f_, f_text);
  theta_hat_.resize(static_cast<Eigen::Index>(model_.parameters.size()));
  for (std::size_t i = 0; i < model_.parameters.size(); ++i) {
    theta_hat_[static_cast<Eigen::Index>(i)] = model_.parameters[i].value;
    parameter_at_.push_back(&vars_[model_.parameters[i].name]);
  }
  scale_.resize(model_.parameters.size());
  for (std::size_t i = 0; i < scale_.size(); ++i)
    scale_[i] = std::abs(theta_hat_[static_cast<Eigen::Index>(i)]) > 0 ? std::abs(theta_hat_[static_cast<Eigen::Index>(i)]) : 1.0;
  for (const auto& [s, v] : measured_) {
    bool is_state = false;
    for (const auto& st : model_.states) is_state = is_state || st.name == s;
    measured_at_.push_back({&vars_[s], &v, is_state});
  }
  t_at_ = &vars_["t"];
  ts_at_ = &vars_["Ts"];
  for (std::size_t i = 0; i < differentiated_.size(); ++i) combos_ *= 3;
  evaluate_sampled();
  for (const auto& s : needed_sampled_) sampled_at_.emplace_back(&vars_[s], &at_sample_[s]);
}

// The past prev(x, n) as the simulator gives it before sample interval k: x at sample k - n, or
// at sample 0 (an input's or a state's value there; a sampled signal's own past is 0).
void EquationRegression::set_prevs(int k) {
  for (const auto& p : prev_at_) {
    const int kk = std::max(0, k - p.lag);
    *p.at = kk < k || p.known_at_start ? (*p.x)[kk] : 0.0;
  }
}

// The needed sampled signals, once, in time order as the simulator evaluates them: from the
// measured symbols at each sample (inputs held, measured states and outputs as measured), their
// own past included; every parameter they use is fixed (resolve_one).
void EquationRegression::evaluate_sampled() {
  for (const auto& s : needed_sampled_) at_sample_[s] = Eigen::VectorXd::Zero(N_);
  for (const auto& pr : prevs_)
    prev_at_.push_back({&vars_[pr.variable], &at_sample_.at(pr.symbol), pr.lag, known_at_start_.count(pr.symbol) > 0});
  if (sampled_.empty()) return;
  for (std::size_t i = 0; i < parameter_at_.size(); ++i) *parameter_at_[i] = theta_hat_[static_cast<Eigen::Index>(i)];
  *ts_at_ = Ts_;
  for (int k = 0; k < N_; ++k) {
    *t_at_ = sim_.time()[static_cast<std::size_t>(k)];
    for (const auto& [sym, v] : at_sample_)
      if (kind_.count(sym) && kind_.at(sym) == 2) vars_[sym] = v[k];
    set_prevs(k);
    for (auto& [slot, p] : sampled_) *slot = p.Eval();
    for (const auto& s : needed_sampled_) at_sample_[s][k] = vars_[s];
  }
}

// The noise of each differentiated state's measured integral, once for every window (only the
// radius of the central difference depends on the window), or the caller's for its column.
void EquationRegression::estimate_noise_of_integrals(const ColumnNoise& noise) {
  for (const auto& z : differentiated_) {
    const auto known = noise.find(column_name_[derivative_of_[z]]);
    sigma_of_[z] = known != noise.end() ? known->second : estimate_noise(measured_[derivative_of_[z]]).sigma;
  }
}

// The integrated derivative over the window, exact in measurements.
Eigen::VectorXd EquationRegression::integrated_derivative(int w) const {
  Eigen::VectorXd D = Eigen::VectorXd::Zero(N_);
  const Eigen::VectorXd& x = *integrated_;
  if (order_ == 1)
    for (int t = w; t < N_; ++t) D[t] = x[t] - x[t - w];
  else
    for (int t = 2 * w; t < N_; ++t) D[t] = x[t] - 2 * x[t - w] + x[t - 2 * w];
  return D;
}

// Each differentiated state: a central difference over +-wv samples of its measured integral,
// with a noise radius rho (3 sigma of that estimate).
void EquationRegression::bind_sample_values(int w) {
  wv_ = std::max(1, w / 4);
  dz_at_.clear();
  for (const auto& z : differentiated_) {
    const Eigen::VectorXd& p = measured_[derivative_of_[z]];
    Eigen::VectorXd v(N_);
    for (int j = 0; j < N_; ++j) {
      const int a = std::max(0, j - wv_), b = std::min(N_ - 1, j + wv_);
      v[j] = (p[b] - p[a]) / ((b - a) * Ts_);
    }
    dz_at_.push_back({&vars_[z], v, 3 * sigma_of_[z] / (std::sqrt(2.0) * wv_ * Ts_)});
  }
}

// Sample interval j (from t_j to t_j+1): held signals at j, states at the interval's midpoint,
// each differentiated state anywhere in its estimate +- rho (combination `combo`).
void EquationRegression::set_sample(int j, int combo) {
  const int j1 = std::min(j + 1, N_ - 1);
  *t_at_ = sim_.time()[static_cast<std::size_t>(j)] + 0.5 * Ts_;
  *ts_at_ = Ts_;
  for (const auto& m : measured_at_) *m.at = m.is_state ? 0.5 * ((*m.v)[j] + (*m.v)[j1]) : (*m.v)[j];
  for (const auto& [at, v] : sampled_at_) *at = (*v)[j];
  set_prevs(j);
  int c = combo;
  for (const auto& z : dz_at_) {
    *z.at = 0.5 * (z.zhat[j] + z.zhat[j1]) + (c % 3 - 1) * z.rho;
    c /= 3;
  }
}

double EquationRegression::eval(const Eigen::VectorXd& theta) {
  for (std::size_t i = 0; i < parameter_at_.size(); ++i) *parameter_at_[i] = theta[static_cast<Eigen::Index>(i)];
  for (auto& [slot, p] : signals_) *slot = p.Eval();
  return f_.Eval();
}

std::vector<int> probe_samples(int N) {
  std::vector<int> out;
  for (int s = 0; s < 40; ++s) out.push_back(static_cast<int>((static_cast<long>(N - 2) * (2 * s + 1)) / 80));
  return out;
}

// The free parameters whose change moves the right-hand side at some probe sample.
std::vector<int> EquationRegression::acting_parameters() {
  std::vector<int> acting;
  for (std::size_t i = 0; i < model_.parameters.size(); ++i) {
    if (model_.parameters[i].fixed) continue;
    Eigen::VectorXd th = theta_hat_;
    th[static_cast<Eigen::Index>(i)] += 0.5 * scale_[i];
    bool acts = false;
    for (int j : probe_samples(N_)) {
      set_sample(j, combos_ / 2);
      const double g0 = eval(theta_hat_), g1 = eval(th);
      acts = acts || g0 != g1;
    }
    if (acts) acting.push_back(static_cast<int>(i));
  }
  return acting;
}

// Is inertia * f affine in the other acting parameters, for no inertia (-1) or one of them? The
// first that is, or -2 for none: second differences and cross differences vanish at the probes.
int EquationRegression::inertia_parameter(const std::vector<int>& acting) {
  for (int c = -1; c < static_cast<int>(acting.size()); ++c) {
    const int ci = c < 0 ? -1 : acting[static_cast<std::size_t>(c)];
    auto g = [&](const Eigen::VectorXd& th) { return (ci < 0 ? 1.0 : th[ci]) * eval(th); };
    bool ok = ci < 0 || theta_hat_[ci] != 0;
    for (int j : probe_samples(N_)) {
      if (!ok) break;
      set_sample(j, combos_ / 2);
      const double g0 = g(theta_hat_);
      double mag = std::abs(g0), worst = 0;
      if (ci >= 0) {
        Eigen::VectorXd th = theta_hat_;
        th[ci] *= 1.7;
        worst = std::max(worst, std::abs(g(th) - g0));
      }
      for (int k : acting) {
        if (k == ci) continue;
        const double hk = 0.5 * scale_[static_cast<std::size_t>(k)];
        Eigen::VectorXd t1 = theta_hat_, t2 = theta_hat_;
        t1[k] += hk;
        t2[k] += 2 * hk;
        const double g1 = g(t1), g2 = g(t2);
        mag = std::max({mag, std::abs(g1), std::abs(g2)});
        worst = std::max(worst, std::abs(g2 - 2 * g1 + g0));
        for (int l : acting) {
          if (l <= k || l == ci) continue;
          Eigen::VectorXd t3 = t1, t4 = theta_hat_;
          t3[l] += 0.5 * scale_[static_cast<std::size_t>(l)];
          t4[l] += 0.5 * scale_[static_cast<std::size_t>(l)];
          worst = std::max(worst, std::abs(g(t3) - g1 - g(t4) + g0));
        }
      }
      ok = worst <= 1e-8 * (mag + 1e-300);
    }
    if (ok) return ci;
  }
  return -2;
}

// Per sample interval: the regressor of each linear parameter and the known part, as the hull
// over the differentiated states' boxes, and their values at the estimates (centre). Sets
// `problem` when the equation is not finite somewhere.
EquationRegression::Regressors EquationRegression::interval_regressors(int inertia, const std::vector<int>& linear,
                                                                       std::string& problem) {
  const auto nl = static_cast<Eigen::Index>(linear.size());
  Regressors g{Eigen::MatrixXd(N_, nl + 1), Eigen::MatrixXd(N_, nl + 1), Eigen::MatrixXd(N_, nl + 1)};  // column nl: c0
  for (int j = 0; j < N_ - 1; ++j) {
    for (int combo = 0; combo < combos_; ++combo) {
      set_sample(j, combo);
      const double gi = inertia < 0 ? 1.0 : theta_hat_[inertia];
      const double g0 = gi * eval(theta_hat_);
      Eigen::VectorXd c(nl + 1);
      double known = g0;
      for (Eigen::Index k = 0; k < nl; ++k) {
        const int pk = linear[static_cast<std::size_t>(k)];
        Eigen::VectorXd th = theta_hat_;
        th[pk] += scale_[static_cast<std::size_t>(pk)];
        c[k] = (gi * eval(th) - g0) / scale_[static_cast<std::size_t>(pk)];
        known -= theta_hat_[pk] * c[k];
      }
      c[nl] = known;
      if (!c.allFinite()) {
        problem = "the equation is not finite at t = " + std::to_string(sim_.time()[static_cast<std::size_t>(j)]) + " s";
        return g;
      }
      if (combo == 0) g.lo.row(j) = g.hi.row(j) = c.transpose();
      g.lo.row(j) = g.lo.row(j).cwiseMin(c.transpose());
      g.hi.row(j) = g.hi.row(j).cwiseMax(c.transpose());
      if (combo == combos_ / 2) g.mid.row(j) = c.transpose();
    }
  }
  return g;
}

// The regressors integrated over the window before each strip's end t (kernel: the box of length
// T = w Ts for order 1 or the triangle of two boxes for order 2, exact over each interval):
// theta_c D - sum theta_k I[c_k] = I[c0]  (theta_c = 1 without an inertia parameter).
void EquationRegression::integrate(int w, int inertia, const std::vector<int>& linear, const Regressors& g,
                                   const Eigen::VectorXd& D, EquationErrorRegression& res) {
  const auto nl = static_cast<Eigen::Index>(linear.size());
  std::vector<double> K;
  if (order_ == 1) {
    K.assign(static_cast<std::size_t>(w), Ts_);
  } else {
    for (int d = 0; d < 2 * w; ++d) K.push_back((d < w ? d + 0.5 : 2 * w - d - 0.5) * Ts_ * Ts_);
  }
  const int span = static_cast<int>(K.size()), first = order_ * w, step = std::max(1, w / 2);
  std::vector<int> rows;
  for (int t = first; t < N_; t += step) rows.push_back(t);
  const auto m = static_cast<Eigen::Index>(rows.size());
  const Eigen::Index p = nl + (inertia >= 0 ? 1 : 0);
  IntervalMatrix Phi(m, p);
  IntervalVector Y(m);
  Eigen::VectorXd resid(m);
  for (Eigen::Index r = 0; r < m; ++r) {
    const int t = rows[static_cast<std::size_t>(r)];
    const int j0 = t - order_ * w;  // the kernel covers intervals j0 .. t - 1
    std::vector<Interval> acc(static_cast<std::size_t>(nl + 1));
    {
      // One rounding-mode switch for the whole sum instead of a save, set and restore per
      // operation (every screened hypothesis builds these sums); the bounds are the same.
      RoundingScope upward;
      for (Eigen::Index k = 0; k <= nl; ++k) {
        UnprotectedInterval a(0.0);
        for (int d = 0; d < span; ++d)
          a += UnprotectedInterval(K[static_cast<std::size_t>(d)]) * UnprotectedInterval(g.lo(j0 + d, k), g.hi(j0 + d, k));
        acc[static_cast<std::size_t>(k)] = a;
      }
    }
    Eigen::VectorXd accm = Eigen::VectorXd::Zero(nl + 1);  // round to nearest again
    for (int d = 0; d < span; ++d)
      for (Eigen::Index k = 0; k <= nl; ++k) accm[k] += K[static_cast<std::size_t>(d)] * g.mid(j0 + d, k);
    Eigen::Index col = 0;
    double e = -accm[nl];
    if (inertia >= 0) {
      Phi(r, col++) = Interval(D[t]);
      e += theta_hat_[inertia] * D[t];
    }
    for (Eigen::Index k = 0; k < nl; ++k) {
      Phi(r, col++) = -acc[static_cast<std::size_t>(k)];
      e -= theta_hat_[linear[static_cast<std::size_t>(k)]] * accm[k];
    }
    Y[r] = acc[static_cast<std::size_t>(nl)] - (inertia >= 0 ? Interval(0.0) : Interval(D[t]));
    if (inertia < 0) e += D[t];
    resid[r] = e;
  }
  res.Phi = Phi;
  res.Y = Y;
  res.Phi_mid.resize(m, p);
  res.Y_mid.resize(m);
  for (Eigen::Index r = 0; r < m; ++r) {
    for (Eigen::Index c = 0; c < p; ++c) res.Phi_mid(r, c) = midpoint(Phi(r, c));
    res.Y_mid[r] = midpoint(Y[r]);
  }
  res.residual = resid;
  res.rows = static_cast<int>(m);
}

// What the sampled signals and pasts rest on: measured values at the samples, whose noise is
// then part of the equation error the bound covers.
std::string EquationRegression::sampled_note() const {
  if (needed_sampled_.empty() && prevs_.empty()) return "";
  std::string names;
  for (const auto& s : needed_sampled_) names += (names.empty() ? "" : ", ") + s;
  for (const auto& p : prevs_) names += (names.empty() ? "prev(" : ", prev(") + p.symbol + ", " + std::to_string(p.lag) + ")";
  return "; " + names + " evaluated sample by sample from the measured inputs and states (as measured: their noise is part of the equation error)";
}

EquationErrorRegression EquationRegression::build(int w) {
  EquationErrorRegression res;
  auto fail = [&](const std::string& why) {
    res.note = "equation-error regression not built for \"" + state_ + "\": " + why;
    return res;
  };
  const Eigen::VectorXd D = integrated_derivative(w);
  bind_sample_values(w);
  try {
    const std::vector<int> acting = acting_parameters();
    if (acting.empty()) return fail("no free parameter acts on the equation");
    const int inertia = inertia_parameter(acting);
    if (inertia == -2) return fail("its free parameters do not enter linearly (not even after multiplying by one of them)");
    std::vector<int> linear;
    for (int k : acting)
      if (k != inertia) linear.push_back(k);
    std::string problem;
    const Regressors g = interval_regressors(inertia, linear, problem);
    if (!problem.empty()) return fail(problem);
    integrate(w, inertia, linear, g, D, res);
    res.built = true;
    res.from_samples = !needed_sampled_.empty() || !prevs_.empty();
    res.has_inertia = inertia >= 0;
    res.window = w;
    res.order = order_;
    std::vector<int> unknowns;
    if (inertia >= 0) unknowns.push_back(inertia);
    for (int k : linear) unknowns.push_back(k);
    for (int u : unknowns) {
      res.parameters.push_back(model_.parameters[static_cast<std::size_t>(u)].name);
      res.scale.push_back(scale_[static_cast<std::size_t>(u)]);
    }
    std::string dnote;
    std::size_t i = 0;
    for (const auto& z : differentiated_)
      dnote += ", " + z + " = d" + derivative_of_[z] + "/dt +- " + std::to_string(dz_at_[i++].rho);
    res.note = "integrated " + std::to_string(order_) + "x over " + std::to_string(w) + " samples, " +
               std::to_string(res.rows) + " strips" + dnote +
               (differentiated_.empty() ? "" : " (3 sigma of the central difference over +-" + std::to_string(wv_) + " samples)") +
               sampled_note();
  } catch (const mu::Parser::exception_type& e) {
    return fail("expression evaluation failed: " + e.GetMsg());
  }
  return res;
}

}  // namespace

std::vector<EquationErrorRegression> equation_error_regressions(const ModelFile& model, const Recording& data,
                                                               const std::string& state, const std::vector<int>& windows,
                                                               const ColumnNoise& noise) {
  EquationRegression regression(model, data, state, noise);
  if (!regression.problem().empty()) {
    EquationErrorRegression res;
    res.note = "equation-error regression not built for \"" + state + "\": " + regression.problem();
    return {res};
  }
  std::vector<EquationErrorRegression> out;
  for (int w : windows) {
    if (w < 1 || regression.samples() < 8 * w) {
      EquationErrorRegression r;
      r.note = "equation-error regression not built for \"" + state + "\": the record is too short for a window of " +
               std::to_string(w) + " samples";
      out.push_back(r);
      continue;
    }
    out.push_back(regression.build(w));
  }
  return out;
}

std::vector<int> equation_error_windows(int N) {
  // Windows from N/500 to N/25 samples: short windows keep more of the record's detail, long ones
  // average the measurement noise of the differences.
  std::vector<int> windows;
  for (int div : {500, 200, 100, 50, 25}) {
    const int w = std::clamp(N / div, 4, 500);
    if (N >= 8 * w && std::find(windows.begin(), windows.end(), w) == windows.end()) windows.push_back(w);
  }
  return windows;
}

EquationErrorResult equation_error_pui(const ModelFile& model, const Recording& data, const std::string& state,
                                       const EquationErrorOptions& options) {
  EquationErrorResult res;
  const std::vector<int> windows = options.window > 0 ? std::vector<int>{options.window} : equation_error_windows(data.rows());
  if (windows.empty()) {
    res.note = "equation-error PUI not built for \"" + state + "\": the record is too short for the integration window";
    return res;
  }
  // Each PUI holds under its own stated bound; the one with the smallest total relative width is
  // reported.
  double best = inf;
  for (const EquationErrorRegression& g : equation_error_regressions(model, data, state, windows)) {
    if (!g.built) {
      if (!res.built) res.note = g.note;
      continue;
    }
    const Eigen::Index m = g.Phi.rows(), p = g.Phi.cols();
    const double delta = std::max(options.bound_factor * g.residual.cwiseAbs().maxCoeff(), 1e-300);
    // Scaled unknowns z = theta / scale and rows in units of delta keep the LPs well conditioned.
    IntervalMatrix Phi = g.Phi;
    IntervalVector Y = g.Y;
    for (Eigen::Index r = 0; r < m; ++r) {
      for (Eigen::Index c = 0; c < p; ++c) Phi(r, c) = Phi(r, c) * Interval(g.scale[static_cast<std::size_t>(c)]) / Interval(delta);
      Y[r] = (Y[r] + Interval(-delta, delta)) / Interval(delta);
    }
    PuiOptions po;
    po.orthants = p <= 5 ? OrthantSelection::all : OrthantSelection::remark2;
    const PuiResult pr = pui(FeasibleParameterSet::from_interval_data(Phi, Y), po);
    if (pr.empty()) {
      if (!res.built)
        res.note = "equation-error PUI not built for \"" + state + "\": the strips are inconsistent under the bound (the model is falsified there)";
      continue;
    }
    EquationErrorResult r;
    r.built = true;
    r.guaranteed = pr.guaranteed;
    r.delta = delta;
    r.rows = g.rows;
    r.window = g.window;
    r.order = g.order;
    r.parameters = g.parameters;
    r.box.resize(p);
    double width = 0;
    for (Eigen::Index c = 0; c < p; ++c) {
      r.box[c] = pr.box[c] * Interval(g.scale[static_cast<std::size_t>(c)]);
      const double v = std::abs(model.parameter(g.parameters[static_cast<std::size_t>(c)])->value);
      width += (r.box[c].upper() - r.box[c].lower()) / (v > 0 ? v : 1.0);
    }
    std::ostringstream bf;
    bf << options.bound_factor;
    r.note = "equation-error PUI of \"" + state + "\": " + g.note + ", equation-error bound = " + bf.str() +
             " x its largest value at the estimate";
    if (!res.built || width < best) {
      best = width;
      res = r;
    }
  }
  if (res.built) res.note += "; windows tried: " + std::to_string(windows.size()) + ", the narrowest reported";
  return res;
}

EquationErrorFit equation_error_fit(const ModelFile& model, const Recording& data, const std::string& state, int window,
                                    const ColumnNoise& noise) {
  EquationErrorFit fit;
  const int w = window > 0 ? window : std::clamp(data.rows() / 200, 4, 500);
  const EquationErrorRegression g = equation_error_regressions(model, data, state, {w}, noise).front();
  fit.note = g.note;
  fit.from_samples = g.from_samples;
  if (!g.built) return fit;
  // Least squares in scaled unknowns; a homogeneous regression (nothing known on the right, an
  // inertia present) fixes the inertia at the model's value: the scale is not identifiable.
  Eigen::MatrixXd A = g.Phi_mid;
  Eigen::VectorXd y = g.Y_mid;
  for (Eigen::Index c = 0; c < A.cols(); ++c) A.col(c) *= g.scale[static_cast<std::size_t>(c)];
  Eigen::Index first = 0;
  if (g.has_inertia && y.norm() <= 1e-9 * A.col(0).norm()) {
    y -= A.col(0) * (model.parameter(g.parameters.front())->value / g.scale.front());
    first = 1;
  }
  const Eigen::MatrixXd Af = A.rightCols(A.cols() - first);
  if (Af.cols() == 0) return fit;
  const Eigen::VectorXd z = Af.completeOrthogonalDecomposition().solve(y);
  if (!z.allFinite()) return fit;
  fit.built = true;
  for (Eigen::Index c = 0; c < A.cols(); ++c) {
    fit.parameters.push_back(g.parameters[static_cast<std::size_t>(c)]);
    fit.estimate.push_back(c < first ? model.parameter(g.parameters.front())->value
                                     : z[c - first] * g.scale[static_cast<std::size_t>(c)]);
  }
  const double yy = (y.array() - y.mean()).matrix().squaredNorm();
  fit.relative_residual = yy > 0 ? std::sqrt((y - Af * z).squaredNorm() / yy) : 0.0;
  return fit;
}

}  // namespace sets
