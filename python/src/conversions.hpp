#pragma once
// Shared by the binding sources: C++ results to numpy arrays and plain dicts, and the GIL-free call helper.
// Arrays are copies owned by Python (numpy, float64), one row per sample; their units are those of the library
// (SI; frames and signs as in lib/pushpred/preprocessing/synchronised_push.hpp).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/estimators/relation_estimator.hpp"
#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred::python {

namespace py = pybind11;

/// An Eigen expression as a numpy array that Python owns.
template <class Derived>
py::array array(const Eigen::MatrixBase<Derived>& m) {
  return py::cast(typename Derived::PlainObject(m));
}
/// A per-sample flag vector as a numpy bool array.
py::array bool_array(const std::vector<char>& flags);

/// A number as Python's repr writes a float (the shortest text that reads back to it), for the classes' reprs.
std::string repr_number(double x);
/// A 3-vector as "[x, y, z]", each number as repr_number.
std::string repr_vector(const Eigen::Vector3d& v);

/// A JSON value as plain Python (dict, list, float, str, bool, None).
py::object from_json(const nlohmann::json& json);
/// The JSON text of a Python value (a dict of the file's form) through Python's json module; a NaN or infinity, which
/// JSON cannot hold, or a value json cannot convert is an InputError naming `argument`.
std::string json_text_of(const py::handle& object, const std::string& argument);
/// Plain Python (dict, list, numbers, str, bool, None) as JSON, by json_text_of.
nlohmann::json to_json(const py::handle& object, const std::string& argument);

py::dict estimate_dict(const DisturbanceEstimate& e);
py::dict relation_dict(const RelationParameters& p);
py::dict errors_dict(const PredictionErrors& e);
py::dict study_dict(const PushStudy& s);

/// u and d_hat (n x 3) from a dict made by estimate_dict (or any mapping with keys "u" and "d_hat").
std::pair<Eigen::MatrixX3d, Eigen::MatrixX3d> input_and_disturbance(const py::dict& estimate);

/// Runs `work` with the GIL released (other Python threads go on meanwhile) and returns its result; the result
/// is converted to Python by the caller once the GIL is held again.
template <class Work>
auto without_gil(Work&& work) {
  py::gil_scoped_release release;
  return work();
}

void bind_reading(py::module_& m);
void bind_observers(py::module_& m);
void bind_estimators(py::module_& m);
void bind_prediction(py::module_& m);
void bind_forecast(py::module_& m);
void bind_simulation(py::module_& m);
void bind_diagnosis(py::module_& m);

}  // namespace pushpred::python
