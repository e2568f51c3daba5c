// Feasible parameter sets, PUIs with their guarantee flag and falsification report, support, the
// outer zonotope of an FPS.

#include "bindings.hpp"
#include "convert.hpp"
#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/fps/outer_zonotope.hpp"

namespace sets::python {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void bind_feasible_parameter_set(py::module_& m) {
  py::class_<FeasibleParameterSet>(
      m, "FeasibleParameterSet",
      "Feasible parameter set of bounded-error, linear-in-parameter data: every theta with, for each\n"
      "sample t, some regressor phi in the box Phi_t and output e in Y_t with phi^T theta = e. With exact\n"
      "regressors sample t is the strip |y_t - phi_t^T theta| <= delta_t.")
      .def(py::init<int>(), py::arg("dimension"), "An empty list of samples in `dimension` parameters.")
      .def_static("from_data", &FeasibleParameterSet::from_data, py::arg("Phi"), py::arg("y"), py::arg("delta"),
                  "Exact regressors: rows of Phi (N x p), outputs y (N), error bounds delta >= 0 (N).")
      .def_static("from_interval_data",
                  [](const Eigen::Ref<const MatrixXd>& phi_lo, const Eigen::Ref<const MatrixXd>& phi_hi,
                     const Eigen::Ref<const VectorXd>& y_lo, const Eigen::Ref<const VectorXd>& y_hi) {
                    return FeasibleParameterSet::from_interval_data(
                        interval_matrix(phi_lo, phi_hi, "from_interval_data: Phi"),
                        interval_matrix(y_lo, y_hi, "from_interval_data: Y").col(0));
                  },
                  py::arg("Phi_lower"), py::arg("Phi_upper"), py::arg("Y_lower"), py::arg("Y_upper"),
                  "Errors in variables: interval regressors [Phi_lower, Phi_upper] (N x p) and interval outputs\n"
                  "[Y_lower, Y_upper] (N), the error bound already included.")
      .def("add_strip",
           py::overload_cast<const Eigen::Ref<const VectorXd>&, double, double>(&FeasibleParameterSet::add_strip),
           py::arg("phi"), py::arg("y"), py::arg("delta"), "|y - phi^T theta| <= delta (ends rounded outward).")
      .def("add_interval_strip",
           [](FeasibleParameterSet& s, const Eigen::Ref<const VectorXd>& lo, const Eigen::Ref<const VectorXd>& hi,
              double y_lo, double y_hi) {
             const IntervalMatrix phi = interval_matrix(lo, hi, "add_interval_strip: phi");
             s.add_strip(IntervalVector(phi.col(0)), interval_matrix(Eigen::Matrix<double, 1, 1>(y_lo),
                                                                      Eigen::Matrix<double, 1, 1>(y_hi),
                                                                      "add_interval_strip: Y")(0, 0));
           },
           py::arg("phi_lower"), py::arg("phi_upper"), py::arg("y_lower"), py::arg("y_upper"),
           "phi in [phi_lower, phi_upper], phi^T theta in [y_lower, y_upper].")
      .def_property_readonly("dimension", &FeasibleParameterSet::dimension)
      .def_property_readonly("size", &FeasibleParameterSet::size, "Number of samples.")
      .def("__len__", &FeasibleParameterSet::size)
      .def_property_readonly("has_interval_regressors", &FeasibleParameterSet::has_interval_regressors)
      .def_property_readonly("regressors_lower", [](const FeasibleParameterSet& s) { return lower(IntervalMatrix(s.regressors())); })
      .def_property_readonly("regressors_upper", [](const FeasibleParameterSet& s) { return upper(IntervalMatrix(s.regressors())); })
      .def_property_readonly("outputs", [](const FeasibleParameterSet& s) { return IntervalVector(s.outputs()); },
                             "The output intervals Y_t as a Box.")
      .def("contains", [](const FeasibleParameterSet& s, const Eigen::Ref<const VectorXd>& theta) {
             check_dimension(theta, s.dimension(), "FeasibleParameterSet.contains: theta");
             return s.contains(theta);
           },
           py::arg("theta"), "Is theta in the set? `unknown` only when rounding cannot decide.")
      .def("least_squares", &FeasibleParameterSet::least_squares, release_gil(),
           "Least squares on the central data (no guarantee; a starting point).")
      .def("orthant_polytope", &FeasibleParameterSet::orthant_polytope, py::arg("orthant"),
           "The exact H-polytope of the set inside one orthant (signs +1/-1 per parameter).")
      .def("__repr__", [](const FeasibleParameterSet& s) {
        return "FeasibleParameterSet(dimension=" + std::to_string(s.dimension()) + ", samples=" + std::to_string(s.size()) +
               (s.has_interval_regressors() ? ", interval regressors)" : ")");
      });
}

// The verdict "do the data falsify the model?" of a PUI or support computation.
void bind_pui_result(py::module_& m) {
  py::class_<PuiResult>(m, "PuiResult", "Parameter uncertainty intervals and how far they can be trusted.")
      .def_readonly("box", &PuiResult::box, "the PUIs [theta_min, theta_max] as a Box")
      .def_readonly("central", &PuiResult::central, "centre of the box (Cerone–Regruto eqs. 41-42)")
      .def_property_readonly("empty", &PuiResult::empty,
                             "True only when the data are certified to falsify the model (consistency.falsified == yes)")
      .def_readonly("consistency", &PuiResult::consistency, "do the data falsify the model? no / yes / unknown")
      .def_readonly("guaranteed", &PuiResult::guaranteed,
                    "True when every finite end is certified by a safe bound (the box is a rigorous outer bound)")
      .def_readonly("orthants", &PuiResult::orthants)
      .def_readonly("lower_points", &PuiResult::lower_points, "column l: a feasible point attaining theta_l^min")
      .def_readonly("upper_points", &PuiResult::upper_points, "column l: a feasible point attaining theta_l^max")
      .def_property_readonly(
          "falsification", [](const PuiResult& r) { return r.consistency.conflict; },
          "the conflicting samples (a proof when empty; an estimate when consistency is unknown)")
      .def_readonly("lp_solves", &PuiResult::lp_solves)
      .def("__repr__", [](const PuiResult& r) {
        if (r.empty()) return "PuiResult(empty: " + r.consistency.message() + ")";
        std::string s = "PuiResult(guaranteed=" + std::string(r.guaranteed ? "True" : "False") + ", box=[";
        for (Eigen::Index i = 0; i < r.box.size(); ++i) s += (i ? ", " : "") + to_string(r.box[i]);
        return s + "])";
      });
}

void bind_support_verdict(py::class_<FpsSupport>& c) {
  c.def_property_readonly("empty", &FpsSupport::empty)
      .def_readonly("consistency", &FpsSupport::consistency)
      .def_property_readonly("falsification", [](const FpsSupport& r) { return r.consistency.conflict; });
}

void bind_pui(py::module_& m) {
  py::enum_<OrthantSelection>(m, "OrthantSelection")
      .value("remark2", OrthantSelection::remark2,
             "least-squares sign orthant (Cerone-Regruto Remark 2), extended across faces a PUI reaches; with "
             "safe=True every other orthant is searched too unless a box proven from p samples misses it, so "
             "the PUIs are those of `all`")
      .value("all", OrthantSelection::all, "every one of the 2^p orthants");
  py::class_<PuiOptions>(m, "PuiOptions", "Options of pui() and support().")
      .def(py::init([](OrthantSelection orthants, bool safe, double zero_tolerance, bool working_set, bool warm_start) {
             PuiOptions o;
             o.orthants = orthants;
             o.safe = safe;
             o.zero_tolerance = zero_tolerance;
             o.working_set = working_set;
             o.warm_start = warm_start;
             return o;
           }),
           py::arg("orthants") = OrthantSelection::remark2, py::arg("safe") = true, py::arg("zero_tolerance") = 1e-9,
           py::arg("working_set") = true, py::arg("warm_start") = true)
      .def_readwrite("orthants", &PuiOptions::orthants)
      .def_readwrite("safe", &PuiOptions::safe, "certify every end with a Neumaier–Shcherbina safe bound")
      .def_readwrite("zero_tolerance", &PuiOptions::zero_tolerance)
      .def_readwrite("working_set", &PuiOptions::working_set)
      .def_readwrite("warm_start", &PuiOptions::warm_start);
  py::enum_<OrthantStatus>(m, "OrthantStatus")
      .value("feasible", OrthantStatus::feasible)
      .value("empty", OrthantStatus::empty)
      .value("unknown", OrthantStatus::unknown);
  py::class_<OrthantReport>(m, "OrthantReport")
      .def_readonly("signs", &OrthantReport::signs, "empty: the whole space (exact regressors)")
      .def_readonly("status", &OrthantReport::status)
      .def_readonly("box", &OrthantReport::box);
  py::class_<Falsification>(m, "Falsification", "Samples that cannot all hold at once (the falsification report).")
      .def_readonly("samples", &Falsification::samples)
      .def_readonly("violation", &Falsification::violation, "how far the best compromise violates each, output units")
      .def("message", &Falsification::message)
      .def("__repr__", &Falsification::message);
  py::enum_<Falsified>(m, "Falsified", "Do the data falsify the model? yes/no only when certified.")
      .value("no", Falsified::no)
      .value("yes", Falsified::yes)
      .value("unknown", Falsified::unknown);
  py::class_<ConsistencyVerdict>(m, "ConsistencyVerdict", "The three-valued verdict and, when not certified, why.")
      .def_readonly("falsified", &ConsistencyVerdict::falsified)
      .def_readonly("conflict", &ConsistencyVerdict::conflict)
      .def_readonly("reason", &ConsistencyVerdict::reason)
      .def("certified_falsified", &ConsistencyVerdict::certified_falsified)
      .def("certified_consistent", &ConsistencyVerdict::certified_consistent)
      .def("message", &ConsistencyVerdict::message)
      .def("__repr__", &ConsistencyVerdict::message);
  bind_pui_result(m);
  m.def("pui", &pui, py::arg("fps"), py::arg("options") = PuiOptions{}, release_gil(),
        "Parameter uncertainty intervals: a box containing the FPS (the part reached by the chosen\n"
        "orthants). With options.safe each finite end is a rigorous bound; see PuiResult.guaranteed.");
  py::class_<FpsSupport> support_class(m, "FpsSupport");
  support_class
      .def_readonly("maxima", &FpsSupport::maxima, "upper bound of max d^T theta per direction")
      .def_readonly("box", &FpsSupport::box)
      .def_readonly("guaranteed", &FpsSupport::guaranteed)
      .def_readonly("lp_solves", &FpsSupport::lp_solves);
  bind_support_verdict(support_class);
  m.def("support",
        [](const FeasibleParameterSet& s, const std::vector<VectorXd>& directions, const PuiOptions& o) {
          for (const auto& d : directions) check_dimension(d, s.dimension(), "support: a direction");
          py::gil_scoped_release release;
          return support(s, directions, o);
        },
        py::arg("fps"), py::arg("directions"), py::arg("options") = PuiOptions{},
        "Upper bounds on max { d^T theta : theta in the FPS } for each direction d (certified when\n"
        "`guaranteed`).");
  m.def("find_conflict", &find_conflict, py::arg("fps"), release_gil(),
        "The samples whose constraints conflict (floating point: a report, not a proof).");
  m.def("all_orthants", &all_orthants, py::arg("p"));
}

void bind_outer_zonotope(py::module_& m) {
  py::class_<FpsZonotopeOptions>(m, "FpsZonotopeOptions")
      .def(py::init([](double max_order, ReductionMethod reduction, std::optional<Zonotope> initial) {
             FpsZonotopeOptions o;
             o.max_order = max_order;
             o.reduction = reduction;
             o.initial = std::move(initial);
             return o;
           }),
           py::arg("max_order") = 10.0, py::arg("reduction") = ReductionMethod::girard, py::arg("initial") = py::none())
      .def_readwrite("max_order", &FpsZonotopeOptions::max_order)
      .def_readwrite("reduction", &FpsZonotopeOptions::reduction)
      .def_readwrite("initial", &FpsZonotopeOptions::initial);
  m.def("outer_zonotope", &outer_zonotope, py::arg("fps"), py::arg("options") = FpsZonotopeOptions{}, release_gil(),
        "A zonotope containing an FPS with exact regressors (strip by strip). Raises EmptySetError when\n"
        "the data provably falsify the model.");
}

}  // namespace

void bind_fps(py::module_& m) {
  bind_feasible_parameter_set(m);
  bind_pui(m);
  bind_outer_zonotope(m);
}

}  // namespace sets::python
