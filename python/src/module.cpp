// sets._sets: the compiled part of the Python package `sets` (docs/python.md).

#include "bindings.hpp"

PYBIND11_MODULE(_sets, m) {
  m.doc() =
      "Guaranteed set-membership system identification (the C++ library `sets`).\n\n"
      "Sets that are guaranteed to contain the true system: outward-rounded intervals and boxes,\n"
      "zonotopes, ellipsoids, H- and V-polytopes, feasible parameter sets with certified parameter\n"
      "uncertainty intervals (PUIs), the four papers' methods and the discrepancy diagnosis.\n"
      "Arrays are numpy arrays (float64); a box is a `Box`; a point is a 1-D array.";
  using namespace sets::python;
  bind_core(m);
  bind_numeric(m);
  bind_domains(m);
  bind_fps(m);
  bind_models_data(m);
  bind_methods(m);
  bind_examples(m);
  bind_diagnosis(m);
}
