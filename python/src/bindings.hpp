#pragma once
// Shared declarations of the pybind11 module sets._sets: one bind_* function per layer, called in
// layer order from module.cpp (a layer's types must be registered before those that use them).

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "sets/numeric/interval_matrix.hpp"

// A box is the Python class sets.Box, not a numpy array of intervals: without this, pybind11's
// Eigen caster would claim IntervalVector (it handles every Eigen::Matrix) and fail on the
// Interval scalar. Every binding file includes this header first.
PYBIND11_MAKE_OPAQUE(sets::IntervalVector)

namespace sets::python {

namespace py = pybind11;

/// Long library calls run without the GIL (other Python threads, e.g. Dask's, go on meanwhile).
using release_gil = py::call_guard<py::gil_scoped_release>;

void bind_core(py::module_& m);       // exceptions, BoolInterval
void bind_numeric(py::module_& m);    // Interval, Box
void bind_domains(py::module_& m);    // Zonotope, Ellipsoid, HPolytope, VPolytope, set I/O
void bind_fps(py::module_& m);        // FeasibleParameterSet, pui, support, outer_zonotope
void bind_models_data(py::module_& m);  // ModelFile, Recording, Simulator
void bind_methods(py::module_& m);    // the four papers' entry points
void bind_examples(py::module_& m);   // the papers' example systems and data generators
void bind_diagnosis(py::module_& m);  // diagnose, its JSON, text and report page

}  // namespace sets::python
