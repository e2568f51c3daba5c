// Exceptions and three-valued truth.

#include "bindings.hpp"
#include "sets/core/bool_interval.hpp"
#include "sets/core/error.hpp"

namespace sets::python {

namespace {

// One Python class per library exception, each also derived from the builtin a Python user
// would catch (ValueError for bad input, ...). Module-lifetime objects: never released.
PyObject* new_exception(py::module_& m, const char* name, const char* doc, PyObject* base, PyObject* builtin) {
  const std::string qualified = std::string("sets.") + name;
  py::tuple bases = base ? py::make_tuple(py::handle(base), py::handle(builtin)) : py::make_tuple(py::handle(builtin));
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

}  // namespace

void bind_core(py::module_& m) {
  static PyObject* base = new_exception(m, "Error", "Base class of every exception of the sets library.", nullptr, PyExc_Exception);
  static PyObject* input = new_exception(
      m, "InputError", "Bad input: the message names the file, line, column, sample, field or argument.", base,
      PyExc_ValueError);
  static PyObject* numerical = new_exception(
      m, "NumericalError", "A numerical procedure could not produce a trustworthy answer (e.g. the LP solver failed).",
      base, PyExc_RuntimeError);
  static PyObject* unsupported = new_exception(
      m, "UnsupportedError", "A valid request outside what is implemented (e.g. exact H->V above 3-D).", base,
      PyExc_NotImplementedError);
  static PyObject* empty = new_exception(
      m, "EmptySetError",
      "An operation proved a set empty (for a strip update or the FPS zonotope: the data falsify the model).", base,
      PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(input, e.what());
    } catch (const NumericalError& e) {
      PyErr_SetString(numerical, e.what());
    } catch (const UnsupportedError& e) {
      PyErr_SetString(unsupported, e.what());
    } catch (const EmptySetError& e) {
      PyErr_SetString(empty, e.what());
    }
  });

  py::enum_<BoolInterval>(m, "BoolInterval",
                          "Three-valued truth of a predicate that floating point cannot always decide:\n"
                          "`yes` and `no` are proven, `unknown` is not a guess. `bool()` of `unknown` raises\n"
                          "ValueError, so an undecided answer is never silently taken as true or false.")
      .value("no", BoolInterval::no)
      .value("yes", BoolInterval::yes)
      .value("unknown", BoolInterval::unknown)
      .def("__bool__",
           [](BoolInterval b) {
             if (b == BoolInterval::unknown)
               throw py::value_error("BoolInterval.unknown has no truth value (the computation could not decide)");
             return b == BoolInterval::yes;
           })
      .def("__str__", [](BoolInterval b) { return std::string(to_string(b)); });
}

}  // namespace sets::python
