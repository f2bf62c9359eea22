// The compiled part of the Python package `pushpred` (pushpred._core); python/pushpred/__init__.py re-exports it.
// Errors: the library's InputError becomes pushpred.InputError (a ValueError), SolverError becomes
// pushpred.SolverError (a RuntimeError), both with the library's message.
#include "conversions.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/core/version.hpp"

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  m.doc() = "pushpred: predict where a pushed object goes, and explain why predictions miss (C++ core).";
  m.attr("__version__") = pushpred::kVersion;
  py::register_exception<pushpred::InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<pushpred::SolverError>(m, "SolverError", PyExc_RuntimeError);
  for (const char* name : {"InputError", "SolverError"}) m.attr(name).attr("__module__") = "pushpred";
  pushpred::python::bind_reading(m);
  pushpred::python::bind_observers(m);
  pushpred::python::bind_estimators(m);
  pushpred::python::bind_prediction(m);
  pushpred::python::bind_simulation(m);
  pushpred::python::bind_diagnosis(m);
  pushpred::python::bind_forecast(m);
}
