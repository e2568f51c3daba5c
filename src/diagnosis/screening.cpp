#include "sets/diagnosis/screening.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <mutex>
#include <set>

#include "models/expression.hpp"
#include "sets/data/simulation.hpp"
#include "sets/diagnosis/equation_error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets {

Eigen::VectorXd bounded_least_squares(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::VectorXd>& b,
                                      const Eigen::Ref<const Eigen::VectorXd>& lo, const Eigen::Ref<const Eigen::VectorXd>& hi) {
  const Eigen::Index p = A.cols();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(p);
  if (p == 0) return x;
  Eigen::VectorXd norm(p);
  for (Eigen::Index c = 0; c < p; ++c) norm[c] = A.col(c).norm() > 0 ? A.col(c).norm() : 1.0;
  std::vector<bool> fixed(static_cast<std::size_t>(p), false);
  for (int pass = 0; pass <= p; ++pass) {
    std::vector<Eigen::Index> freecols;
    Eigen::VectorXd rhs = b;
    for (Eigen::Index c = 0; c < p; ++c) {
      if (fixed[static_cast<std::size_t>(c)]) rhs -= A.col(c) * x[c];
      else freecols.push_back(c);
    }
    if (freecols.empty()) break;
    Eigen::MatrixXd Af(A.rows(), static_cast<Eigen::Index>(freecols.size()));
    for (std::size_t k = 0; k < freecols.size(); ++k) Af.col(static_cast<Eigen::Index>(k)) = A.col(freecols[k]) / norm[freecols[k]];
    const Eigen::VectorXd z = Af.completeOrthogonalDecomposition().solve(rhs);
    bool violated = false;
    for (std::size_t k = 0; k < freecols.size(); ++k) {
      const Eigen::Index c = freecols[k];
      x[c] = z[static_cast<Eigen::Index>(k)] / norm[c];
    }
    for (Eigen::Index c = 0; c < p; ++c) {
      if (fixed[static_cast<std::size_t>(c)]) continue;
      if (x[c] < lo[c] || x[c] > hi[c]) {
        x[c] = std::clamp(x[c], lo[c], hi[c]);
        fixed[static_cast<std::size_t>(c)] = true;
        violated = true;
      }
    }
    if (!violated) break;
  }
  return x;
}

namespace {

// Simulations run side by side (Simulator::simulate_outputs_each) ahead of the code that asks for
// them one at a time: a parameter vector asked for again gets the outputs simulating it gives,
// bit for bit; any other is simulated.
class Simulated_ahead {
 public:
  Simulated_ahead(const Simulator& s, std::vector<Eigen::VectorXd> ps) : s_(s), ps_(std::move(ps)) {
    if (ps_.empty()) return;
    Eigen::MatrixXd columns(ps_.front().size(), static_cast<Eigen::Index>(ps_.size()));
    for (std::size_t i = 0; i < ps_.size(); ++i) columns.col(static_cast<Eigen::Index>(i)) = ps_[i];
    s_.simulate_outputs_each(columns, ys_, ok_);
  }
  bool simulate_outputs(const Eigen::VectorXd& p, Eigen::MatrixXd& y) const {
    for (std::size_t i = 0; i < ps_.size(); ++i)
      if (ps_[i].size() == p.size() && ps_[i] == p) {
        y = ys_[i];
        return ok_[i];
      }
    return s_.simulate_outputs(p, y);
  }

 private:
  const Simulator& s_;
  std::vector<Eigen::VectorXd> ps_;
  std::vector<Eigen::MatrixXd> ys_;
  std::vector<bool> ok_;
};

// Outputs stacked (output after output), each divided by ||y_j - mean y_j||: the calibration's cost.
Eigen::VectorXd weighted(const Eigen::MatrixXd& M, const Eigen::VectorXd& w) {
  const Eigen::Index N = M.rows();
  Eigen::VectorXd v(M.size());
  for (Eigen::Index j = 0; j < M.cols(); ++j) v.segment(j * N, N) = M.col(j) * w[j];
  return v;
}

struct Around {  // the current model, around which every hypothesis is linearised
  Eigen::MatrixXd Y, y0;
  Eigen::VectorXd w;
  std::vector<std::string> free_names;
  Eigen::MatrixXd J;  // weighted sensitivities to the current free parameters
};

// The parameters of a sensitivity's simulation: p with parameter i moved by step.
Eigen::VectorXd moved(const Eigen::VectorXd& p, int i, double step) {
  Eigen::VectorXd q = p;
  q[i] += step;
  return q;
}

// Sensitivity of the (weighted) outputs to parameter i at p, forward difference; the step is
// enlarged when it moves the outputs by less than round-off. Empty when it cannot be simulated.
Eigen::VectorXd sensitivity(const Simulated_ahead& s, const Eigen::VectorXd& p, int i, double step, const Eigen::MatrixXd& y,
                            const Eigen::VectorXd& w, int& sims) {
  Eigen::MatrixXd y1;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const Eigen::VectorXd q = moved(p, i, step);
    ++sims;
    if (!s.simulate_outputs(q, y1) || !y1.allFinite()) {
      step = -step;
      continue;
    }
    const Eigen::VectorXd d = weighted(y1 - y, w);
    if (d.norm() > 1e-10 * std::max(1.0, weighted(y, w).norm()) || attempt == 1) return d / step;
    step *= 1e3;
  }
  return Eigen::VectorXd();
}

// Where a candidate's parameters sit in its simulator: the current model's free parameters that
// stay free in the candidate (a replaced one does not; their columns of a.J) and its new ones.
struct CandidateLayout {
  std::vector<int> cur_cols, cur_index, new_index;
};

CandidateLayout layout_of(const Around& a, const Candidate& c, const Simulator& s) {
  const std::vector<std::string> names = s.parameter_names();
  const std::vector<int> free = s.free_parameters();
  auto index_of = [&](const std::string& n) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == n) return static_cast<int>(i);
    return -1;
  };
  CandidateLayout L;
  for (std::size_t k = 0; k < a.free_names.size(); ++k) {
    const int i = index_of(a.free_names[k]);
    if (i >= 0 && std::find(free.begin(), free.end(), i) != free.end())
      L.cur_cols.push_back(static_cast<int>(k)), L.cur_index.push_back(i);
  }
  for (const auto& n : c.parameters) L.new_index.push_back(index_of(n));
  return L;
}

// The linearised least-squares fit at one grid point of the nonlinear parameters: the shift d of
// the outputs the grid point alone gives, the sensitivity columns A (current parameters, then
// the new ones) and the cost of the bounded step x.
struct GridFit {
  double cost;
  Eigen::VectorXd start, stepped;  // linear coefficients fitted (nonlinear on the grid); all stepped
  Eigen::VectorXd d;
  Eigen::MatrixXd A;
};

// The parameters at grid point g: the linear new ones at 0, the nonlinear ones on the grid.
Eigen::VectorXd grid_point(const Candidate& c, const CandidateLayout& L, const Eigen::VectorXd& base,
                           const std::vector<double>& g) {
  Eigen::VectorXd p = base;
  std::size_t gi = 0;
  for (std::size_t k = 0; k < c.parameters.size(); ++k) {
    if (c.linear[k]) p[L.new_index[k]] = 0.0;
    else if (gi < g.size()) p[L.new_index[k]] = g[gi++];
  }
  return p;
}

// Whether the grid point is simulated (with only linear new parameters, at 0, it is the current
// model).
bool simulates_grid_point(const Candidate& c) {
  return !c.grid.empty() || std::find(c.linear.begin(), c.linear.end(), true) == c.linear.end();
}

// The first step of the sensitivity to new parameter k at grid point p.
double sensitivity_step(const Candidate& c, const CandidateLayout& L, const Eigen::VectorXd& p, std::size_t k) {
  const double scale = c.scales[k] > 0 ? c.scales[k] : 1.0;
  return c.linear[k] ? 1e-3 * scale : 1e-2 * std::max(std::abs(p[L.new_index[k]]), 1e-3 * scale);
}

std::optional<GridFit> fit_grid_point(const Around& a, const Candidate& c, const CandidateLayout& L, const Simulated_ahead& s,
                                      const Eigen::VectorXd& base, const Eigen::VectorXd& R, const std::vector<double>& g,
                                      int& sims) {
  const std::vector<int>& ni = L.new_index;
  const Eigen::VectorXd p = grid_point(c, L, base, g);
  Eigen::MatrixXd yg = a.y0;
  if (simulates_grid_point(c)) {
    ++sims;
    if (!s.simulate_outputs(p, yg) || !yg.allFinite()) return std::nullopt;
  }
  const Eigen::VectorXd d = weighted(yg - a.y0, a.w);
  const auto q0 = static_cast<Eigen::Index>(L.cur_cols.size());
  const auto q = q0 + static_cast<Eigen::Index>(c.parameters.size());
  Eigen::MatrixXd A(R.size(), q);
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(q, -1e300), hi = Eigen::VectorXd::Constant(q, 1e300);
  for (Eigen::Index k = 0; k < q0; ++k) A.col(k) = a.J.col(L.cur_cols[static_cast<std::size_t>(k)]);
  for (std::size_t k = 0; k < c.parameters.size(); ++k) {
    const Eigen::Index col = q0 + static_cast<Eigen::Index>(k);
    const Eigen::VectorXd sk = sensitivity(s, p, ni[k], sensitivity_step(c, L, p, k), yg, a.w, sims);
    if (sk.size() == 0) return std::nullopt;
    A.col(col) = sk;
    const auto& mp = c.model.parameters[static_cast<std::size_t>(ni[k])];
    lo[col] = mp.min - p[ni[k]];
    hi[col] = mp.max - p[ni[k]];
  }
  const Eigen::VectorXd x = bounded_least_squares(A, R - d, lo, hi);
  GridFit fit{(R - d - A * x).squaredNorm(), p, p, d, A};
  for (std::size_t k = 0; k < c.parameters.size(); ++k) {
    const double v = p[ni[k]] + x[q0 + static_cast<Eigen::Index>(k)];
    if (c.linear[k]) fit.start[ni[k]] = v;  // the nonlinear ones stay on their grid point
    fit.stepped[ni[k]] = v;
  }
  for (std::size_t k = 0; k < L.cur_cols.size(); ++k) {
    const auto& mp = c.model.parameters[static_cast<std::size_t>(L.cur_index[k])];
    fit.stepped[L.cur_index[k]] = std::clamp(base[L.cur_index[k]] + x[static_cast<Eigen::Index>(k)], mp.min, mp.max);
  }
  return fit;
}

// The best grid point's linearisation in the new parameters: columns, shift and the bounds of
// the step from the point the columns were taken at.
void keep_linearisation(const Candidate& c, const CandidateLayout& L, const GridFit& b, ScreenedHypothesis& h) {
  const auto qn = static_cast<Eigen::Index>(c.parameters.size());
  h.columns = b.A.rightCols(qn);
  h.shift = b.d;
  h.lower.resize(qn);
  h.upper.resize(qn);
  for (Eigen::Index k = 0; k < qn; ++k) {
    const int i = L.new_index[static_cast<std::size_t>(k)];
    const auto& mp = c.model.parameters[static_cast<std::size_t>(i)];
    const double at = c.linear[static_cast<std::size_t>(k)] ? 0.0 : b.start[i];
    h.lower[k] = mp.min - at;
    h.upper[k] = mp.max - at;
  }
}

// Consistency with the noise bound: a common point of the linearised strips (decimated).
bool consistent_with_noise(const Around& a, const ScreeningOptions& o, const Eigen::VectorXd& R, const GridFit& b) {
  const Eigen::Index N = a.Y.rows(), ny = a.Y.cols(), stride = std::max<Eigen::Index>(1, N / 800);
  const Eigen::Index m = (N + stride - 1) / stride;
  Eigen::MatrixXd Phi(m * ny, b.A.cols());
  Eigen::VectorXd yy(m * ny), dd(m * ny);
  for (Eigen::Index j = 0; j < ny; ++j)
    for (Eigen::Index i = 0; i < m; ++i) {
      const Eigen::Index t = j * N + i * stride;
      // In units of the bound (the weights cancel): |r - d - A x| / (w delta) <= 1.
      const double scale = a.w[j] * std::max(o.noise_bound[static_cast<std::size_t>(j)], 1e-300);
      Phi.row(j * m + i) = b.A.row(t) / scale;
      yy[j * m + i] = (R[t] - b.d[t]) / scale;
      dd[j * m + i] = 1.0;
    }
  for (Eigen::Index col = 0; col < Phi.cols(); ++col) {
    const double n = Phi.col(col).norm();
    if (n > 0) Phi.col(col) /= n;
  }
  try {
    return find_conflict(FeasibleParameterSet::from_data(Phi, yy, dd)).samples.empty();
  } catch (const std::exception&) {
    return false;
  }
}

ScreenedHypothesis screen_one(const Around& a, const Recording& data, const Candidate& c, const ScreeningOptions& o,
                              int& sims) {
  ScreenedHypothesis h;
  h.candidate = c;
  h.new_parameters = static_cast<int>(c.parameters.size()) + (c.effect == "time_delay" ? 1 : 0);
  h.cost = std::numeric_limits<double>::infinity();
  Simulator s(c.model, data, {o.substeps});
  const CandidateLayout L = layout_of(a, c, s);
  const Eigen::VectorXd base = s.parameter_values();
  const Eigen::VectorXd R = weighted(a.Y - a.y0, a.w);
  const auto grid = c.grid.empty() ? std::vector<std::vector<double>>{{}} : c.grid;
  // Every grid point and the first simulation of each of its sensitivities, side by side.
  std::vector<Eigen::VectorXd> first;
  for (const auto& g : grid) {
    const Eigen::VectorXd p = grid_point(c, L, base, g);
    if (simulates_grid_point(c)) first.push_back(p);
    for (std::size_t k = 0; k < c.parameters.size(); ++k) first.push_back(moved(p, L.new_index[k], sensitivity_step(c, L, p, k)));
  }
  const Simulated_ahead ahead(s, std::move(first));
  std::vector<GridFit> done;
  for (const auto& g : grid)
    if (auto fit = fit_grid_point(a, c, L, ahead, base, R, g, sims)) done.push_back(std::move(*fit));
  if (done.empty()) {
    h.note = "could not be simulated";
    return h;
  }
  std::sort(done.begin(), done.end(), [](const GridFit& x, const GridFit& y) { return x.cost < y.cost; });
  h.cost = done.front().cost;
  keep_linearisation(c, L, done.front(), h);
  // Multi-start in the nonlinear parameters: the best three grid points, each with its
  // least-squares linear coefficients and (for the best) the full least-squares step.
  for (std::size_t r = 0; r < std::min<std::size_t>(3, done.size()); ++r) {
    h.starts.push_back(done[r].start);
    if (r == 0) h.starts.push_back(done[r].stepped);
  }
  for (std::size_t i = 0; i < h.candidate.model.parameters.size(); ++i) h.candidate.model.parameters[i].value = h.starts.front()[static_cast<Eigen::Index>(i)];
  if (!o.noise_bound.empty()) h.consistent = consistent_with_noise(a, o, R, done.front());
  return h;
}

bool compatible(const Candidate& a, const Candidate& b) {
  static const std::vector<std::string> sign_laws = {"coulomb_friction", "stribeck_friction", "asymmetric_friction",
                                                     "viscous_friction", "quadratic_drag"};
  static const std::vector<std::string> sensors = {"output_saturation", "hysteresis", "absolute_value_sensor"};
  auto in = [](const std::vector<std::string>& v, const std::string& e) { return std::find(v.begin(), v.end(), e) != v.end(); };
  if (a.effect == b.effect) return false;
  if (in(sign_laws, a.effect) && in(sign_laws, b.effect) && a.equation == b.equation) return false;
  if (in(sensors, a.effect) && in(sensors, b.effect) && a.equation == b.equation) return false;
  return a.parts.empty() && b.parts.empty();
}

// Pairs of the best single hypotheses: the least squares with both sets of columns and both
// shifts (first order: the effects add), then the combined model built on the first's.
std::vector<ScreenedHypothesis> screen_pairs(const Around& a, const Eigen::VectorXd& R, const Recording& data,
                                             const std::vector<ScreenedHypothesis>& singles, const ScreeningOptions& o,
                                             int& sims) {
  std::vector<const ScreenedHypothesis*> top;
  for (const auto& h : singles) {
    if (static_cast<int>(top.size()) >= o.pairs) break;
    if (!std::isfinite(h.cost) || h.columns.rows() != R.size() || h.starts.empty()) continue;
    bool seen = false;  // one delay per actuator
    for (const auto* t : top) seen = seen || (t->candidate.effect == h.candidate.effect && t->candidate.equation == h.candidate.equation);
    if (!seen) top.push_back(&h);
  }
  std::vector<ScreenedHypothesis> out;
  const Eigen::Index q0 = a.J.cols();
  for (std::size_t i = 0; i < top.size(); ++i)
    for (std::size_t j = i + 1; j < top.size(); ++j) {
      const ScreenedHypothesis &x = *top[i], &y = *top[j];
      if (!compatible(x.candidate, y.candidate)) continue;
      const Eigen::Index qx = x.columns.cols(), qy = y.columns.cols();
      Eigen::MatrixXd A(R.size(), q0 + qx + qy);
      A << a.J, x.columns, y.columns;
      Eigen::VectorXd lo(A.cols()), hi(A.cols());
      lo << Eigen::VectorXd::Constant(q0, -1e300), x.lower, y.lower;
      hi << Eigen::VectorXd::Constant(q0, 1e300), x.upper, y.upper;
      const Eigen::VectorXd b = R - x.shift - y.shift;
      const double cost = (b - A * bounded_least_squares(A, b, lo, hi)).squaredNorm();
      if (!(cost < std::min(x.cost, y.cost))) continue;
      // The second effect on the first's model (its start values), found by effect and place.
      try {
        Simulator s(x.candidate.model, data, {o.substeps});
        ++sims;
        const auto sim = s.simulate(s.parameter_values());
        const Candidate* second = nullptr;
        const std::vector<Candidate> on_first = generate_candidates(x.candidate.model, sim, data);
        for (const auto& c : on_first)
          if (c.effect == y.candidate.effect && c.equation == y.candidate.equation &&
              (c.effect != "time_delay" || c.delay_samples == y.candidate.delay_samples))
            second = &c;
        if (!second) continue;
        ScreenedHypothesis p;
        p.candidate = combine_candidates(x.candidate, *second);
        // Start: the first's start, the second's new parameters from its own start (by role).
        Simulator sc(p.candidate.model, data, {o.substeps});
        Eigen::VectorXd start = sc.parameter_values();
        for (std::size_t k = 0; k < second->parameters.size(); ++k)
          for (std::size_t q = 0; q < y.candidate.parameters.size(); ++q)
            if (y.candidate.roles[q] == second->roles[k])
              for (std::size_t m = 0; m < p.candidate.model.parameters.size(); ++m) {
                if (p.candidate.model.parameters[m].name != second->parameters[k]) continue;
                for (std::size_t n = 0; n < y.candidate.model.parameters.size(); ++n)
                  if (y.candidate.model.parameters[n].name == y.candidate.parameters[q])
                    start[static_cast<Eigen::Index>(m)] = y.starts.front()[static_cast<Eigen::Index>(n)];
              }
        p.starts = {start};
        for (std::size_t m = 0; m < p.candidate.model.parameters.size(); ++m) p.candidate.model.parameters[m].value = start[static_cast<Eigen::Index>(m)];
        p.cost = cost;
        p.new_parameters = x.new_parameters + y.new_parameters;
        p.score = cost * std::pow(o.sparsity_tolerance, p.new_parameters);
        p.note = "pair";
        out.push_back(std::move(p));
      } catch (const std::exception&) {
      }
    }
  return out;
}

// The state equations of `model` that use any of `names`, directly or through signals and
// sampled signals: where an actuator's new signal acts.
std::vector<std::string> states_using(const ModelFile& model, const std::vector<std::string>& names) {
  std::set<std::string> reach(names.begin(), names.end());
  auto uses_any = [&](const std::string& text) {
    const auto e = check_expression(text, [](const std::string&) { return true; }, "equation");
    return std::any_of(e.symbols.begin(), e.symbols.end(), [&](const std::string& x) { return reach.count(x) > 0; });
  };
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto* texts : {&model.signals, &model.sampled})
      for (const auto& [n, e] : *texts)
        if (!reach.count(n) && uses_any(e)) grew = reach.insert(n).second;
  }
  std::vector<std::string> out;
  for (const auto& st : model.states)
    if (const std::string* d = model.derivative(st.name); d && uses_any(*d)) out.push_back(st.name);
  return out;
}

// The state equations a candidate's equation error is fitted on: its own, or those its actuator
// signal drives.
std::vector<std::string> equation_error_states(const ModelFile& current, const Candidate& c) {
  if (current.derivative(c.equation)) return {c.equation};
  return states_using(c.model, c.parameters);
}

// The equation-error fit of one state equation of a candidate: as the candidate stands, or, for an
// actuator law (a play or threshold inside a sampled signal, whose history a free parameter would
// move), with its nonlinear parameters fixed at the best grid point (the first start). A law in
// the state equation itself is fitted as it stands (Stribeck's vs keeps it from being built).
EquationErrorFit candidate_fit(const Candidate& c, const Recording& data, const ColumnNoise& column_noise,
                               const std::string& state, const std::vector<Eigen::VectorXd>& starts) {
  EquationErrorFit f = equation_error_fit(c.model, data, state, 0, column_noise);
  if (f.built || state == c.equation || starts.empty() ||
      std::all_of(c.linear.begin(), c.linear.end(), [](bool l) { return l; }))
    return f;
  ModelFile at_grid = c.model;
  for (std::size_t q = 0; q < at_grid.parameters.size(); ++q) at_grid.parameters[q].value = starts.front()[static_cast<Eigen::Index>(q)];
  for (std::size_t k = 0; k < c.parameters.size(); ++k)
    if (!c.linear[k]) at_grid.parameter(c.parameters[k])->fixed = true;
  return equation_error_fit(at_grid, data, state, 0, column_noise);
}

// The equation-error fits of a candidate: its gain over the current model's (baseline: that
// model's relative residual on the same equation; the best over the equations fitted) and its
// estimates as another start, the nonlinear parameters from the best grid point. A fit that
// cannot be built adds nothing.
void add_equation_error_start(const Candidate& c, const Recording& data, const ColumnNoise& column_noise,
                              const std::map<std::string, double>& baselines, ScreenedHypothesis& h) {
  Eigen::VectorXd st = h.starts.empty() ? Eigen::VectorXd() : h.starts.front();
  bool moved = false;
  for (const auto& [state, baseline] : baselines) {
    try {
      const EquationErrorFit f = candidate_fit(c, data, column_noise, state, h.starts);
      // A law in the state equation keeps the fits it had: one from sampled signals (a position
      // loop's force balance) would start Coulomb friction there but never Stribeck's richer law,
      // whose vs keeps the regression from being built, and the nested rule then names the
      // special case (development plant 5 002 818, Hypotheses.RicherLawIsRefinedAgain...).
      if (!f.built || (state == c.equation && f.from_samples)) continue;
      const double gain = 1 - (f.relative_residual * f.relative_residual) / (baseline * baseline);
      if (!std::isfinite(h.ee_gain) || gain > h.ee_gain) h.ee_gain = gain;
      if (st.size() == 0) continue;
      for (std::size_t k = 0; k < f.parameters.size(); ++k)
        for (std::size_t q = 0; q < c.model.parameters.size(); ++q)
          if (c.model.parameters[q].name == f.parameters[k]) {
            const auto& mp = c.model.parameters[q];
            st[static_cast<Eigen::Index>(q)] = std::clamp(f.estimate[k], mp.min, mp.max);
            moved = true;
          }
    } catch (const std::exception&) {
    }
  }
  if (moved) h.starts.push_back(st);
}

}  // namespace

Screening screen_hypotheses(const ModelFile& current, const Recording& data, const std::vector<Candidate>& candidates,
                            const ScreeningOptions& o) {
  Screening out;
  Simulator s(current, data, {o.substeps});
  Around a;
  a.Y = s.measured();
  a.w.resize(a.Y.cols());
  for (Eigen::Index j = 0; j < a.Y.cols(); ++j) {
    const double den = (a.Y.col(j).array() - a.Y.col(j).mean()).matrix().norm();
    a.w[j] = den > 0 ? 1 / den : 1.0;
  }
  const Eigen::VectorXd p0 = s.parameter_values();
  const std::vector<int> free = s.free_parameters();
  const auto step = [&](std::size_t k) { return 1e-4 * (std::abs(p0[free[k]]) > 0 ? std::abs(p0[free[k]]) : 1.0); };
  std::vector<Eigen::VectorXd> first{p0};  // the current model and its sensitivities' first steps, side by side
  for (std::size_t k = 0; k < free.size(); ++k) first.push_back(moved(p0, free[k], step(k)));
  const Simulated_ahead ahead(s, std::move(first));
  if (!ahead.simulate_outputs(p0, a.y0)) return out;
  ++out.simulations;
  const std::vector<std::string> names = s.parameter_names();
  a.J.resize(a.Y.size(), static_cast<Eigen::Index>(free.size()));
  for (std::size_t k = 0; k < free.size(); ++k) {
    a.free_names.push_back(names[static_cast<std::size_t>(free[k])]);
    Eigen::VectorXd sk = sensitivity(ahead, p0, free[k], step(k), a.y0, a.w, out.simulations);
    a.J.col(static_cast<Eigen::Index>(k)) = sk.size() ? sk : Eigen::VectorXd::Zero(a.Y.size());
  }
  const Eigen::VectorXd R = weighted(a.Y - a.y0, a.w);
  {
    const Eigen::VectorXd inf = Eigen::VectorXd::Constant(a.J.cols(), 1e300);
    out.baseline = (R - a.J * bounded_least_squares(a.J, R, -inf, inf)).squaredNorm();
  }
  // Equation-error baselines, one per state equation (the current model's own least squares).
  // The noise of the measured columns (a property of the data) once, not once per hypothesis.
  std::map<std::string, double> ee_base;
  std::vector<std::map<std::string, double>> ee_bases(candidates.size());  // per candidate: its states' baselines
  ColumnNoise column_noise;
  if (o.equation_error) column_noise = measured_noise(current, data);
  if (o.equation_error)
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (candidates[i].effect == "time_delay") continue;
      for (const auto& state : equation_error_states(current, candidates[i])) {
        if (!ee_base.count(state)) {
          const EquationErrorFit f = equation_error_fit(current, data, state, 0, column_noise);
          ee_base[state] = f.built ? f.relative_residual : -1;
        }
        if (ee_base[state] > 0) ee_bases[i][state] = ee_base[state];
      }
    }
  std::vector<ScreenedHypothesis> hs(candidates.size());
  // Longest first (simulations: one per grid point and one per new parameter at each), so that
  // the screening does not end on one long candidate while the other thread idles; results are
  // kept by candidate index, so the order of the jobs changes nothing else.
  std::vector<std::size_t> order(candidates.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto work = [&](std::size_t i) { return std::max<std::size_t>(1, candidates[i].grid.size()) * (1 + candidates[i].parameters.size()); };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return work(x) > work(y); });
  std::vector<int> sims(candidates.size(), 0);
  run_jobs(o.threads, candidates.size(), [&](std::size_t j) {
    const std::size_t i = order[j];
    try {
      hs[i] = screen_one(a, data, candidates[i], o, sims[i]);
    } catch (const std::exception& e) {
      hs[i].candidate = candidates[i];
      hs[i].cost = std::numeric_limits<double>::infinity();
      hs[i].note = e.what();
    }
    if (!ee_bases[i].empty()) add_equation_error_start(candidates[i], data, column_noise, ee_bases[i], hs[i]);
  });
  for (int n : sims) out.simulations += n;
  for (auto& h : hs) {
    h.gain = out.baseline > 0 ? 1 - h.cost / out.baseline : 0;
    h.score = h.cost * std::pow(o.sparsity_tolerance, h.new_parameters);
  }
  std::sort(hs.begin(), hs.end(), [](const auto& x, const auto& y) { return x.score < y.score; });
  if (o.pairs > 1) {
    std::vector<ScreenedHypothesis> pairs = screen_pairs(a, R, data, hs, o, out.simulations);
    for (auto& p : pairs) {
      p.gain = out.baseline > 0 ? 1 - p.cost / out.baseline : 0;
      hs.push_back(std::move(p));
    }
    std::sort(hs.begin(), hs.end(), [](const auto& x, const auto& y) { return x.score < y.score; });
  }
  out.ranked = std::move(hs);
  return out;
}

}  // namespace sets
