#pragma once
// Small conversions shared by the binding files.

#include <Eigen/Core>

#include <string>

#include "sets/core/error.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace sets::python {

/// n x 2 array of [lower, upper] rows.
inline Eigen::MatrixX2d box_array(const IntervalVector& b) {
  Eigen::MatrixX2d a(b.size(), 2);
  for (Eigen::Index i = 0; i < b.size(); ++i) a.row(i) << b[i].lower(), b[i].upper();
  return a;
}

inline void check_dimension(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Index n, const std::string& what) {
  if (x.size() != n)
    throw InputError(what + " has " + std::to_string(x.size()) + " entries, expected " + std::to_string(n));
}

/// Interval matrix from its lower and upper ends (InputError naming `what` on a size mismatch
/// or lower > upper).
inline IntervalMatrix interval_matrix(const Eigen::Ref<const Eigen::MatrixXd>& lo, const Eigen::Ref<const Eigen::MatrixXd>& hi,
                                      const std::string& what) {
  if (lo.rows() != hi.rows() || lo.cols() != hi.cols())
    throw InputError(what + ": lower is " + std::to_string(lo.rows()) + "x" + std::to_string(lo.cols()) + ", upper " +
                     std::to_string(hi.rows()) + "x" + std::to_string(hi.cols()));
  IntervalMatrix M(lo.rows(), lo.cols());
  for (Eigen::Index i = 0; i < lo.rows(); ++i)
    for (Eigen::Index j = 0; j < lo.cols(); ++j) {
      if (!(lo(i, j) <= hi(i, j)))
        throw InputError(what + ": entry (" + std::to_string(i) + ", " + std::to_string(j) + ") has lower > upper or NaN");
      M(i, j) = Interval(lo(i, j), hi(i, j));
    }
  return M;
}

}  // namespace sets::python

#include <pybind11/pybind11.h>

namespace sets::python {

/// Options structs: `T(field=value, ...)` from Python, starting from the C++ defaults (an
/// unknown field raises AttributeError).
template <class T, class... Extra>
void with_keywords(pybind11::class_<T, Extra...>& c) {
  namespace py = pybind11;
  c.def(py::init([](const py::kwargs& kw) {
          py::object o = py::cast(T{});
          for (const auto& [k, v] : kw) py::setattr(o, k, v);
          return o.cast<T>();
        }),
        "Keyword arguments set the fields of the same names (the others keep their defaults).");
}

}  // namespace sets::python
