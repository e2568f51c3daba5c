// Interval (outward-rounded) and Box (an IntervalVector).

#include <pybind11/numpy.h>
#include <pybind11/operators.h>

#include <sstream>

#include "bindings.hpp"
#include "convert.hpp"
#include "sets/core/error.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets::python {

namespace {

Interval make_interval(double lo, double hi) {
  if (std::isnan(lo) || std::isnan(hi) || lo > hi)
    throw InputError("Interval(" + std::to_string(lo) + ", " + std::to_string(hi) + "): need lo <= hi, no NaN");
  return Interval(lo, hi);
}

std::string box_repr(const IntervalVector& b) {
  std::ostringstream o;
  o.precision(17);
  o << "Box([";
  for (Eigen::Index i = 0; i < b.size(); ++i) o << (i ? ", " : "") << "[" << b[i].lower() << ", " << b[i].upper() << "]";
  o << "])";
  return o.str();
}

}  // namespace

IntervalVector box_from_bounds(const Eigen::Ref<const Eigen::VectorXd>& lo, const Eigen::Ref<const Eigen::VectorXd>& hi) {
  return make_box(lo, hi);
}

void bind_numeric(py::module_& m) {
  py::class_<Interval>(m, "Interval",
                       "A closed interval [lo, hi] of reals. Every arithmetic operation rounds outward,\n"
                       "so the result contains every value the operation can take on the operands.")
      .def(py::init(&make_interval), py::arg("lo"), py::arg("hi"))
      .def(py::init([](double x) { return make_interval(x, x); }), py::arg("x"), "The degenerate interval [x, x].")
      .def_static("from_string", &interval_from_string, py::arg("text"),
                  "The smallest interval containing the decimal number in `text` ('0.1' is not a double).")
      .def_static("around", &interval_around, py::arg("x"), py::arg("r"), "[x - r, x + r], rounded outward.")
      .def_property_readonly("lo", [](const Interval& x) { return x.lower(); })
      .def_property_readonly("hi", [](const Interval& x) { return x.upper(); })
      .def_property_readonly("mid", [](const Interval& x) { return midpoint(x); })
      .def_property_readonly("rad", [](const Interval& x) { return radius(x); }, "Radius, rounded up.")
      .def_property_readonly("width", [](const Interval& x) { return boost::numeric::width(x); })
      .def("contains", [](const Interval& x, double v) { return x.lower() <= v && v <= x.upper(); }, py::arg("x"))
      .def(py::self + py::self)
      .def(py::self - py::self)
      .def(py::self * py::self)
      .def(py::self / py::self)
      .def(py::self + double())
      .def(py::self - double())
      .def(py::self * double())
      .def(py::self / double())
      .def(double() + py::self)
      .def(double() - py::self)
      .def(double() * py::self)
      .def(double() / py::self)
      .def(-py::self)
      .def("__pow__", [](const Interval& x, int n) { return sets::pow(x, n); }, py::is_operator())
      .def("__eq__", [](const Interval& a, const Interval& b) { return a.lower() == b.lower() && a.upper() == b.upper(); })
      .def("__iter__", [](const Interval& x) { return py::iter(py::make_tuple(x.lower(), x.upper())); })
      .def("__repr__", [](const Interval& x) { return "Interval" + to_string(x); })
      .def("__str__", [](const Interval& x) { return to_string(x); })
      .def(py::pickle([](const Interval& x) { return py::make_tuple(x.lower(), x.upper()); },
                      [](py::tuple t) { return make_interval(t[0].cast<double>(), t[1].cast<double>()); }));
  m.def("hull", [](const Interval& a, const Interval& b) { return hull(a, b); }, py::arg("a"), py::arg("b"),
        "Interval hull of two intervals.");
  m.def("sqrt", [](const Interval& x) { return boost::numeric::sqrt(x); }, py::arg("x"));
  m.def("exp", [](const Interval& x) { return boost::numeric::exp(x); }, py::arg("x"));
  m.def("log", [](const Interval& x) { return boost::numeric::log(x); }, py::arg("x"));
  m.def("sin", [](const Interval& x) { return boost::numeric::sin(x); }, py::arg("x"));
  m.def("cos", [](const Interval& x) { return boost::numeric::cos(x); }, py::arg("x"));

  py::class_<IntervalVector>(m, "Box",
                             "A box [lo_1, hi_1] x ... x [lo_n, hi_n] (an interval vector). Ends may be infinite.")
      .def(py::init(&box_from_bounds), py::arg("lower"), py::arg("upper"),
           "Box from its lower and upper corners (InputError if lower > upper somewhere or NaN).")
      .def(py::init([](const std::vector<Interval>& xs) {
             IntervalVector b(static_cast<Eigen::Index>(xs.size()));
             for (std::size_t i = 0; i < xs.size(); ++i) b[static_cast<Eigen::Index>(i)] = xs[i];
             return b;
           }),
           py::arg("intervals"), "Box from a list of Interval.")
      .def_property_readonly("dimension", [](const IntervalVector& b) { return b.size(); })
      .def_property_readonly("lower", [](const IntervalVector& b) { return lower(b); })
      .def_property_readonly("upper", [](const IntervalVector& b) { return upper(b); })
      .def_property_readonly("midpoint", [](const IntervalVector& b) { return midpoint(b); })
      .def_property_readonly("radius", [](const IntervalVector& b) { return radius(b); }, "Radii, rounded up.")
      .def("to_array", [](const IntervalVector& b) { return box_array(b); }, "n x 2 array of [lower, upper] rows.")
      .def("contains", [](const IntervalVector& b, const Eigen::VectorXd& x) {
             check_dimension(x, b.size(), "Box.contains: x");
             return contains(b, x);
           },
           py::arg("x"), "Is the point in the (closed) box? Exact comparison of doubles.")
      .def("volume", [](const IntervalVector& b) { return volume(b); }, "Product of the widths (rounded up).")
      .def("hull", [](const IntervalVector& a, const IntervalVector& b) {
             if (a.size() != b.size()) throw InputError("Box.hull: dimensions " + std::to_string(a.size()) + " and " + std::to_string(b.size()));
             return hull(a, b);
           },
           py::arg("other"))
      .def("__len__", [](const IntervalVector& b) { return b.size(); })
      .def("__getitem__", [](const IntervalVector& b, Eigen::Index i) {
             if (i < 0) i += b.size();
             if (i < 0 || i >= b.size()) throw py::index_error("Box index out of range");
             return b[i];
           })
      .def("__eq__", [](const IntervalVector& a, const IntervalVector& b) {
             return a.size() == b.size() && lower(a) == lower(b) && upper(a) == upper(b);
           })
      .def("__repr__", &box_repr)
      .def(py::pickle([](const IntervalVector& b) { return py::make_tuple(lower(b), upper(b)); },
                      [](py::tuple t) { return make_box(t[0].cast<Eigen::VectorXd>(), t[1].cast<Eigen::VectorXd>()); }));
}

}  // namespace sets::python
