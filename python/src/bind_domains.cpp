// The set types and their operations (free functions with the C++ names), set I/O, projections.

#include <pybind11/numpy.h>

#include "bindings.hpp"
#include "convert.hpp"
#include "sets/domains/conversions.hpp"
#include "sets/domains/ellipsoid.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/domains/set_io.hpp"
#include "sets/domains/vpolytope.hpp"
#include "sets/domains/zonotope.hpp"

namespace sets::python {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

py::object json_module() { return py::module_::import("json"); }
py::object to_python_json(const nlohmann::json& j) { return json_module().attr("loads")(j.dump()); }
nlohmann::json from_python_json(const py::object& o) {
  return nlohmann::json::parse(json_module().attr("dumps")(o).cast<std::string>());
}

template <class Set>
void bind_common(py::class_<Set>& c) {
  c.def_property_readonly("dimension", &Set::dimension)
      .def("__repr__", [](const Set& s) { return to_string(s); })
      .def("to_json", [](const Set& s) { return to_python_json(to_json(AnySet(s))); },
           "The set as a JSON-ready dict (the format of docs/architecture.md, exact round trip).")
      .def(py::pickle([](const Set& s) { return to_json(AnySet(s)).dump(); },
                      [](const std::string& text) { return std::get<Set>(from_json(nlohmann::json::parse(text))); }));
}

void bind_zonotope(py::module_& m) {
  py::class_<Zonotope> z(m, "Zonotope",
                         "Zonotope {c + G xi : xi in [-1, 1]^m}: centre c (n) and generators G (n x m, one\n"
                         "generator per column). Flat (rank-deficient) generator matrices are allowed.");
  z.def(py::init<VectorXd, MatrixXd>(), py::arg("center"), py::arg("generators"))
      .def_static("from_box", &Zonotope::from_box, py::arg("box"), "The box itself (contains it after rounding).")
      .def_property_readonly("center", &Zonotope::center)
      .def_property_readonly("generators", &Zonotope::generators)
      .def_property_readonly("num_generators", &Zonotope::num_generators)
      .def_property_readonly("order", &Zonotope::order, "Generators per dimension, m / n.");
  bind_common(z);
  py::enum_<ReductionMethod>(m, "ReductionMethod", "Order-reduction method of reduce_order.")
      .value("girard", ReductionMethod::girard, "importance ||g||_1 - ||g||_inf (Girard 2005)")
      .value("combastel", ReductionMethod::combastel, "importance ||g||_2 (Combastel 2003)")
      .value("pca", ReductionMethod::pca, "discarded generators boxed in their principal axes");
  m.def("reduce_order", &reduce_order, py::arg("Z"), py::arg("order"), py::arg("method") = ReductionMethod::girard,
        release_gil(),
        "An outer approximation of Z with at most max(n, order*n) generators (order >= 1); always contains Z.");
  m.def("compact", &compact, py::arg("Z"), "Removes zero generators and merges parallel ones (contains Z).");
  m.def("try_intersect_strip",
        py::overload_cast<const Zonotope&, const Eigen::Ref<const VectorXd>&, double, double>(&try_intersect_strip), py::arg("Z"), py::arg("a"), py::arg("y"), py::arg("delta"),
        "Outer zonotope of Z ∩ {x : |y - a^T x| <= delta} (Alamo–Bravo–Camacho), None if provably empty.");
}

void bind_ellipsoid(py::module_& m) {
  py::class_<Ellipsoid> e(m, "Ellipsoid",
                          "Ellipsoid {x : (x-c)^T P^-1 (x-c) <= 1}, P symmetric positive semidefinite\n"
                          "(flat when P is singular).");
  e.def(py::init<VectorXd, MatrixXd>(), py::arg("center"), py::arg("shape"))
      .def_static("from_level_set", &Ellipsoid::from_level_set, py::arg("theta0"), py::arg("R"), py::arg("gamma"),
                  "{theta : (theta-theta0)^T R (theta-theta0) <= gamma}, contained after rounding.")
      .def_static("ball", &Ellipsoid::ball, py::arg("center"), py::arg("radius"))
      .def_property_readonly("center", &Ellipsoid::center)
      .def_property_readonly("shape", &Ellipsoid::shape);
  bind_common(e);
  py::enum_<EllipsoidCriterion>(m, "EllipsoidCriterion")
      .value("min_volume", EllipsoidCriterion::min_volume)
      .value("min_trace", EllipsoidCriterion::min_trace);
  m.def("project", &project, py::arg("E"), py::arg("coords"),
        "Exact projection (shadow) {x_K : x in E} onto the listed coordinates.");
  m.def("slice", &slice, py::arg("E"), py::arg("coords"), py::arg("fixed_values"),
        "Slice {x_K : x in E, x_F = v} (floating point, not enlarged); None when empty. Contained in the projection.");
  m.def("volume", py::overload_cast<const Ellipsoid&>(&volume), py::arg("E"), "Volume (floating point, approximate).");
  m.def("flatness", &flatness, py::arg("E"), "Smallest over largest eigenvalue of P (floating point).");
  m.def("intersect_strip",
        py::overload_cast<const Ellipsoid&, const Eigen::Ref<const VectorXd>&, double, double, EllipsoidCriterion>(&intersect_strip),
        py::arg("E"), py::arg("a"), py::arg("y"), py::arg("delta"), py::arg("criterion") = EllipsoidCriterion::min_volume,
        "Optimal bounding ellipsoid of E ∩ {x : |y - a^T x| <= delta} (Fogel–Huang); contains the intersection.\n"
        "Raises EmptySetError when the intersection is provably empty (the data falsify the model).");
  m.def("try_intersect_strip",
        [](const Ellipsoid& E, const VectorXd& a, double y, double delta, EllipsoidCriterion c) {
          return try_intersect_strip(E, a, y, delta, StripOptions{c});
        },
        py::arg("E"), py::arg("a"), py::arg("y"), py::arg("delta"), py::arg("criterion") = EllipsoidCriterion::min_volume,
        "As intersect_strip, but None when provably empty.");
  m.def("outer_polygon", &outer_polygon, py::arg("E"), py::arg("n") = 64,
        "2 x n vertices of a polygon circumscribed about a 2-D ellipsoid (contains it).");
}

void bind_polytopes(py::module_& m) {
  py::class_<HPolytope> h(m, "HPolytope", "H-polytope {x : A x <= b}; possibly empty or unbounded (b may hold inf).");
  h.def(py::init<MatrixXd, VectorXd>(), py::arg("A"), py::arg("b"))
      .def_property_readonly("A", &HPolytope::A)
      .def_property_readonly("b", &HPolytope::b)
      .def_property_readonly("num_constraints", &HPolytope::num_constraints);
  bind_common(h);
  py::class_<VPolytope> v(m, "VPolytope", "Convex hull of the columns of an n x k matrix of points.");
  v.def(py::init<MatrixXd>(), py::arg("points"))
      .def_property_readonly("points", &VPolytope::points)
      .def_property_readonly("num_points", &VPolytope::num_points);
  bind_common(v);
  py::class_<ChebyshevBall>(m, "ChebyshevBall", "Largest inscribed ball (floating point LP, not a guarantee).")
      .def_readonly("center", &ChebyshevBall::center)
      .def_readonly("radius", &ChebyshevBall::radius);
  m.def("is_empty", &is_empty, py::arg("P"), release_gil(), "yes/no from GLPK's exact rational simplex.");
  m.def("chebyshev_ball", &chebyshev_ball, py::arg("P"), release_gil());
  m.def("intersect", &intersect, py::arg("P"), py::arg("Q"), "P ∩ Q (rows stacked; exact).");
  m.def("remove_redundant", &remove_redundant, py::arg("P"), release_gil(),
        "Drops rows the LP finds redundant; the result contains P.");
  m.def("convex_hull", &convex_hull, py::arg("V"), release_gil(), "Vertices of the hull (CGAL, exact), 1-3 D.");
}

// The generic operations: one Python name, one overload per set type (as in C++).
void bind_generic(py::module_& m) {
  m.def("outer_box", py::overload_cast<const Zonotope&>(&outer_box), py::arg("set"),
        "Guaranteed box containing the set (a Box).");
  m.def("outer_box", py::overload_cast<const Ellipsoid&>(&outer_box), py::arg("set"));
  m.def("outer_box", py::overload_cast<const HPolytope&>(&outer_box), py::arg("set"), release_gil());
  m.def("outer_box", py::overload_cast<const VPolytope&>(&outer_box), py::arg("set"));

  m.def("support", py::overload_cast<const Zonotope&, const Eigen::Ref<const VectorXd>&>(&support), py::arg("set"), py::arg("d"),
        "Rigorous upper bound on max_{x in set} d^T x.");
  m.def("support", py::overload_cast<const Ellipsoid&, const Eigen::Ref<const VectorXd>&>(&support), py::arg("set"), py::arg("d"));
  m.def("support", py::overload_cast<const HPolytope&, const Eigen::Ref<const VectorXd>&>(&support), py::arg("set"), py::arg("d"),
        release_gil());
  m.def("support", py::overload_cast<const VPolytope&, const Eigen::Ref<const VectorXd>&>(&support), py::arg("set"), py::arg("d"));

  m.def("contains", py::overload_cast<const Zonotope&, const Eigen::Ref<const VectorXd>&>(&contains), py::arg("set"), py::arg("x"),
        "Is x in the set? A BoolInterval: yes/no only when proven.");
  m.def("contains", py::overload_cast<const Ellipsoid&, const Eigen::Ref<const VectorXd>&>(&contains), py::arg("set"), py::arg("x"));
  m.def("contains", py::overload_cast<const HPolytope&, const Eigen::Ref<const VectorXd>&>(&contains), py::arg("set"), py::arg("x"));
  m.def("contains", py::overload_cast<const VPolytope&, const Eigen::Ref<const VectorXd>&>(&contains), py::arg("set"), py::arg("x"));

  m.def("linear_map", py::overload_cast<const Eigen::Ref<const MatrixXd>&, const Zonotope&>(&linear_map), py::arg("A"), py::arg("set"),
        "Image A set. Zonotope, Ellipsoid, HPolytope: contains the exact image; VPolytope: points mapped in\n"
        "floating point (approximate).");
  m.def("linear_map", py::overload_cast<const Eigen::Ref<const MatrixXd>&, const Ellipsoid&>(&linear_map), py::arg("A"), py::arg("set"));
  m.def("linear_map", py::overload_cast<const Eigen::Ref<const MatrixXd>&, const HPolytope&>(&linear_map), py::arg("A"), py::arg("set"),
        release_gil());
  m.def("linear_map", py::overload_cast<const Eigen::Ref<const MatrixXd>&, const VPolytope&>(&linear_map), py::arg("A"), py::arg("set"));

  m.def("translate", py::overload_cast<const Zonotope&, const Eigen::Ref<const VectorXd>&>(&translate), py::arg("set"), py::arg("b"));
  m.def("translate", py::overload_cast<const Ellipsoid&, const Eigen::Ref<const VectorXd>&>(&translate), py::arg("set"), py::arg("b"));
  m.def("minkowski_sum", py::overload_cast<const Zonotope&, const Zonotope&>(&minkowski_sum), py::arg("a"),
        py::arg("b"), "Z1 + Z2 (exact up to rounding of the centre).");
  m.def("minkowski_sum", py::overload_cast<const Ellipsoid&, const Ellipsoid&, EllipsoidCriterion>(&minkowski_sum),
        py::arg("a"), py::arg("b"), py::arg("criterion") = EllipsoidCriterion::min_trace,
        "Outer ellipsoid of E1 + E2 (contains the sum).");

  m.def("to_hpolytope", py::overload_cast<const IntervalVector&>(&to_hpolytope), py::arg("set"),
        "H-representation containing the set (exact for boxes; CGAL for V-polytopes, 1-3 D).");
  m.def("to_hpolytope", py::overload_cast<const Zonotope&, long>(&to_hpolytope), py::arg("set"),
        py::arg("max_facets") = 200000, release_gil());
  m.def("to_hpolytope", py::overload_cast<const VPolytope&>(&to_hpolytope), py::arg("set"), release_gil());
  m.def("to_vpolytope", py::overload_cast<const IntervalVector&>(&to_vpolytope), py::arg("set"),
        "Vertices (rounded to nearest; not an enclosure) of a box, a 2-/3-D zonotope or a 1-3 D H-polytope.");
  m.def("to_vpolytope", py::overload_cast<const Zonotope&>(&to_vpolytope), py::arg("set"), release_gil());
  m.def("to_vpolytope", py::overload_cast<const HPolytope&>(&to_vpolytope), py::arg("set"), release_gil());

  m.def("polygon_vertices", py::overload_cast<const Zonotope&>(&polygon_vertices), py::arg("set"),
        "2 x k counter-clockwise vertices of a 2-D set (for plotting).");
  m.def("polygon_vertices", py::overload_cast<const VPolytope&>(&polygon_vertices), py::arg("set"));
  m.def("polygon_vertices", py::overload_cast<const HPolytope&>(&polygon_vertices), py::arg("set"));

  m.def("projection_polygon", &projection_polygon, py::arg("set"), py::arg("i"), py::arg("j"),
        py::arg("directions") = 64, release_gil(),
        "2 x k convex polygon containing the projection of the set onto coordinates (i, j): the exact\n"
        "shadow (up to rounding) of zonotopes, V-polytopes and boxes, circumscribed for ellipsoids,\n"
        "certified supporting half-planes for H-polytopes.");
}

void bind_set_io(py::module_& m) {
  m.def("set_to_json", [](const AnySet& s) { return to_python_json(to_json(s)); }, py::arg("set"),
        "Any set (Box, Zonotope, Ellipsoid, HPolytope, VPolytope) as a JSON-ready dict.");
  m.def("set_from_json", [](const py::object& o) { return from_json(from_python_json(o), "dict"); }, py::arg("data"),
        "The set described by a dict (or list) in the JSON format; InputError naming the bad field.");
  m.def("save_set", &save_json, py::arg("path"), py::arg("set"), "Writes the set as JSON (complete or not at all).");
  m.def("load_set", &load_json, py::arg("path"), "Reads a set from a JSON file.");
  m.def("set_to_string", py::overload_cast<const AnySet&>(&to_string), py::arg("set"), "Text form (round-trips).");
  m.def("set_from_string", &from_string, py::arg("text"), py::arg("where") = "text", "Reads the text form.");
}

}  // namespace

void bind_domains(py::module_& m) {
  bind_zonotope(m);
  bind_ellipsoid(m);
  bind_polytopes(m);
  // Boxes take part in the generic operations too.
  m.def("outer_box", [](const IntervalVector& b) { return b; }, py::arg("set"));
  m.def("contains", [](const IntervalVector& b, const VectorXd& x) {
          check_dimension(x, b.size(), "contains: x");
          return to_bool_interval(contains(b, x));
        }, py::arg("set"), py::arg("x"));
  bind_generic(m);
  bind_set_io(m);
}

}  // namespace sets::python
