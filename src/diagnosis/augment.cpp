// Stage 4 of the diagnosis: the augmented model with the full substeps, its fits, and the new
// parameters' intervals (output-error and equation-error PUIs, statistical 95 %).

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <map>

#include "diagnosis/stages.hpp"
#include "sets/core/error.hpp"
#include "sets/diagnosis/equation_error.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/numeric/interval.hpp"
#include "sets/numeric/linear_program.hpp"

namespace sets::diagnosis_stage {

void augment(const Context& c, const NominalFit& nominal, const HypothesisSearch& search, Diagnosis& d) {
  if (d.effects.empty()) {
    d.augmented = d.nominal;
    d.fit_augmented_estimation = d.fit_nominal_estimation;
    d.fit_augmented_validation = d.fit_nominal_validation;
    d.augmented_estimation = nominal.simulation.outputs;
    d.augmented_validation = nominal.validation_outputs;
    return;
  }
  ModelFile refined = search.current;  // its values refined with the final substeps below
  const ModelFile& current = refined;
  const auto& chosen_candidates = search.chosen;
  const Recording& est = c.estimation;
  const Recording* val = c.validation;
  const DiagnosisOptions& opt = c.options;
  const Eigen::MatrixXd& Y = c.exact.measured();
  const Eigen::Index N = Y.rows(), ny = Y.cols();
  const std::vector<double> norm = output_norms(Y);
  c.say("refining the augmented model and computing parameter uncertainty intervals");
  Simulator aug(current, est, {opt.final_substeps});
  const std::vector<int> fr = aug.free_parameters();
  CalibrationOptions o;
  o.scale = scales_for(current, fr, search.known_scales);
  const auto r = refine_with_final_substeps(c, aug, aug.parameter_values(), fr, o);
  if (!r.ok) throw NumericalError("the augmented model blows up with the full substeps");
  store_values(refined, r.parameters);
  d.augmented = current;
  d.fit_augmented_estimation = r.fit;
  d.augmented_estimation = r.outputs;
  if (val) {
    Simulator av(current, *val, {opt.final_substeps});
    d.augmented_validation = av.simulate(r.parameters).outputs;
    d.fit_augmented_validation = fits(av.measured(), d.augmented_validation);
  }
  // Linearised output error around the estimate (stage_helpers: the bounded-error strips), and
  // the same residuals, sub-sampled and normalised, for the statistical intervals.
  const Eigen::MatrixXd J = output_jacobian(aug, r.parameters, fr, o.scale, r.outputs);
  const Eigen::MatrixXd Ra = Y - r.outputs;
  const OutputErrorIntervals oe = output_error_intervals(J, Ra, r.parameters, fr, o.scale);
  const Eigen::Index stride = oe.stride, m = (N + stride - 1) / stride;
  Eigen::MatrixXd Jw(m * ny, J.cols());
  Eigen::VectorXd rw(m * ny);
  for (Eigen::Index j = 0; j < ny; ++j)
    for (Eigen::Index i = 0; i < m; ++i) {
      Jw.row(j * m + i) = J.row(j * N + i * stride) / norm[static_cast<std::size_t>(j)];
      rw[j * m + i] = Ra(i * stride, j) / norm[static_cast<std::size_t>(j)];
    }
  const std::vector<double>& oe_delta = oe.delta;
  const bool have_pui = oe.built;
  d.bound_note +=
      "; PUIs: strips of the output error linearised at the estimate (every " + std::to_string(stride) +
      "th sample), bound per output = 1.5 x the largest |residual| of the augmented model there";
  if (!have_pui) d.bound_note += "; " + oe.note;
  if (have_pui) d.bound_note += oe.guaranteed ? "; every finite PUI end certified by a safe bound" : "; some PUI ends not certified";
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
    for (std::size_t q = 0; q < chosen_candidates[k].parameters.size(); ++q) {
      const std::string& pn = chosen_candidates[k].parameters[q];
      EffectParameter ep;
      ep.name = pn;
      ep.role = chosen_candidates[k].roles[q];
      ep.oe_delta = oe_delta;
      for (std::size_t i = 0; i < fr.size(); ++i) {
        if (current.parameters[static_cast<std::size_t>(fr[i])].name != pn) continue;
        const auto ii = static_cast<Eigen::Index>(i);
        ep.estimate = r.parameters[fr[i]];
        // The parameter's own bounds (min/max) hold too, so the interval is cut to them.
        const auto& mp = current.parameters[static_cast<std::size_t>(fr[i])];
        double oe_lo = -inf, oe_hi = inf;
        if (have_pui) oe_lo = oe.lo[i], oe_hi = oe.hi[i];
        ep.lo = ep.oe_lo = std::max(oe_lo, mp.min);
        ep.hi = ep.oe_hi = std::min(oe_hi, mp.max);
        const auto ee = ee_results.find(chosen_candidates[k].equation);
        if (ee != ee_results.end() && ee->second.built)
          for (Eigen::Index c = 0; c < ee->second.box.size(); ++c)
            if (ee->second.parameters[static_cast<std::size_t>(c)] == pn) {
              ep.has_ee = true;
              ep.ee_delta = ee->second.delta;
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
}

}  // namespace sets::diagnosis_stage
