// The four papers' methods. Each section binds the entry point the library offers today and the
// types it takes and returns (docs/python.md lists which call each method's app makes).

#include <pybind11/complex.h>
#include <pybind11/functional.h>

#include "bindings.hpp"
#include "convert.hpp"
#include "sets/methods/hinf_bound/hinf_bound.hpp"
#include "sets/methods/lpv_pui/lpv_pui.hpp"
#include "sets/methods/ss_uncertainty/canonical_fps.hpp"
#include "sets/methods/ss_uncertainty/ss_uncertainty.hpp"
#include "sets/methods/tv_bound/tv_bound.hpp"

namespace sets::python {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// ---------------------------------------------------------------- Cerone–Regruto (lpv_pui)
void bind_lpv(py::module_& m) {
  py::class_<RangeOptions> range(m, "RangeOptions", "Tightness of the basis functions' ranges over boxes.");
  with_keywords(range);
  range.def_readwrite("tolerance", &RangeOptions::tolerance).def_readwrite("max_pieces", &RangeOptions::max_pieces);
  py::class_<LpvModelStructure>(m, "LpvModelStructure",
                                "Orders, scheduling dimension and basis functions of an LPV input-output model\n"
                                "(Cerone–Regruto). Build it with `parse` or `sets.examples.cerone_regruto_structure()`.")
      .def_static("parse", &parse_lpv_structure_json, py::arg("text"), py::arg("source") = "model",
                  "From JSON text, e.g. {\"alpha\": 1, \"a\": [[\"lambda\"], [\"1\", \"lambda^2\"]], "
                  "\"b\": [[], [\"1\"], [\"lambda\", \"lambda^2\"]]}.")
      .def_readonly("alpha", &LpvModelStructure::alpha)
      .def_property_readonly("na", &LpvModelStructure::na)
      .def_property_readonly("nb", &LpvModelStructure::nb)
      .def_property_readonly("num_parameters", &LpvModelStructure::num_parameters)
      .def_property_readonly("parameter_names", &LpvModelStructure::parameter_names);
  py::class_<LpvMeasurements> meas(m, "LpvMeasurements",
                                   "u, y (T), r (T x alpha) and the error bounds delta_eta (T or 1), delta_eps\n"
                                   "(T x alpha or 1 x alpha).");
  with_keywords(meas);
  meas.def_readwrite("u", &LpvMeasurements::u)
      .def_readwrite("y", &LpvMeasurements::y)
      .def_readwrite("r", &LpvMeasurements::r)
      .def_readwrite("delta_eta", &LpvMeasurements::delta_eta)
      .def_readwrite("delta_eps", &LpvMeasurements::delta_eps);
  py::class_<LpvRegression>(m, "LpvRegression", "The interval regression of eqs. 18-34.")
      .def_property_readonly("Phi_lower", [](const LpvRegression& r) { return lower(r.Phi); })
      .def_property_readonly("Phi_upper", [](const LpvRegression& r) { return upper(r.Phi); })
      .def_readonly("Y", &LpvRegression::Y)
      .def_readonly("central", &LpvRegression::central)
      .def_readonly("radius", &LpvRegression::radius)
      .def_readonly("time", &LpvRegression::time)
      .def_readonly("all_ranges_tight", &LpvRegression::all_ranges_tight);
  py::class_<LpvPuiResult>(m, "LpvPuiResult")
      .def_readonly("regression", &LpvPuiResult::regression)
      .def_readonly("pui", &LpvPuiResult::pui)
      .def_readonly("falsifying_times", &LpvPuiResult::falsifying_times);
  m.def("lpv_pui", &lpv_pui, py::arg("structure"), py::arg("data"), py::arg("options") = PuiOptions{},
        py::arg("range") = RangeOptions{}, release_gil(),
        "Cerone–Regruto: PUIs and central estimate of an LPV model from output and scheduling data with\n"
        "bounded errors (the entry point of sets-lpv-pui).");
  m.def("simulate_lpv", &simulate_lpv, py::arg("structure"), py::arg("theta"), py::arg("u"), py::arg("lam"),
        "Noise-free simulation from zero initial conditions.");
}

// ---------------------------------------------------------------- Farah et al. (ss_uncertainty)
void bind_ss_uncertainty(py::module_& m) {
  py::class_<StateSpaceModel> ss(m, "StateSpaceModel", "x(t+1) = A x + B u, y = C x + D u.");
  with_keywords(ss);
  ss.def_readwrite("A", &StateSpaceModel::A)
      .def_readwrite("B", &StateSpaceModel::B)
      .def_readwrite("C", &StateSpaceModel::C)
      .def_readwrite("D", &StateSpaceModel::D);
  m.def("simulate_state_space",
        py::overload_cast<const StateSpaceModel&, const Eigen::Ref<const MatrixXd>&, const Eigen::Ref<const VectorXd>&>(&simulate), py::arg("model"), py::arg("u"), py::arg("x0") = VectorXd(),
        "Simulates from x0 (zero if empty); u is N x nu, the result N x ny.");
  py::class_<ObservabilityRow>(m, "ObservabilityRow", "Row C(output,:) A^lag of the observability matrix.")
      .def(py::init([](int lag, int output) { return ObservabilityRow{lag, output}; }), py::arg("lag"), py::arg("output"))
      .def_readwrite("lag", &ObservabilityRow::lag)
      .def_readwrite("output", &ObservabilityRow::output)
      .def("__repr__", [](const ObservabilityRow& r) { return to_string(r); });
  py::enum_<RowSelection>(m, "RowSelection")
      .value("output_major", RowSelection::output_major)
      .value("lag_major", RowSelection::lag_major);
  py::enum_<ResidualSelection>(m, "ResidualSelection")
      .value("all", ResidualSelection::all)
      .value("outputs", ResidualSelection::outputs)
      .value("states", ResidualSelection::states);
  py::enum_<ResidualNorm>(m, "ResidualNorm")
      .value("entrywise", ResidualNorm::entrywise)
      .value("sample_euclidean", ResidualNorm::sample_euclidean)
      .value("per_equation", ResidualNorm::per_equation);
  py::class_<PropagatorOptions> po(m, "PropagatorOptions");
  with_keywords(po);
  po.def_readwrite("order", &PropagatorOptions::order)
      .def_readwrite("past", &PropagatorOptions::past)
      .def_readwrite("estimate_d", &PropagatorOptions::estimate_d)
      .def_readwrite("rows", &PropagatorOptions::rows)
      .def_readwrite("selection", &PropagatorOptions::selection)
      .def_readwrite("rank_tolerance", &PropagatorOptions::rank_tolerance);
  py::class_<LevelSetOptions> lo(m, "LevelSetOptions");
  with_keywords(lo);
  lo.def_readwrite("residuals", &LevelSetOptions::residuals)
      .def_readwrite("norm", &LevelSetOptions::norm)
      .def_readwrite("level_factor", &LevelSetOptions::level_factor);
  py::class_<SsUncertaintyOptions> so(m, "SsUncertaintyOptions");
  with_keywords(so);
  so.def_readwrite("identification", &SsUncertaintyOptions::identification)
      .def_readwrite("level", &SsUncertaintyOptions::level)
      .def_readwrite("estimate_fps_pui", &SsUncertaintyOptions::estimate_fps_pui);
  py::class_<CanonicalStructure>(m, "CanonicalStructure",
                                 "The observable canonical form implied by a choice of observability rows.")
      .def(py::init<std::vector<ObservabilityRow>, int, int, bool>(), py::arg("rows"), py::arg("nu"), py::arg("ny"),
           py::arg("estimate_d"))
      .def_property_readonly("nx", &CanonicalStructure::nx)
      .def_property_readonly("parameter_names", &CanonicalStructure::parameter_names)
      .def("to_parameters", &CanonicalStructure::to_parameters, py::arg("model"));
  m.def("select_rows", &select_rows, py::arg("A"), py::arg("C"), py::arg("selection") = RowSelection::output_major,
        "n_x independent rows of the observability matrix of (A, C).");
  m.def("canonical_form", &canonical_form, py::arg("system"), py::arg("rows"),
        "The observable canonical form x_c = Gamma_1 x of a system for the given rows.");
  py::class_<PropagatorResult>(m, "PropagatorResult")
      .def_readonly("rows", &PropagatorResult::rows)
      .def_readonly("theta", &PropagatorResult::theta, "least-squares estimate of the canonical parameters")
      .def_readonly("model", &PropagatorResult::model, "the canonical model from theta")
      .def_readonly("structure", &PropagatorResult::structure)
      .def_readonly("states", &PropagatorResult::states)
      .def_readonly("gamma_k_singular_values", &PropagatorResult::gamma_k_singular_values);
  py::class_<LevelSetDomain>(m, "LevelSetDomain", "The paper's level-set ellipsoid (an estimate, not guaranteed).")
      .def_readonly("ellipsoid", &LevelSetDomain::ellipsoid)
      .def_readonly("theta", &LevelSetDomain::theta)
      .def_readonly("R", &LevelSetDomain::R)
      .def_readonly("residuals", &LevelSetDomain::residuals)
      .def_readonly("j_min", &LevelSetDomain::j_min)
      .def_readonly("ell", &LevelSetDomain::ell)
      .def_readonly("j_d", &LevelSetDomain::j_d);
  py::class_<CanonicalFps> cf(m, "CanonicalFps",
                             "The FPS of the canonical regression as one FPS per block of equations that share\n"
                             "parameters (their Cartesian product).");
  py::class_<CanonicalFps::Block>(cf, "Block")
      .def_readonly("parameters", &CanonicalFps::Block::parameters, "indices into theta")
      .def_readonly("rows", &CanonicalFps::Block::rows, "rows of the regression")
      .def_readonly("set", &CanonicalFps::Block::set, "the block's FPS, in its own parameters");
  cf.def_property_readonly("dimension", &CanonicalFps::dimension)
      .def("__len__", &CanonicalFps::size)
      .def_property_readonly("blocks", &CanonicalFps::blocks)
      .def_property_readonly("falsified_rows", &CanonicalFps::falsified_rows)
      .def("contains", &CanonicalFps::contains, py::arg("theta"),
           "Is theta in the set (three-valued)? `no` also when a row without parameters is falsified.");
  m.def("pui", py::overload_cast<const CanonicalFps&, const PuiOptions&>(&pui), py::arg("fps"),
        py::arg("options") = PuiOptions{}, release_gil(), "PUIs of a CanonicalFps, block by block.");
  py::class_<SsUncertaintyResult>(m, "SsUncertaintyResult",
                                  "Farah et al.: the identified canonical model and its uncertainty domains. The\n"
                                  "names say what they are: `estimate_*` are not guaranteed (l is read from the\n"
                                  "residuals, not a noise bound).")
      .def_readonly("identification", &SsUncertaintyResult::identification)
      .def_readonly("estimate_level_set", &SsUncertaintyResult::estimate_level_set)
      .def_readonly("estimate_fps", &SsUncertaintyResult::estimate_fps)
      .def_readonly("estimate_fps_pui", &SsUncertaintyResult::estimate_fps_pui);
  m.def("ss_uncertainty", &ss_uncertainty, py::arg("u"), py::arg("y"), py::arg("options"), release_gil(),
        "Farah et al.: identifies a canonical state-space model from u (N x nu) and y (N x ny) by propagator\n"
        "subspace least squares, with the paper's level-set ellipsoid and the FPS of the same regression.");
  py::class_<PairView>(m, "PairView")
      .def_readonly("projection", &PairView::projection)
      .def_readonly("slice", &PairView::slice);
  m.def("pair_view", &pair_view, py::arg("E"), py::arg("i"), py::arg("j"),
        "Exact projection (shadow) and slice through the centre of an ellipsoid onto parameters (i, j).");
}

// ---------------------------------------------------------------- Hakvoort–Van den Hof (hinf_bound)
void bind_hinf_types(py::module_& m) {
  py::class_<OrthonormalBasis>(m, "OrthonormalBasis", "FIR, Laguerre or Kautz orthonormal basis functions.")
      .def_static("fir", &OrthonormalBasis::fir)
      .def_static("laguerre", &OrthonormalBasis::laguerre, py::arg("a"))
      .def_static("kautz", &OrthonormalBasis::kautz, py::arg("xi"))
      .def("describe", &OrthonormalBasis::describe)
      .def("__repr__", &OrthonormalBasis::describe);
  py::class_<HinfPriors> pr(m, "HinfPriors", "Priors on G0: |g0(k)| <= M rho^k, |u(t)| <= u_bar before the data.");
  with_keywords(pr);
  pr.def_readwrite("M", &HinfPriors::M)
      .def_readwrite("rho", &HinfPriors::rho)
      .def_readwrite("u_bar", &HinfPriors::u_bar)
      .def_readwrite("M_ic", &HinfPriors::M_ic)
      .def_readwrite("rho_ic", &HinfPriors::rho_ic);
  py::enum_<NoiseModel>(m, "NoiseModel").value("stochastic", NoiseModel::stochastic).value("bounded", NoiseModel::bounded);
  py::enum_<RegionShape>(m, "RegionShape").value("rectangle", RegionShape::rectangle).value("ellipse", RegionShape::ellipse);
  py::class_<UncertaintyOptions> uo(m, "UncertaintyOptions");
  with_keywords(uo);
  uo.def_readwrite("noise", &UncertaintyOptions::noise)
      .def_readwrite("shape", &UncertaintyOptions::shape)
      .def_readwrite("alpha", &UncertaintyOptions::alpha)
      .def_readwrite("simultaneous", &UncertaintyOptions::simultaneous)
      .def_readwrite("v_bar", &UncertaintyOptions::v_bar)
      .def_readwrite("max_lag", &UncertaintyOptions::max_lag)
      .def_readwrite("first_sample", &UncertaintyOptions::first_sample)
      .def_readwrite("tail_terms", &UncertaintyOptions::tail_terms)
      .def_readwrite("coefficient_share", &UncertaintyOptions::coefficient_share);
  py::class_<NominalOptions> no(m, "NominalOptions");
  with_keywords(no);
  no.def_readwrite("order", &NominalOptions::order)
      .def_readwrite("polygon_sides", &NominalOptions::polygon_sides)
      .def_readwrite("iterations", &NominalOptions::iterations)
      .def_readwrite("weight", &NominalOptions::weight);
  py::class_<WeightOptions> wo(m, "WeightOptions");
  with_keywords(wo);
  wo.def_readwrite("degree", &WeightOptions::degree).def_readwrite("weight", &WeightOptions::weight);
  py::class_<HinfBoundOptions> ho(m, "HinfBoundOptions");
  with_keywords(ho);
  ho.def_readwrite("uncertainty", &HinfBoundOptions::uncertainty)
      .def_readwrite("nominal", &HinfBoundOptions::nominal)
      .def_readwrite("weight", &HinfBoundOptions::weight);
  py::class_<FrequencyRegion>(m, "FrequencyRegion", "A rectangle or an ellipse of the complex plane.")
      .def_readonly("shape", &FrequencyRegion::shape)
      .def_readonly("centre", &FrequencyRegion::centre)
      .def_readonly("half_re", &FrequencyRegion::half_re)
      .def_readonly("half_im", &FrequencyRegion::half_im)
      .def_readonly("Q", &FrequencyRegion::Q)
      .def("contains", &FrequencyRegion::contains, py::arg("g"), py::arg("tolerance") = 0.0)
      .def("boundary", &FrequencyRegion::boundary, py::arg("points") = 64);
  py::class_<RationalModel>(m, "RationalModel", "b(z^-1) / a(z^-1), a(0) = 1.")
      .def_readonly("b", &RationalModel::b)
      .def_readonly("a", &RationalModel::a)
      .def("__call__", &RationalModel::operator(), py::arg("w"), "G(e^{iw})")
      .def("poles", &RationalModel::poles)
      .def("stable", &RationalModel::stable, py::arg("margin") = 0.0)
      .def("__repr__", &RationalModel::to_string);
}

void bind_hinf(py::module_& m) {
  bind_hinf_types(m);
  py::class_<UncertaintySet>(m, "UncertaintySet", "Per-frequency regions that contain G0(w_j).")
      .def_readonly("frequencies", &UncertaintySet::frequencies)
      .def_readonly("regions", &UncertaintySet::regions)
      .def_readonly("estimate", &UncertaintySet::estimate)
      .def_readonly("theta", &UncertaintySet::theta)
      .def_readonly("beta1", &UncertaintySet::beta1)
      .def_readonly("level", &UncertaintySet::level)
      .def_readonly("noise_variance", &UncertaintySet::noise_variance)
      .def_property_readonly("empty", &UncertaintySet::empty, "bounded noise: the data provably falsify the priors")
      .def_readonly("consistency", &UncertaintySet::consistency, "bounded noise: the three-valued verdict")
      .def_property_readonly(
          "falsification", [](const UncertaintySet& s) { return s.empty() ? s.consistency.message() : std::string(); },
          "why the data falsify the priors (empty unless empty is true), as before consistency existed")
      .def_readonly("lp_solves", &UncertaintySet::lp_solves);
  py::class_<NominalFit>(m, "NominalFit")
      .def_readonly("model", &NominalFit::model)
      .def_readonly("centres", &NominalFit::centres)
      .def_readonly("max_error", &NominalFit::max_error);
  py::class_<WeightFit>(m, "WeightFit")
      .def_readonly("trig", &WeightFit::trig)
      .def_readonly("h", &WeightFit::h, "W^-1(z) = sum_k h_k z^-k, minimum phase")
      .def_readonly("max_gap", &WeightFit::max_gap)
      .def("inverse", &WeightFit::inverse, py::arg("w"));
  py::class_<BoundResult>(m, "BoundResult")
      .def_readonly("b", &BoundResult::b, "bounds ||W (G - Ghat)||_inf on [0, pi]")
      .def_readonly("b_grid", &BoundResult::b_grid)
      .def_readonly("b_data", &BoundResult::b_data)
      .def_readonly("kappa", &BoundResult::kappa)
      .def_readonly("delta_u", &BoundResult::delta_u)
      .def_readonly("lambda_", &BoundResult::lambda)
      .def_readonly("beta", &BoundResult::beta);
  py::class_<HinfBoundResult>(m, "HinfBoundResult")
      .def_readonly("set", &HinfBoundResult::set)
      .def_readonly("nominal", &HinfBoundResult::nominal)
      .def_readonly("delta", &HinfBoundResult::delta)
      .def_readonly("weight", &HinfBoundResult::weight)
      .def_readonly("bound", &HinfBoundResult::bound)
      .def_readonly("unweighted", &HinfBoundResult::unweighted);
  py::class_<HinfData> hd(m, "HinfData", "One experiment: u, y and (closed loop) the reference r, or r empty.");
  with_keywords(hd);
  hd.def_readwrite("u", &HinfData::u).def_readwrite("y", &HinfData::y).def_readwrite("r", &HinfData::r);
  py::class_<HinfStructure> hs(m, "HinfStructure", "The basis and its number of functions, the priors and the frequency grid.");
  with_keywords(hs);
  hs.def_readwrite("basis", &HinfStructure::basis)
      .def_readwrite("order", &HinfStructure::order)
      .def_readwrite("priors", &HinfStructure::priors)
      .def_readwrite("grid", &HinfStructure::grid);
  m.def("midpoint_grid", &midpoint_grid, py::arg("points"), py::arg("w_min") = 0.0, py::arg("w_max") = M_PI,
        "`points` frequencies at the midpoints of equal cells of [w_min, w_max] (sets-hinf-bound's --grid).");
  m.def("hinf_bound", py::overload_cast<const HinfData&, const HinfStructure&, const HinfBoundOptions&>(&hinf_bound),
        py::arg("data"), py::arg("structure"), py::arg("options") = HinfBoundOptions{}, release_gil(),
        "Hakvoort–Van den Hof, the method's entry point: frequency regions, nominal model, weighting and the\n"
        "H-infinity bound b on one data set (what sets-hinf-bound calls).");
  m.def("hinf_bound",
        [](const Eigen::Ref<const VectorXd>& u, const Eigen::Ref<const VectorXd>& y, const OrthonormalBasis& basis,
           int order, const Eigen::Ref<const VectorXd>& grid, const HinfPriors& priors, const HinfBoundOptions& options,
           std::optional<VectorXd> instrument) {
          py::gil_scoped_release release;
          return hinf_bound(HinfData{u, y, instrument ? *instrument : VectorXd()}, HinfStructure{basis, order, priors, grid},
                            options);
        },
        py::arg("u"), py::arg("y"), py::arg("basis"), py::arg("order"), py::arg("grid"), py::arg("priors"),
        py::arg("options") = HinfBoundOptions{}, py::arg("instrument") = py::none(),
        "Hakvoort–Van den Hof: frequency regions, nominal model, weighting and the H-infinity bound b\n"
        "(the entry point of sets-hinf-bound). `instrument`: reference signal for closed-loop data.");
}

// ---------------------------------------------------------------- Salehpour–Johansson (tv_bound)
void bind_tv(py::module_& m) {
  py::class_<TimeVaryingModel> tv(m, "TimeVaryingModel",
                                  "x(k+1) = A x + B u + P (pi (x) x) + D pi + Q (pi (x) u), y = C x (eq. 1).");
  with_keywords(tv);
  tv.def_readwrite("A", &TimeVaryingModel::A)
      .def_readwrite("B", &TimeVaryingModel::B)
      .def_readwrite("C", &TimeVaryingModel::C)
      .def_readwrite("P", &TimeVaryingModel::P)
      .def_readwrite("D", &TimeVaryingModel::D)
      .def_readwrite("Q", &TimeVaryingModel::Q);
  py::class_<TimeVaryingSimulation>(m, "TimeVaryingSimulation")
      .def_readonly("x", &TimeVaryingSimulation::x)
      .def_readonly("y", &TimeVaryingSimulation::y);
  m.def("simulate_time_varying", py::overload_cast<const TimeVaryingModel&, const Eigen::Ref<const VectorXd>&, const Eigen::Ref<const MatrixXd>&, const Eigen::Ref<const MatrixXd>&>(&simulate),
        py::arg("model"), py::arg("x0"), py::arg("u"), py::arg("pi"), "Exact simulation of eq. (1).");
  py::class_<BiaffineRegression>(m, "BiaffineRegression")
      .def_readonly("zeta", &BiaffineRegression::zeta)
      .def_readonly("upsilon", &BiaffineRegression::upsilon)
      .def_readonly("xi", &BiaffineRegression::xi);
  m.def("biaffine_regression", &biaffine_regression, py::arg("model"), py::arg("x0"), py::arg("u"),
        "Upsilon and Xi of eqs. (3)-(4) for the nominal model.");
  py::class_<WindowNorm>(m, "WindowNorm", "||v||_w = max_k sum_i w(k-i) |v(i)| (w non-increasing).")
      .def(py::init<VectorXd>(), py::arg("weights"))
      .def_static("pulse", &WindowNorm::pulse, py::arg("length"), py::arg("height"))
      .def_property_readonly("weights", &WindowNorm::weights)
      .def("__call__", &WindowNorm::operator(), py::arg("v"));
  py::class_<TvBoundData>(m, "TvBoundData")
      .def(py::init([](BiaffineRegression r, MatrixXd y, std::vector<WindowNorm> w) {
             TvBoundData d{std::move(r), std::move(y), std::move(w)};
             d.validate();
             return d;
           }),
           py::arg("regression"), py::arg("y"), py::arg("windows"),
           "Measured outputs y ((N+1) x l) against the regression; one window per output or one for all.");
  py::enum_<MilpStatus>(m, "MilpStatus")
      .value("optimal", MilpStatus::optimal)
      .value("feasible", MilpStatus::feasible)
      .value("infeasible", MilpStatus::infeasible)
      .value("no_solution", MilpStatus::no_solution);
  py::class_<TvChange>(m, "TvChange")
      .def_readonly("sample", &TvChange::sample)
      .def_readonly("parameter", &TvChange::parameter)
      .def_readonly("size", &TvChange::size);
  py::class_<TvBoundResult>(m, "TvBoundResult",
                            "Estimated perturbation trajectory pi-hat and rho-hat = max |pi-hat| (estimates, not bounds).")
      .def_readonly("pi", &TvBoundResult::pi)
      .def_readonly("bound", &TvBoundResult::bound)
      .def_readonly("epsilon", &TvBoundResult::epsilon)
      .def_readonly("residual", &TvBoundResult::residual)
      .def_readonly("changes", &TvBoundResult::changes)
      .def_readonly("objective", &TvBoundResult::objective)
      .def_readonly("status", &TvBoundResult::status)
      .def_readonly("gap", &TvBoundResult::gap)
      .def_readonly("nodes", &TvBoundResult::nodes)
      .def_readonly("consistency", &TvBoundResult::consistency,
                    "linf_bound with a given epsilon: do the data falsify the model? (yes only when certified)");
  py::class_<LinfBoundOptions> lo(m, "LinfBoundOptions");
  with_keywords(lo);
  lo.def_readwrite("F", &LinfBoundOptions::F)
      .def_readwrite("G", &LinfBoundOptions::G)
      .def_readwrite("h", &LinfBoundOptions::h)
      .def_readwrite("epsilon", &LinfBoundOptions::epsilon)
      .def_readwrite("initial_difference", &LinfBoundOptions::initial_difference)
      .def_readwrite("mu", &LinfBoundOptions::mu);
  py::class_<MilpOptions> mo(m, "MilpOptions");
  with_keywords(mo);
  mo.def_readwrite("time_limit_s", &MilpOptions::time_limit_s)
      .def_readwrite("relative_gap", &MilpOptions::relative_gap)
      .def_readwrite("node_limit", &MilpOptions::node_limit);
  py::class_<SparseBoundOptions> sp(m, "SparseBoundOptions");
  with_keywords(sp);
  sp.def_readwrite("F", &SparseBoundOptions::F)
      .def_readwrite("mu", &SparseBoundOptions::mu)
      .def_readwrite("max_abs", &SparseBoundOptions::max_abs)
      .def_readwrite("epsilon", &SparseBoundOptions::epsilon)
      .def_readwrite("initial_difference", &SparseBoundOptions::initial_difference)
      .def_readwrite("milp", &SparseBoundOptions::milp)
      .def_readwrite("start", &SparseBoundOptions::start);
  m.def("linf_bound", &linf_bound, py::arg("data"), py::arg("options") = LinfBoundOptions{}, release_gil(),
        "Salehpour–Johansson eq. (8), one LP (the first call of sets-tv-bound).");
  m.def("sparse_bound", &sparse_bound, py::arg("data"), py::arg("options"), release_gil(),
        "Salehpour–Johansson eq. (14), a MILP (the second call of sets-tv-bound).");
}

}  // namespace

void bind_methods(py::module_& m) {
  bind_lpv(m);
  bind_ss_uncertainty(m);
  bind_hinf(m);
  bind_tv(m);
}

}  // namespace sets::python
