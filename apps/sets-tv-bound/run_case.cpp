#include "run_case.hpp"

#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "sets/methods/tv_bound/tv_bound.hpp"
#include "sets/methods/tv_bound/tv_relinearisation.hpp"

namespace {

using sets::app::Json;
using sets::app::to_json;

std::string fmt(const Eigen::VectorXd& v, int prec = 2) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(prec) << "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
  s << "]";
  return s.str();
}

// Window norm of nu = y_m - Upsilon - Xi Pi at the true Pi: noise plus linearization error.
double true_residual(const sets::TvBoundData& data, const Eigen::MatrixXd& pi, const sets::WindowNorm& window) {
  return window(sets::stack_samples(data.y) - data.regression.upsilon - data.regression.xi * sets::stack_samples(pi));
}

}  // namespace

Json run_case(const sets::crane::Case& c, const TvSettings& s) {
  const int N = s.N;
  const sets::TimeVaryingModel model = sets::crane::model(c.lambda0, c.kappa0, c.b0);
  const Eigen::MatrixXd u = sets::crane::input(s.input, N, s.input_seed), pi = sets::crane::perturbation(c, N);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(3);
  const sets::BiaffineRegression nominal_regression = sets::biaffine_regression(model, x0, u);
  const Eigen::MatrixXd y_plant =
      s.plant == "exact" ? sets::simulate(model, x0, u, pi).y
                         : sets::unstack_samples(nominal_regression.upsilon + nominal_regression.xi * sets::stack_samples(pi),
                                                 model.outputs());
  const sets::WindowNorm window = sets::crane::window();
  sets::TvBoundData data{nominal_regression, y_plant + sets::crane::noise(N, c.noise, window, s.seed), {window}};
  const Eigen::Vector3d nominal(c.b0, c.lambda0, c.kappa0);
  const Eigen::VectorXd F = nominal.cwiseInverse();
  const Eigen::VectorXd true_bound = pi.cwiseAbs().colwise().maxCoeff().transpose();
  Json j = {{"table", c.table}, {"label", c.label}, {"lambda0", c.lambda0}, {"kappa0", c.kappa0},
            {"b0", c.b0}, {"noise_window_norm", c.noise}, {"shape", c.sine ? "sine" : "steps"},
            {"true_bound", to_json(true_bound)}};
  const double true_nu = true_residual(data, pi, window);
  const double deviation = window(sets::stack_samples(data.y) - data.regression.upsilon);
  j["true_residual_window_norm"] = true_nu;
  // How strongly each parameter shows in the output under (2): window norm of Xi Pi for a constant
  // pi_i = true amplitude (others 0). A parameter whose effect is of the order of the noise cannot
  // be told apart from it.
  Eigen::Vector3d sensitivity;
  for (int i = 0; i < 3; ++i) {
    Eigen::MatrixXd p1 = Eigen::MatrixXd::Zero(N, 3);
    p1.col(i).setConstant(c.amplitude[i]);
    sensitivity[i] = window(nominal_regression.xi * sets::stack_samples(p1));
  }
  j["sensitivity_window_norm"] = to_json(sensitivity);
  j["output_deviation_window_norm"] = deviation;
  std::cout << "  " << std::left << std::setw(40) << c.label << std::right << " true " << fmt(true_bound)
            << "  ||y-Cz||_w " << std::setprecision(3) << deviation << "  ||nu(true pi)||_w " << true_nu
            << "  ||Xi pi_i||_w " << fmt(sensitivity, 3) << "\n";
  sets::TvBoundResult linf;  // the MILP needs eps from (8)
  sets::LinfBoundOptions lo;
  lo.F = F;
  lo.G = F;
  lo.mu = s.mu_rel * nominal;
  if (s.relinearise == 0) {
    linf = sets::linf_bound(data, lo);
  } else {
    const auto t0 = std::chrono::steady_clock::now();
    const auto rl = sets::relinearised_linf_bound(model, x0, u, data.y, data.windows, s.relinearise, lo);
    linf = rl.linf;
    linf.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    data = rl.data;  // the MILP runs on the last linearisation, with the last LP's eps
    // nu(true pi) on the linearisation around the last-but-one estimate (the one (8) and (14) use).
    const double relin_nu = true_residual(data, pi, window);
    Json steps = Json::array();
    for (const auto& st : rl.steps)
      steps.push_back({{"objective", st.objective}, {"epsilon", to_json(st.epsilon)}, {"bound", to_json(st.bound)},
                       {"max_change", st.max_change}, {"exact_residual_window_norm", to_json(st.exact_residual)}});
    j["relinearisation"] = {{"true_residual_window_norm", relin_nu}, {"steps", steps}};
    std::cout << "      relinearised " << s.relinearise << "x: ||nu(true pi)||_w " << std::setprecision(3) << relin_nu
              << " on the last linearisation; per LP: bound, eps, max |pi - pi_bar|, ||y - y(pi-hat)||_w exact\n";
    for (std::size_t m = 0; m < rl.steps.size(); ++m)
      std::cout << "        " << m << "  " << fmt(rl.steps[m].bound) << "  " << fmt(rl.steps[m].epsilon, 3) << "  "
                << std::setprecision(3) << rl.steps[m].max_change << "  " << fmt(rl.steps[m].exact_residual, 3) << "\n";
  }
  if (s.linf) {
    const Eigen::VectorXd rms = sets::rms_tracking_error(linf.pi, pi);
    j["linf"] = {{"bound", to_json(linf.bound)}, {"rms_tracking", to_json(rms)}, {"seconds", linf.seconds},
                 {"epsilon", to_json(linf.epsilon)}, {"changes", linf.changes.size()}};
    std::cout << "      linf  bound " << fmt(linf.bound) << "  rms " << fmt(rms, 3) << "  eps " << fmt(linf.epsilon, 3)
              << "  " << std::fixed << std::setprecision(2) << linf.seconds << " s\n";
  }
  if (s.milp) {
    sets::SparseBoundOptions so;
    so.F = F;
    so.mu = s.mu_rel * nominal;
    so.max_abs = s.box_rel * nominal;
    // oracle: the window norm of nu at the true pi (a diagnostic; on the last linearisation if any)
    so.epsilon = s.milp_eps == "oracle" ? Eigen::VectorXd::Constant(1, true_residual(data, pi, window)) : linf.epsilon;
    so.formulation = s.formulation == "paper" ? sets::SparseFormulation::paper : sets::SparseFormulation::single_binary;
    so.milp = {s.time_limit, s.gap, s.verbose, s.node_limit};
    so.solver = s.solver == "glpk" ? sets::SparseSolver::glpk_big_m : sets::SparseSolver::jump_search;
    so.grid = s.grid;
    if (s.warm) so.start = linf.pi;
    const auto m = sets::sparse_bound(data, so);
    const Eigen::VectorXd rms = sets::rms_tracking_error(m.pi, pi);
    j["milp"] = {{"bound", to_json(m.bound)}, {"rms_tracking", to_json(rms)}, {"seconds", m.seconds}, {"gap", m.gap},
                 {"status", sets::to_string(m.status)}, {"objective", m.objective},
                 {"best_bound", m.best_bound}, {"changes", m.changes.size()}, {"nodes", m.nodes}};
    std::cout << "      milp  bound " << fmt(m.bound) << "  rms " << fmt(rms, 3) << "  jumps " << m.changes.size()
              << "  obj " << m.objective << "  gap " << std::setprecision(3) << m.gap << "  " << std::fixed
              << std::setprecision(2) << m.seconds << " s, " << m.nodes << " nodes (" << sets::to_string(m.status) << ")\n";
  }
  return j;
}
