// Stage 4 of the diagnosis: the augmented model with the full substeps, its fits, and the new
// parameters' intervals (output-error and equation-error PUIs, statistical 95 %).

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>

#include "diagnosis/stages.hpp"
#include "sets/core/error.hpp"
#include "sets/diagnosis/equation_error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/interval.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets::diagnosis_stage {

namespace {

// Starts for the effects' parameters that Levenberg-Marquardt from the search's optimum does not
// reach: the cost is not convex in a threshold, a sign law's coefficients or a Stribeck velocity.
// Per chosen effect: its catalogue grid of the nonlinear parameters (data units), the effect
// switched off (its neutral values), and each of its special cases (fixed roles at their values);
// every other parameter at the optimum.
std::vector<Eigen::VectorXd> effect_starts(const ModelFile& m, const std::vector<Candidate>& chosen) {
  const Eigen::VectorXd p0 = values_of(m);
  auto index_of = [&](const std::string& name) -> Eigen::Index {
    for (std::size_t i = 0; i < m.parameters.size(); ++i)
      if (m.parameters[i].name == name) return static_cast<Eigen::Index>(i);
    return -1;
  };
  std::vector<Eigen::VectorXd> out;
  auto keep = [&](const Eigen::VectorXd& p) {
    if (p != p0 && std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
  };
  for (const Candidate& k : chosen) {
    for (const auto& g : k.grid) {
      Eigen::VectorXd p = p0;
      std::size_t gi = 0;
      for (std::size_t q = 0; q < k.parameters.size(); ++q)
        if (!k.linear[q] && gi < g.size())
          if (const Eigen::Index i = index_of(k.parameters[q]); i >= 0) p[i] = g[gi++];
      keep(p);
    }
    Eigen::VectorXd off = p0;
    for (std::size_t q = 0; q < k.parameters.size(); ++q)
      if (const Eigen::Index i = index_of(k.parameters[q]); i >= 0 && !std::isnan(k.neutral[q])) off[i] = k.neutral[q];
    keep(off);
    if (const PhysicsEffect* e = find_effect(k.effect))
      for (const auto& sc : e->special_cases) {
        Eigen::VectorXd p = p0;
        for (const auto& [role, value] : sc.fixed)
          for (std::size_t q = 0; q < k.roles.size(); ++q)
            if (const Eigen::Index i = index_of(k.parameters[q]); k.roles[q] == role && i >= 0) p[i] = value;
        keep(p);
      }
  }
  return out;
}

// The global step's starts: every start of effect_starts costed by one simulation (screening
// substeps, one worker job each, each worker with its own simulator), the best
// `global_step_starts` kept in cost order (ties in start order, as serially).
std::vector<Eigen::VectorXd> global_step_starts(const Context& c, const ModelFile& current, const std::vector<Candidate>& chosen) {
  const auto calibrated = static_cast<std::size_t>(std::max(0, c.options.global_step_starts));
  if (calibrated == 0) return {};
  const std::vector<Eigen::VectorXd> starts = effect_starts(current, chosen);
  std::vector<CalibrationResult> costs(starts.size());
  run_jobs_with(
      c.options.threads, starts.size(),
      [&] { return std::make_unique<Simulator>(current, c.estimation, SimulationOptions{c.options.screening_substeps}); },
      [&](const std::unique_ptr<Simulator>& fast, std::size_t i) { costs[i] = evaluate(*fast, starts[i]); });
  std::vector<std::pair<double, Eigen::VectorXd>> costed;
  for (std::size_t i = 0; i < starts.size(); ++i)
    if (costs[i].ok && std::isfinite(costs[i].cost)) costed.emplace_back(costs[i].cost, starts[i]);
  std::stable_sort(costed.begin(), costed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  costed.resize(std::min(costed.size(), calibrated));
  std::vector<Eigen::VectorXd> out;
  for (auto& [cost, p] : costed) out.push_back(std::move(p));
  return out;
}

// The optima the estimate is chosen from: first the search's optimum refined with the final
// substeps (`from_search`; else the model's values are a start like the others), then each start
// of the global step calibrated (the search's budget) and refined with the final substeps. One
// worker job each, with simulators of its own (a Simulator holds its expressions' state and is
// never shared between threads), results in this order whatever the number of threads. A start
// that cannot be calibrated adds nothing (not ok).
std::vector<CalibrationResult> optima_of(const Context& c, const ModelFile& current, const std::vector<Candidate>& chosen,
                                         const std::vector<int>& free, const CalibrationOptions& o, bool from_search) {
  const std::vector<Eigen::VectorXd> starts = global_step_starts(c, current, chosen);
  CalibrationOptions full = o;
  full.max_evaluations = 80 * static_cast<int>(free.size() + 1);
  std::vector<CalibrationResult> out(starts.size() + 1);
  run_jobs(c.options.threads, out.size(), [&](std::size_t i) {
    try {
      const Simulator exact(current, c.estimation, {c.options.final_substeps});
      if (i == 0 && from_search) {
        out[0] = refine_with_final_substeps(c, exact, exact.parameter_values(), free, o);
        return;
      }
      const Simulator fast(current, c.estimation, {c.options.screening_substeps});
      const CalibrationResult coarse = calibrate(fast, i == 0 ? exact.parameter_values() : starts[i - 1], free, full);
      if (coarse.ok) out[i] = refine_with_final_substeps(c, exact, coarse.parameters, free, o);
    } catch (...) {
      out[i] = CalibrationResult();  // a start that cannot be calibrated adds nothing
    }
  });
  return out;
}

// Is the residual of another optimum inside the bound on the strips' samples? Then it is a point
// of the same bounded-error set.
bool inside_bound(const Eigen::MatrixXd& R, const OutputErrorIntervals& oe) {
  for (Eigen::Index j = 0; j < R.cols(); ++j)
    for (Eigen::Index i = 0; i < R.rows(); i += oe.stride)
      if (!(std::abs(R(i, j)) <= oe.delta[static_cast<std::size_t>(j)])) return false;
  return true;
}

// The global step's optima (the first from the search's optimum or the model's values); the
// estimate is the best of those that can be simulated (not ok when none can).
struct GlobalStep {
  std::vector<CalibrationResult> optima;
  std::size_t best = 0;
  const CalibrationResult& estimate() const { return optima[best]; }
};

GlobalStep global_step(const Context& c, const ModelFile& current, const std::vector<Candidate>& chosen,
                       const std::vector<int>& fr, const CalibrationOptions& o, bool from_search, Diagnosis& d) {
  GlobalStep g;
  for (auto& r : optima_of(c, current, chosen, fr, o, from_search))
    if (g.optima.empty() || (r.ok && std::isfinite(r.cost) && r.outputs.allFinite())) g.optima.push_back(std::move(r));
  for (std::size_t k = 1; k < g.optima.size(); ++k)
    if (!g.estimate().ok || g.optima[k].cost < g.estimate().cost) g.best = k;
  if (from_search && g.best != 0 && g.optima.front().ok)
    d.bound_note += "; the estimate comes from the global step over the effects' parameters (misfit " +
                    fmt(g.estimate().cost) + " against " + fmt(g.optima.front().cost) + " from the search's optimum)";
  return g;
}

// The search calibrates with the screening substeps, and like the nominal's (calibrate_from) its
// optimum can lie where that coarse step hides a growing mode (RK4 damps a mode it resolves
// coarsely): a negative damping fits at the screening step and diverges, or fits worse than the
// calibrated nominal the augmented model extends, at the final one. Then the screening step is
// chosen again at the search's optimum, finer (screening_substeps, as diagnose does for the
// calibrated nominal), and the global step is run again from the nominal's calibrated values (the
// effects' parameters at the search's). The better estimate is kept; d.bound_note says so.
GlobalStep global_step_again(const Context& c, const ModelFile& current, const std::vector<Candidate>& chosen,
                             const std::vector<int>& fr, const CalibrationOptions& o, double nominal_cost, GlobalStep first, Diagnosis& d) {
  const Simulator exact(current, c.estimation, {c.options.final_substeps});
  DiagnosisOptions finer = c.options;
  finer.screening_substeps = std::min(finer.final_substeps, screening_substeps(current, c.estimation, exact, exact.parameter_values(),
                                                                               finer.final_substeps, finer.screening_substeps + 1));
  const Simulator fast(current, c.estimation, {finer.screening_substeps});
  const Context again{current, c.estimation, c.validation, finer, exact, fast, nullptr, c.say};
  ModelFile restart = current;
  for (auto& q : restart.parameters)
    if (const ModelParameter* n = d.nominal.parameter(q.name); n && !q.fixed) q.value = n->value;
  std::ostringstream note;
  note << "; at " << c.options.final_substeps << " RK4 substeps the search's optimum "
       << (first.estimate().ok ? "fits worse than the calibrated nominal (misfit " + fmt(first.estimate().cost) + " against " + fmt(nominal_cost) + ")" : "diverges")
       << " (the screening step of " << c.options.screening_substeps << " hides it): calibrated again with "
       << finer.screening_substeps << " from the nominal's values";
  c.say("the augmented model: " + note.str().substr(2));
  GlobalStep second = global_step(again, restart, chosen, fr, o, false, d);
  const bool better = second.estimate().ok && (!first.estimate().ok || second.estimate().cost < first.estimate().cost);
  note << " -> " << (second.estimate().ok ? "misfit " + fmt(second.estimate().cost) : std::string("diverges"))
       << (better ? ", used" : ", not better: the search's optimum is kept");
  d.bound_note += note.str();
  return better ? second : first;
}

// The augmented model (values refined) and its fits on both records.
void store_augmented(const Context& c, const ModelFile& current, const CalibrationResult& r, Diagnosis& d) {
  d.augmented = current;
  d.fit_augmented_estimation = r.fit;
  d.augmented_estimation = r.outputs;
  if (!c.validation) return;
  Simulator av(current, *c.validation, {c.options.final_substeps});
  d.augmented_validation = av.simulate(r.parameters).outputs;
  d.fit_augmented_validation = fits(av.measured(), d.augmented_validation);
}

// The output-error PUIs linearised at the estimate. Another optimum whose residual stays inside
// the same bound is a point of the same bounded-error set, in another component of it: the
// intervals are the hull of the linearised components around every such point (else they would
// leave out a parameter value the bound admits). Says in d.bound_note what they rest on.
OutputErrorIntervals output_error_hull(const Context& c, const ModelFile& current, const std::vector<int>& fr,
                                       const CalibrationOptions& o, const GlobalStep& step, const Eigen::MatrixXd& J,
                                       const Eigen::MatrixXd& Ra, Diagnosis& d) {
  const CalibrationResult& r = step.estimate();
  OutputErrorIntervals oe = output_error_intervals(J, Ra, r.parameters, fr, o.scale);
  int components = 1;
  for (std::size_t k = 0; oe.built && k < step.optima.size(); ++k) {
    const CalibrationResult& other = step.optima[k];
    if (k == step.best || !other.ok || (other.parameters - r.parameters).cwiseAbs().maxCoeff() == 0) continue;
    const Eigen::MatrixXd Rk = c.exact.measured() - other.outputs;
    if (!inside_bound(Rk, oe)) continue;
    try {
      const Eigen::MatrixXd Jk = output_jacobian(current, c.estimation, c.options.final_substeps, c.options.threads,
                                                 other.parameters, fr, o.scale, other.outputs);
      const OutputErrorIntervals ok = output_error_intervals(Jk, Rk, other.parameters, fr, o.scale, &oe.delta);
      if (!ok.built) continue;
      for (std::size_t i = 0; i < fr.size(); ++i) oe.lo[i] = std::min(oe.lo[i], ok.lo[i]), oe.hi[i] = std::max(oe.hi[i], ok.hi[i]);
      oe.guaranteed = oe.guaranteed && ok.guaranteed;
      ++components;
    } catch (const std::exception&) {
      // its sensitivities blow up: that component is not added (the note counts the ones that were)
    }
  }
  d.bound_note +=
      "; output-error PUIs (estimates: linearised at the estimate, they never cut the bounded-error interval): strips every " +
      std::to_string(oe.stride) + "th sample, bound per output = 1.5 x the largest |residual| of the augmented model there";
  if (!oe.built) d.bound_note += "; " + oe.note;
  if (components > 1)
    d.bound_note += "; " + std::to_string(components) +
                    " optima of the global step inside the bound: the PUIs are the hull of their linearised components";
  if (oe.built) d.bound_note += oe.guaranteed ? "; every finite PUI end certified by a safe bound" : "; some PUI ends not certified";
  return oe;
}

// The covariance of the statistical intervals: the strips' samples, each output normalised, with
// white-noise variance from the residual.
Eigen::MatrixXd statistical_covariance(const Eigen::MatrixXd& J, const Eigen::MatrixXd& Ra, Eigen::Index stride,
                                       const std::vector<double>& norm) {
  const Eigen::Index N = Ra.rows(), ny = Ra.cols(), m = (N + stride - 1) / stride;
  Eigen::MatrixXd Jw(m * ny, J.cols());
  Eigen::VectorXd rw(m * ny);
  for (Eigen::Index j = 0; j < ny; ++j)
    for (Eigen::Index i = 0; i < m; ++i) {
      Jw.row(j * m + i) = J.row(j * N + i * stride) / norm[static_cast<std::size_t>(j)];
      rw[j * m + i] = Ra(i * stride, j) / norm[static_cast<std::size_t>(j)];
    }
  const double dof = std::max<double>(1.0, static_cast<double>(rw.size() - Jw.cols()));
  const double s2 = rw.squaredNorm() / dof;
  return (Jw.transpose() * Jw).completeOrthogonalDecomposition().pseudoInverse() * s2;
}

// Equation-error PUIs where the effect's equation allows them (linear parameters, measured or
// differentiable states): much less sensitive to what the model leaves out at high frequency.
std::map<std::string, EquationErrorResult> equation_error_puis(const ModelFile& current, const Recording& est,
                                                               const std::vector<Candidate>& chosen, Diagnosis& d) {
  std::map<std::string, EquationErrorResult> ee;
  for (const auto& c : chosen) {
    if (ee.count(c.equation)) continue;
    try {
      ee[c.equation] = equation_error_pui(current, est, c.equation);
    } catch (const std::exception& e) {
      ee[c.equation].note = std::string("equation-error PUI failed: ") + e.what();
    }
    d.bound_note += "; " + ee[c.equation].note;
  }
  return ee;
}

// Parameter q of a chosen effect: its estimate, the bounded-error interval and the estimates
// beside it (linearised output error, statistical).
EffectParameter effect_parameter(const Candidate& effect, std::size_t q, const ModelFile& current, const std::vector<int>& fr,
                                 const CalibrationResult& r, const OutputErrorIntervals& oe,
                                 const std::map<std::string, EquationErrorResult>& ee_results, const Eigen::MatrixXd& cov,
                                 Diagnosis& d) {
  const std::string& pn = effect.parameters[q];
  EffectParameter ep;
  ep.name = pn;
  ep.role = effect.roles[q];
  ep.oe_delta = oe.delta;
  for (std::size_t i = 0; i < fr.size(); ++i) {
    if (current.parameters[static_cast<std::size_t>(fr[i])].name != pn) continue;
    const auto ii = static_cast<Eigen::Index>(i);
    ep.estimate = r.parameters[fr[i]];
    // The parameter's own bounds (min/max) hold too, so every interval is cut to them.
    const auto [min, max] = declared_range(current.parameters[static_cast<std::size_t>(fr[i])]);
    ep.estimate_oe_lo = std::max(oe.built ? oe.lo[i] : -inf, min);
    ep.estimate_oe_hi = std::min(oe.built ? oe.hi[i] : inf, max);
    const auto ee = ee_results.find(effect.equation);
    if (ee != ee_results.end() && ee->second.built)
      for (Eigen::Index c = 0; c < ee->second.box.size(); ++c)
        if (ee->second.parameters[static_cast<std::size_t>(c)] == pn) {
          ep.has_ee = true;
          ep.ee_certified = ee->second.guaranteed;
          ep.ee_delta = ee->second.delta;
          ep.ee_lo = std::max(ee->second.box[c].lower(), min);
          ep.ee_hi = std::min(ee->second.box[c].upper(), max);
        }
    set_bounded_error_interval(ep, min, max);
    if (ep.has_ee && (ep.estimate_oe_hi < ep.ee_lo || ep.ee_hi < ep.estimate_oe_lo))
      d.bound_note += "; the linearised output-error estimate of " + pn + " lies outside its equation-error PUI";
    const double sd = std::sqrt(std::max(0.0, cov(ii, ii)));
    ep.estimate_stat_lo = ep.estimate - 1.96 * sd;
    ep.estimate_stat_hi = ep.estimate + 1.96 * sd;
  }
  return ep;
}

}  // namespace

// A meet is guaranteed only if every set met is: the equation-error PUI is (under its bound, every
// end certified), the output-error PUI linearised at the estimate is not (the nonlinear model's
// bounded-error set need not lie inside the linearised one; e.g. a threshold law or another basin),
// nor is the statistical interval. So only the first cuts the declared [min, max]; the others
// stay beside it as estimates.
std::pair<double, double> declared_range(const ModelParameter& p) {
  const double inf = std::numeric_limits<double>::infinity();
  return {p.min <= -1e300 ? -inf : p.min, p.max >= 1e300 ? inf : p.max};
}

void set_bounded_error_interval(EffectParameter& ep, double min, double max) {
  ep.lo = min;
  ep.hi = max;
  if (!ep.has_bounded_error_interval()) return;
  ep.lo = std::max(ep.lo, ep.ee_lo);
  ep.hi = std::min(ep.hi, ep.ee_hi);
}

namespace {

void nominal_is_final(const NominalFit& nominal, Diagnosis& d) {
  d.augmented = d.nominal;
  d.fit_augmented_estimation = d.fit_nominal_estimation;
  d.fit_augmented_validation = d.fit_nominal_validation;
  d.augmented_estimation = nominal.simulation.outputs;
  d.augmented_validation = nominal.validation_outputs;
}

}  // namespace

void augment(const Context& c, const NominalFit& nominal, const HypothesisSearch& search, Diagnosis& d) {
  if (d.effects.empty()) return nominal_is_final(nominal, d);
  c.say("refining the augmented model and computing parameter uncertainty intervals");
  ModelFile current = search.current;  // its values refined with the final substeps here
  const std::vector<int> fr = Simulator(current, c.estimation, {c.options.final_substeps}).free_parameters();
  CalibrationOptions o;
  o.scale = scales_for(current, fr, search.known_scales);
  GlobalStep step = global_step(c, current, search.chosen, fr, o, true, d);
  if (!step.estimate().ok || step.estimate().cost > nominal.cost)
    step = global_step_again(c, current, search.chosen, fr, o, nominal.cost, std::move(step), d);
  if (!step.estimate().ok) {
    // No optimum can be simulated with the full substeps: a model that blows up is no answer, so
    // no effect is kept (random plant 5 001 610: a nominal with a negative damping, which one sine
    // cannot rule out, plus the output saturation the search found).
    std::string names;
    for (const auto& e : d.effects) names += (names.empty() ? "" : ", ") + e.name;
    const std::string why = "the augmented model (" + names + ") blows up with the full substeps from every optimum: no effect is kept";
    c.say(why);
    d.bound_note += (d.bound_note.empty() ? "" : "; ") + why;
    d.effects.clear();
    return nominal_is_final(nominal, d);
  }
  const CalibrationResult& r = step.estimate();
  store_values(current, r.parameters);
  store_augmented(c, current, r, d);
  // Linearised output error around the estimate (stage_helpers: the bounded-error strips), and
  // the same residuals, sub-sampled and normalised, for the statistical intervals.
  const Eigen::MatrixXd& Y = c.exact.measured();
  const Eigen::MatrixXd J =
      output_jacobian(current, c.estimation, c.options.final_substeps, c.options.threads, r.parameters, fr, o.scale, r.outputs);
  const Eigen::MatrixXd Ra = Y - r.outputs;
  const OutputErrorIntervals oe = output_error_hull(c, current, fr, o, step, J, Ra, d);
  const Eigen::MatrixXd cov = statistical_covariance(J, Ra, oe.stride, output_norms(Y));
  const std::map<std::string, EquationErrorResult> ee = equation_error_puis(current, c.estimation, search.chosen, d);
  for (std::size_t k = 0; k < search.chosen.size(); ++k)
    for (std::size_t q = 0; q < search.chosen[k].parameters.size(); ++q)
      d.effects[k].parameters.push_back(effect_parameter(search.chosen[k], q, current, fr, r, oe, ee, cov, d));
}

}  // namespace sets::diagnosis_stage
