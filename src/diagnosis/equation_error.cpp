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

// The model symbols an expression uses (the Simulator built before has checked every expression).
std::set<std::string> used_symbols(const std::string& text) {
  const auto e = check_expression(text, [](const std::string&) { return true; }, "equation");
  return {e.symbols.begin(), e.symbols.end()};
}

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

std::vector<EquationErrorRegression> equation_error_regressions(const ModelFile& model, const Recording& data,
                                                               const std::string& state, const std::vector<int>& windows,
                                                               const ColumnNoise* noise) {
  std::vector<EquationErrorRegression> out;
  auto fail = [&](const std::string& why) {
    EquationErrorRegression res;
    res.note = "equation-error regression not built for \"" + state + "\": " + why;
    return std::vector<EquationErrorRegression>{res};
  };
  const std::string* f_text = model.derivative(state);
  if (!f_text) return fail("not a state equation");
  Simulator sim(model, data, {1});  // time, sample time and the same input errors as everywhere
  const int N = sim.samples();
  const double Ts = sim.sample_time();

  // Measured symbols: inputs, and every model symbol compared with a column.
  std::map<std::string, Eigen::VectorXd> measured;
  auto column = [&](const std::string& c) { return column_of(data, c); };
  for (const auto& [sym, col] : model.inputs) {
    // An input that is not held enters each interval at its midpoint value (the midpoint rule, as the states).
    const Intersample mode = declared_intersample(model, sym);
    const std::vector<double> mid = input_between_samples(data.column(col), mode, 0.5);
    measured[sym] = Eigen::Map<const Eigen::VectorXd>(mid.data(), static_cast<Eigen::Index>(mid.size()));
  }
  std::map<std::string, std::string> column_name;  // measured output symbol -> its column
  for (const auto& [sym, col] : model.outputs) measured[sym] = column(col), column_name[sym] = col;
  // Unmeasured states that are the derivative of a measured one (q' = v, q measured): estimated by
  // a central difference over +-wv samples, with a noise radius rho (3 sigma of that estimate).
  std::map<std::string, std::string> derivative_of;  // z -> measured p with p' = z
  for (const auto& s : model.states)
    if (measured.count(s.name))
      if (const std::string* d = model.derivative(s.name)) {
        const std::string z = trimmed(*d);
        bool is_state = false;
        for (const auto& s2 : model.states) is_state = is_state || s2.name == z;
        if (is_state && !measured.count(z)) derivative_of[z] = s.name;
      }
  int order = 0;
  const Eigen::VectorXd* integrated = nullptr;  // x (order 1) or p with p' = x (order 2)
  if (measured.count(state)) {
    order = 1;
    integrated = &measured[state];
  } else if (derivative_of.count(state)) {
    order = 2;
    integrated = &measured[derivative_of[state]];
  } else {
    return fail("the state is neither measured nor the derivative of a measured state");
  }

  // Which symbols the equation needs (through its signals), and whether each one is available.
  std::map<std::string, int> kind;  // 0 time, 1 parameter, 2 measured, 3 differentiated, 4 signal
  kind["t"] = 0;
  kind["Ts"] = 0;
  for (const auto& p : model.parameters) kind[p.name] = 1;
  for (const auto& [sym, v] : measured) kind[sym] = 2;
  for (const auto& [z, p] : derivative_of) kind[z] = 3;
  std::set<std::string> needed_signals, differentiated;
  std::vector<std::string> todo{*f_text};
  while (!todo.empty()) {
    const std::string text = todo.back();
    todo.pop_back();
    if (text.find("prev") != std::string::npos) return fail("the equation uses prev()");
    for (const auto& s : used_symbols(text)) {
      if (kind.count(s)) {
        if (kind[s] == 3) differentiated.insert(s);
        continue;
      }
      bool found = false;
      for (const auto& [name, expr] : model.signals)
        if (name == s) {
          found = true;
          if (needed_signals.insert(s).second) todo.push_back(expr);
        }
      if (!found) return fail("\"" + s + "\" is neither measured nor computable from measurements");
    }
  }
  if (differentiated.size() > 3) return fail("more than three differentiated states");

  // Evaluation of the equation's right-hand side from measured values (muparser, like the simulator).
  std::map<std::string, double> vars;  // node addresses are stable
  for (const auto& [s, k] : kind) vars[s] = 0;
  for (const auto& s : needed_signals) vars[s] = 0;
  auto compile = [&](mu::Parser& p, const std::string& text) {
    compile_expression(p, check_expression(text, [](const std::string&) { return true; }, "equation"),
                       [&](const std::string& s) { return &vars[s]; });
  };
  std::vector<std::pair<double*, mu::Parser>> signals;
  signals.reserve(model.signals.size());  // compiled parsers are not moved afterwards
  for (const auto& [name, expr] : model.signals)
    if (needed_signals.count(name)) {
      signals.emplace_back(&vars[name], mu::Parser());
      compile(signals.back().second, expr);
    }
  mu::Parser f;
  compile(f, *f_text);

  // The noise of each differentiated state's measured integral, once for every window (only the
  // radius of the central difference depends on the window), or the caller's for its column.
  std::map<std::string, double> sigma_of;
  for (const auto& z : differentiated) {
    const auto known = noise ? noise->find(column_name[derivative_of[z]]) : ColumnNoise::const_iterator();
    sigma_of[z] = noise && known != noise->end() ? known->second : estimate_noise(measured[derivative_of[z]]).sigma;
  }

  // One regression per integration window w (samples).
  auto attempt = [&](int w) -> EquationErrorRegression {
  EquationErrorRegression res;
  auto fail = [&](const std::string& why) {
    res.note = "equation-error regression not built for \"" + state + "\": " + why;
    return res;
  };
  Eigen::VectorXd D = Eigen::VectorXd::Zero(N);  // the integrated derivative, exact in measurements
  {
    const Eigen::VectorXd& x = *integrated;
    if (order == 1)
      for (int t = w; t < N; ++t) D[t] = x[t] - x[t - w];
    else
      for (int t = 2 * w; t < N; ++t) D[t] = x[t] - 2 * x[t - w] + x[t - 2 * w];
  }
  const int wv = std::max(1, w / 4);
  std::map<std::string, Eigen::VectorXd> zhat;
  std::map<std::string, double> rho;
  for (const auto& z : differentiated) {
    const Eigen::VectorXd& p = measured[derivative_of[z]];
    Eigen::VectorXd v(N);
    for (int j = 0; j < N; ++j) {
      const int a = std::max(0, j - wv), b = std::min(N - 1, j + wv);
      v[j] = (p[b] - p[a]) / ((b - a) * Ts);
    }
    zhat[z] = v;
    rho[z] = 3 * sigma_of[z] / (std::sqrt(2.0) * wv * Ts);
  }
  // Sample interval j (from t_j to t_j+1): held signals at j, states at the interval's midpoint,
  // each differentiated state anywhere in its estimate +- rho (combination `combo`).
  const std::vector<std::string> dz(differentiated.begin(), differentiated.end());
  int combos = 1;
  for (std::size_t i = 0; i < dz.size(); ++i) combos *= 3;
  // Where each symbol's value goes, looked up once (the loops below run per sample and parameter).
  struct Measured {
    double* at;
    const Eigen::VectorXd* v;
    bool is_state;
  };
  std::vector<Measured> measured_at;
  for (const auto& [s, v] : measured) {
    bool is_state = false;
    for (const auto& st : model.states) is_state = is_state || st.name == s;
    measured_at.push_back({&vars[s], &v, is_state});
  }
  struct Differentiated {
    double* at;
    const Eigen::VectorXd* zhat;
    double rho;
  };
  std::vector<Differentiated> dz_at;
  for (const auto& z : dz) dz_at.push_back({&vars[z], &zhat[z], rho[z]});
  double* const t_at = &vars["t"];
  double* const ts_at = &vars["Ts"];
  std::vector<double*> parameter_at;
  for (const auto& p : model.parameters) parameter_at.push_back(&vars[p.name]);
  auto set_sample = [&](int j, int combo) {
    const int j1 = std::min(j + 1, N - 1);
    *t_at = sim.time()[static_cast<std::size_t>(j)] + 0.5 * Ts;
    *ts_at = Ts;
    for (const auto& m : measured_at) *m.at = m.is_state ? 0.5 * ((*m.v)[j] + (*m.v)[j1]) : (*m.v)[j];
    int c = combo;
    for (const auto& z : dz_at) {
      *z.at = 0.5 * ((*z.zhat)[j] + (*z.zhat)[j1]) + (c % 3 - 1) * z.rho;
      c /= 3;
    }
  };
  const Eigen::VectorXd theta_hat = [&] {
    Eigen::VectorXd p(static_cast<Eigen::Index>(model.parameters.size()));
    for (std::size_t i = 0; i < model.parameters.size(); ++i) p[static_cast<Eigen::Index>(i)] = model.parameters[i].value;
    return p;
  }();
  auto eval = [&](const Eigen::VectorXd& theta) {
    for (std::size_t i = 0; i < parameter_at.size(); ++i) *parameter_at[i] = theta[static_cast<Eigen::Index>(i)];
    for (auto& [slot, p] : signals) *slot = p.Eval();
    return f.Eval();
  };
  std::vector<double> scale(model.parameters.size());
  for (std::size_t i = 0; i < scale.size(); ++i)
    scale[i] = std::abs(theta_hat[static_cast<Eigen::Index>(i)]) > 0 ? std::abs(theta_hat[static_cast<Eigen::Index>(i)]) : 1.0;

  try {
    // Which free parameters act on the equation, and is inertia * f affine in the others?
    std::vector<int> probe_samples;
    for (int s = 0; s < 40; ++s) probe_samples.push_back(static_cast<int>((static_cast<long>(N - 2) * (2 * s + 1)) / 80));
    std::vector<int> acting;
    for (std::size_t i = 0; i < model.parameters.size(); ++i) {
      if (model.parameters[i].fixed) continue;
      Eigen::VectorXd th = theta_hat;
      th[static_cast<Eigen::Index>(i)] += 0.5 * scale[i];
      bool acts = false;
      for (int j : probe_samples) {
        set_sample(j, combos / 2);
        const double g0 = eval(theta_hat), g1 = eval(th);
        acts = acts || g0 != g1;
      }
      if (acts) acting.push_back(static_cast<int>(i));
    }
    if (acting.empty()) return fail("no free parameter acts on the equation");
    int inertia = -2;
    for (int c = -1; c < static_cast<int>(acting.size()) && inertia == -2; ++c) {
      const int ci = c < 0 ? -1 : acting[static_cast<std::size_t>(c)];
      auto g = [&](const Eigen::VectorXd& th) { return (ci < 0 ? 1.0 : th[ci]) * eval(th); };
      bool ok = ci < 0 || theta_hat[ci] != 0;
      for (int j : probe_samples) {
        if (!ok) break;
        set_sample(j, combos / 2);
        const double g0 = g(theta_hat);
        double mag = std::abs(g0), worst = 0;
        if (ci >= 0) {
          Eigen::VectorXd th = theta_hat;
          th[ci] *= 1.7;
          worst = std::max(worst, std::abs(g(th) - g0));
        }
        for (int k : acting) {
          if (k == ci) continue;
          const double hk = 0.5 * scale[static_cast<std::size_t>(k)];
          Eigen::VectorXd t1 = theta_hat, t2 = theta_hat;
          t1[k] += hk;
          t2[k] += 2 * hk;
          const double g1 = g(t1), g2 = g(t2);
          mag = std::max({mag, std::abs(g1), std::abs(g2)});
          worst = std::max(worst, std::abs(g2 - 2 * g1 + g0));
          for (int l : acting) {
            if (l <= k || l == ci) continue;
            Eigen::VectorXd t3 = t1, t4 = theta_hat;
            t3[l] += 0.5 * scale[static_cast<std::size_t>(l)];
            t4[l] += 0.5 * scale[static_cast<std::size_t>(l)];
            worst = std::max(worst, std::abs(g(t3) - g1 - g(t4) + g0));
          }
        }
        ok = worst <= 1e-8 * (mag + 1e-300);
      }
      if (ok) inertia = ci;
    }
    if (inertia == -2) return fail("its free parameters do not enter linearly (not even after multiplying by one of them)");

    // Per sample interval: the regressor of each linear parameter and the known part, as the hull
    // over the differentiated states' boxes, and their values at the estimates (centre).
    std::vector<int> linear;
    for (int k : acting)
      if (k != inertia) linear.push_back(k);
    const auto nl = static_cast<Eigen::Index>(linear.size());
    Eigen::MatrixXd lo(N, nl + 1), hi(N, nl + 1), mid(N, nl + 1);  // column nl: the known part c0
    for (int j = 0; j < N - 1; ++j) {
      for (int combo = 0; combo < combos; ++combo) {
        set_sample(j, combo);
        const double gi = inertia < 0 ? 1.0 : theta_hat[inertia];
        const double g0 = gi * eval(theta_hat);
        Eigen::VectorXd c(nl + 1);
        double known = g0;
        for (Eigen::Index k = 0; k < nl; ++k) {
          const int pk = linear[static_cast<std::size_t>(k)];
          Eigen::VectorXd th = theta_hat;
          th[pk] += scale[static_cast<std::size_t>(pk)];
          c[k] = (gi * eval(th) - g0) / scale[static_cast<std::size_t>(pk)];
          known -= theta_hat[pk] * c[k];
        }
        c[nl] = known;
        if (!c.allFinite()) return fail("the equation is not finite at t = " + std::to_string(sim.time()[static_cast<std::size_t>(j)]) + " s");
        if (combo == 0) lo.row(j) = hi.row(j) = c.transpose();
        lo.row(j) = lo.row(j).cwiseMin(c.transpose());
        hi.row(j) = hi.row(j).cwiseMax(c.transpose());
        if (combo == combos / 2) mid.row(j) = c.transpose();
      }
    }
    // Integration kernel over the sample intervals before t: the box of length T = w Ts (order 1)
    // or the triangle of two boxes (order 2), integrated exactly over each interval.
    std::vector<double> K;
    if (order == 1) {
      K.assign(static_cast<std::size_t>(w), Ts);
    } else {
      for (int d = 0; d < 2 * w; ++d) K.push_back((d < w ? d + 0.5 : 2 * w - d - 0.5) * Ts * Ts);
    }
    const int span = static_cast<int>(K.size()), first = order * w, step = std::max(1, w / 2);
    std::vector<int> rows;
    for (int t = first; t < N; t += step) rows.push_back(t);
    const auto m = static_cast<Eigen::Index>(rows.size());
    const Eigen::Index p = nl + (inertia >= 0 ? 1 : 0);
    IntervalMatrix Phi(m, p);
    IntervalVector Y(m);
    Eigen::VectorXd resid(m);
    for (Eigen::Index r = 0; r < m; ++r) {
      const int t = rows[static_cast<std::size_t>(r)];
      const int j0 = t - order * w;  // the kernel covers intervals j0 .. t - 1
      std::vector<Interval> acc(static_cast<std::size_t>(nl + 1));
      {
        // One rounding-mode switch for the whole sum instead of a save, set and restore per
        // operation (every screened hypothesis builds these sums); the bounds are the same.
        RoundingScope upward;
        for (Eigen::Index k = 0; k <= nl; ++k) {
          UnprotectedInterval a(0.0);
          for (int d = 0; d < span; ++d)
            a += UnprotectedInterval(K[static_cast<std::size_t>(d)]) * UnprotectedInterval(lo(j0 + d, k), hi(j0 + d, k));
          acc[static_cast<std::size_t>(k)] = a;
        }
      }
      Eigen::VectorXd accm = Eigen::VectorXd::Zero(nl + 1);  // round to nearest again
      for (int d = 0; d < span; ++d)
        for (Eigen::Index k = 0; k <= nl; ++k) accm[k] += K[static_cast<std::size_t>(d)] * mid(j0 + d, k);
      // theta_c D - sum theta_k I[c_k] = I[c0]  (theta_c = 1 without an inertia parameter).
      Eigen::Index col = 0;
      double e = -accm[nl];
      if (inertia >= 0) {
        Phi(r, col++) = Interval(D[t]);
        e += theta_hat[inertia] * D[t];
      }
      for (Eigen::Index k = 0; k < nl; ++k) {
        Phi(r, col++) = -acc[static_cast<std::size_t>(k)];
        e -= theta_hat[linear[static_cast<std::size_t>(k)]] * accm[k];
      }
      Y[r] = acc[static_cast<std::size_t>(nl)] - (inertia >= 0 ? Interval(0.0) : Interval(D[t]));
      if (inertia < 0) e += D[t];
      resid[r] = e;
    }
    std::vector<int> unknowns;
    if (inertia >= 0) unknowns.push_back(inertia);
    for (int k : linear) unknowns.push_back(k);
    res.built = true;
    res.Phi = Phi;
    res.Y = Y;
    res.Phi_mid.resize(m, p);
    res.Y_mid.resize(m);
    for (Eigen::Index r = 0; r < m; ++r) {
      for (Eigen::Index c = 0; c < p; ++c) res.Phi_mid(r, c) = midpoint(Phi(r, c));
      res.Y_mid[r] = midpoint(Y[r]);
    }
    res.residual = resid;
    res.has_inertia = inertia >= 0;
    res.rows = static_cast<int>(m);
    res.window = w;
    res.order = order;
    for (int u : unknowns) {
      res.parameters.push_back(model.parameters[static_cast<std::size_t>(u)].name);
      res.scale.push_back(scale[static_cast<std::size_t>(u)]);
    }
    std::string dnote;
    for (const auto& z : dz) dnote += ", " + z + " = d" + derivative_of[z] + "/dt +- " + std::to_string(rho[z]);
    res.note = "integrated " + std::to_string(order) + "x over " + std::to_string(w) + " samples, " + std::to_string(m) +
               " strips" + dnote + (dz.empty() ? "" : " (3 sigma of the central difference over +-" + std::to_string(wv) + " samples)");
  } catch (const mu::Parser::exception_type& e) {
    return fail("expression evaluation failed: " + e.GetMsg());
  }
  return res;
  };
  for (int w : windows) {
    if (w < 1 || N < 8 * w) {
      EquationErrorRegression r;
      r.note = "equation-error regression not built for \"" + state + "\": the record is too short for a window of " +
               std::to_string(w) + " samples";
      out.push_back(r);
      continue;
    }
    out.push_back(attempt(w));
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
                                    const ColumnNoise* noise) {
  EquationErrorFit fit;
  const int w = window > 0 ? window : std::clamp(data.rows() / 200, 4, 500);
  const EquationErrorRegression g = equation_error_regressions(model, data, state, {w}, noise).front();
  fit.note = g.note;
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
