#include "conversions.hpp"

#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/reports/prediction_summary.hpp"

namespace pushpred::python {

py::array bool_array(const std::vector<char>& flags) {
  py::array_t<bool> out(static_cast<py::ssize_t>(flags.size()));
  auto view = out.mutable_unchecked<1>();
  for (std::size_t k = 0; k < flags.size(); ++k) view(static_cast<py::ssize_t>(k)) = flags[k] != 0;
  return std::move(out);
}

py::object from_json(const nlohmann::json& json) {
  // Through Python's own json module: one well-tested mapping of JSON onto Python values.
  return py::module_::import("json").attr("loads")(json.dump());
}

std::string json_text_of(const py::handle& object, const std::string& argument) {
  try {
    return py::str(py::module_::import("json").attr("dumps")(object, py::arg("allow_nan") = false));
  } catch (const py::error_already_set& e) {
    // ValueError: a NaN or infinity (json would write the non-JSON NaN, which the parser then refused with a
    // "parse error at column 7313"); TypeError: a value json does not convert.
    if (e.matches(PyExc_ValueError))
      throw InputError(argument + ": holds NaN or an infinity, which a number here cannot be");
    throw InputError(argument + ": does not convert to JSON (" + std::string(py::str(e.value())) + ")");
  }
}

nlohmann::json to_json(const py::handle& object, const std::string& argument) {
  return nlohmann::json::parse(json_text_of(object, argument));
}

py::dict estimate_dict(const DisturbanceEstimate& e) {
  py::dict d;
  d["estimator"] = e.estimator;
  d["t_s"] = array(e.t_s);
  d["u"] = array(e.u);
  d["d_hat"] = array(e.d_hat);
  d["velocity"] = array(e.velocity);
  d["total"] = array(e.total);
  d["nominal_inertia"] = array(e.nominal_inertia);
  return d;
}

py::dict relation_dict(const RelationParameters& p) {
  py::dict d;
  d["estimator"] = p.estimator;
  d["beta"] = array(p.beta);
  d["eps"] = array(p.eps);
  py::list cov;
  for (int c = 0; c < 3; ++c) cov.append(array(p.covariance[static_cast<std::size_t>(c)]));
  d["covariance"] = cov;
  d["beta_std"] = array(p.beta_std());
  d["eps_std"] = array(p.eps_std());
  d["residual_std"] = array(p.residual_std);
  d["samples"] = p.samples;
  d["effective_samples"] = p.effective_samples;
  d["intervals"] = p.intervals;
  d["loss_scale"] = array(p.loss_scale);
  return d;
}

std::string repr_number(double x) { return py::repr(py::float_(x)).cast<std::string>(); }

std::string repr_vector(const Eigen::Vector3d& v) {
  return "[" + repr_number(v(0)) + ", " + repr_number(v(1)) + ", " + repr_number(v(2)) + "]";
}

py::dict errors_dict(const PredictionErrors& e) {
  // Through the library's own summary.json conversion, so that the keys are always those of `pushpred predict`.
  return from_json(errors_json(e));
}

py::dict study_dict(const PushStudy& s) {
  py::dict d;
  d["source"] = s.source;
  d["span"] = s.span;
  py::list intervals;
  for (const auto& iv : s.intervals) intervals.append(py::make_tuple(iv.t0_s, iv.t1_s));
  d["intervals_s"] = intervals;
  py::list phases;
  for (const auto& ph : s.phases) {
    py::dict p;
    p["phase"] = ph.phase;
    p["t0_s"] = ph.interval.t0_s;
    p["t1_s"] = ph.interval.t1_s;
    p["relation"] = relation_dict(ph.relation);
    p["note"] = ph.note;
    p["t_s"] = array(ph.t_s);
    p["measured"] = array(ph.measured);
    py::dict predicted, errors;
    for (const auto& [method, pose] : ph.predicted) predicted[py::str(method)] = array(pose);
    for (const auto& [method, e] : ph.errors) errors[py::str(method)] = errors_dict(e);
    p["predicted"] = predicted;
    p["errors"] = errors;
    p["initial_velocity"] = array(ph.initial_velocity);
    // The same fields as summary.json's: per method that reports any, {name: {value, std, unit, source}}; and what
    // each method says about the phase.
    py::dict method_parameters;
    for (const auto& [method, parameters] : ph.method_parameters) {
      py::dict by_name;
      for (const auto& q : parameters) {
        py::dict one;
        one["value"] = q.value;
        one["std"] = q.std;
        one["unit"] = q.unit;
        one["source"] = q.source;
        by_name[py::str(q.name)] = one;
      }
      method_parameters[py::str(method)] = by_name;
    }
    p["method_parameters"] = method_parameters;
    py::dict method_notes;
    for (const auto& [method, note] : ph.method_notes) method_notes[py::str(method)] = note;
    p["method_notes"] = method_notes;
    if (!ph.corrected_relation.estimator.empty()) p["corrected_relation"] = relation_dict(ph.corrected_relation);
    phases.append(p);
  }
  d["phases"] = phases;
  py::list identification;
  for (const auto& e : s.identification) identification.append(estimate_dict(e));
  d["identification"] = identification;
  d["estimator_seconds"] = s.estimator_seconds;
  return d;
}

std::pair<Eigen::MatrixX3d, Eigen::MatrixX3d> input_and_disturbance(const py::dict& estimate) {
  if (!estimate.contains("u") || !estimate.contains("d_hat"))
    throw py::key_error("an estimate needs the keys 'u' and 'd_hat' (n x 3 arrays)");
  return {estimate["u"].cast<Eigen::MatrixX3d>(), estimate["d_hat"].cast<Eigen::MatrixX3d>()};
}

}  // namespace pushpred::python
