// The diagnosis (diagnosis/diagnosis.hpp) through its top-level diagnose() and DiagnosisResult, converted to plain
// dicts; and effects of a user's own, written in Python, registered in an EffectLibrary.
//
// A Python effect is a force law (ForceLawEffect): the library calls into the Python object
// for kind(), description(), parameters() and unit_force(); the diagnosis runs with the GIL released and takes it
// back for each call. PythonEffect holds the Python object (rather than pybind11 moving a C++ base out of it), so
// the library may keep it for as long as it likes.
#include <memory>
#include <string>

#include "conversions.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/candidate_effect.hpp"
#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/reports/diagnosis_report.hpp"

namespace pushpred::python {
namespace {

py::dict shape_dict(const ShapeInfo& s) {
  py::dict d;
  d["name"] = s.name;
  d["mass_kg"] = s.mass_kg;
  d["inertia_kgm2"] = s.inertia_kgm2;
  d["centroid_m"] = array(s.centroid_m);
  d["dim1_m"] = s.dim1_m;
  d["dim2_m"] = s.dim2_m;
  return d;
}

class PythonEffect final : public ForceLawEffect {
 public:
  explicit PythonEffect(py::object effect) : effect_(std::move(effect)) {
    // Read once, with the GIL held (registration runs in Python): the library asks for these often.
    kind_ = call<std::string>("kind");
    description_ = call<std::string>("description");
    for (const auto& p : effect_.attr("parameters")()) {
      const auto pair = p.cast<std::pair<std::string, std::string>>();
      parameters_.push_back({pair.first, pair.second});
    }
    if (parameters_.empty()) throw InputError("effect '" + kind_ + "': parameters() lists no parameter");
    if (py::hasattr(effect_, "settings")) settings_ = call<std::vector<double>>("settings");
    if (py::hasattr(effect_, "setting_name")) {
      const auto pair = call<std::pair<std::string, std::string>>("setting_name");
      setting_name_ = {pair.first, pair.second};
    }
    if (py::hasattr(effect_, "needs_friction_base")) needs_friction_base_ = call<bool>("needs_friction_base");
  }
  ~PythonEffect() override {
    py::gil_scoped_acquire gil;
    effect_ = py::object();
    shape_cache_ = py::object();
  }

  std::string kind() const override { return kind_; }
  std::string description() const override { return description_; }
  std::vector<EffectParameter> parameters() const override { return parameters_; }
  std::vector<double> settings() const override { return settings_; }
  EffectParameter setting_name() const override { return setting_name_; }
  bool needs_friction_base() const override { return needs_friction_base_; }

  Eigen::Vector3d unit_force(int parameter, double setting, const EffectState& state,
                             const ShapeInfo& shape) const override {
    py::gil_scoped_acquire gil;
    try {
      if (shape_name_ != shape.name || shape_cache_.is_none()) {
        shape_cache_ = shape_dict(shape);
        shape_name_ = shape.name;
      }
      py::dict s;
      s["pose"] = array(state.pose);
      s["velocity"] = array(state.velocity);
      s["input"] = array(state.input);
      s["start_pose"] = array(state.start_pose);
      const Eigen::Vector3d f = effect_.attr("unit_force")(parameter, setting, s, shape_cache_).cast<Eigen::Vector3d>();
      return f;
    } catch (py::error_already_set& e) {
      throw InputError("effect '" + kind_ + "': unit_force raised " + e.what());
    } catch (const py::cast_error&) {
      throw InputError("effect '" + kind_ + "': unit_force must return three numbers (f_x [N], f_y [N], torque [N m])");
    }
  }

 private:
  template <class T>
  T call(const char* method) const {
    return effect_.attr(method)().cast<T>();
  }

  py::object effect_;
  std::string kind_, description_;
  std::vector<EffectParameter> parameters_;
  std::vector<double> settings_;
  EffectParameter setting_name_;
  bool needs_friction_base_ = false;
  mutable py::object shape_cache_ = py::none();
  mutable std::string shape_name_;
};

py::dict summary_arrays(const DiagnosisResult& r) {
  py::dict d;
  py::list residuals;
  for (const auto& t : r.residuals) {
    py::dict x;
    x["source"] = t.source;
    x["t_s"] = array(t.t_s);
    x["before"] = array(t.before);
    x["after"] = array(t.after);
    x["friction"] = array(t.friction);
    residuals.append(x);
  }
  d["residuals"] = residuals;
  py::list phases;
  for (const auto& p : r.test_phases) {
    py::dict x;
    x["source"] = p.source;
    x["phase"] = p.phase;
    x["t0_s"] = p.t0_s;
    x["t_s"] = array(p.t_s);
    py::dict error;
    for (const auto& [method, e] : p.error) error[py::str(method)] = array(e);
    x["error"] = error;
    phases.append(x);
  }
  d["test_phases"] = phases;
  return d;
}

/// DiagnosisOptions fields a Python caller may set by name (diagnose(..., name=value)); the one place to update
/// when the options change.
const std::vector<std::pair<const char*, double DiagnosisOptions::*>>& number_options() {
  static const std::vector<std::pair<const char*, double DiagnosisOptions::*>> options{
      {"bic_threshold", &DiagnosisOptions::bic_threshold},
      {"relevance_fraction", &DiagnosisOptions::relevance_fraction},
      {"floor_margin_std", &DiagnosisOptions::floor_margin_std},
      {"sensor_zero_spread_N", &DiagnosisOptions::sensor_zero_spread_N}};
  return options;
}
const std::vector<std::pair<const char*, bool DiagnosisOptions::*>>& flag_options() {
  static const std::vector<std::pair<const char*, bool DiagnosisOptions::*>> options{
      {"fit_base_settings", &DiagnosisOptions::fit_base_settings},
      {"measured_contact_compliance", &DiagnosisOptions::measured_contact_compliance}};
  return options;
}

DiagnosisOptions diagnosis_options_from(const py::kwargs& given) {
  DiagnosisOptions o;
  for (const auto& [key, value] : given) {
    const std::string name = py::str(key);
    bool known = true;
    if (name == "estimator") {
      o.study.estimator = value.cast<std::string>();
    } else if (name == "intervals") {
      o.study.schedule.intervals = value.cast<int>();
    } else {
      known = false;
      for (const auto& [option, field] : number_options())
        if (name == option) o.*field = value.cast<double>(), known = true;
      for (const auto& [option, field] : flag_options())
        if (name == option) o.*field = value.cast<bool>(), known = true;
    }
    if (!known) {
      std::string names = "estimator, intervals";
      for (const auto& option : number_options()) names += std::string(", ") + option.first;
      for (const auto& option : flag_options()) names += std::string(", ") + option.first;
      throw InputError("diagnose: unknown option '" + name + "' (known: " + names + ")");
    }
  }
  o.validate();
  return o;
}

}  // namespace

void bind_diagnosis(py::module_& m) {
  py::class_<EffectLibrary>(m, "EffectLibrary", R"doc(
The candidate effects a diagnosis tests, in a fixed order. EffectLibrary.standard() holds the library's own;
register() adds one written in Python: an object with kind() and description() (strings), parameters() (a list
of (name, unit) pairs) and unit_force(parameter, setting, state, shape), which returns the generalized force
[f_x [N], f_y [N], torque [N m]] per unit of parameter `parameter` at `state` (a dict of 3-vectors: pose
(x [m], y [m], theta [rad], {R}), velocity [m/s, m/s, rad/s], input (f_x [N], f_y [N], torque [N m]), start_pose)
for the object `shape` (a dict: mass_kg, inertia_kgm2, ...). Optional: settings() (a grid of a structural
constant), setting_name() ((name, unit)), needs_friction_base() (bool). See pushpred.ForceLawEffect.)doc")
      .def(py::init<>(), "an empty library")
      .def_static("standard", &EffectLibrary::standard, "every effect the library ships")
      .def("__repr__",
           [](const EffectLibrary& library) {
             std::string kinds;
             for (const auto& k : library.kinds()) kinds += (kinds.empty() ? "'" : ", '") + k + "'";
             return "<pushpred.EffectLibrary of " + std::to_string(library.kinds().size()) + " effects: [" + kinds +
                    "]>";
           })
      .def("kinds", &EffectLibrary::kinds, "the effects' kinds, in library order")
      .def("remove", &EffectLibrary::remove, py::arg("kind"),
           "removes the effect called `kind`; raises InputError when there is none")
      .def(
          "register",
          [](EffectLibrary& library, py::object effect) {
            library.register_effect(std::make_unique<PythonEffect>(std::move(effect)));
          },
          py::arg("effect"), "adds a force-law effect written in Python (see the class docstring)")
      .def(
          "describe",
          [](const EffectLibrary& library) {
            py::list out;
            for (const auto& e : library.effects()) {
              py::dict d;
              d["kind"] = e->kind();
              d["description"] = e->description();
              d["test"] = effect_test_name(e->test());
              py::list params;
              for (const auto& p : e->parameters()) params.append(py::make_tuple(p.name, p.unit));
              d["parameters"] = params;
              out.append(d);
            }
            return out;
          },
          "kind, description, test and parameters of every effect, in library order");

  m.def("diagnosis_options", [] {
    const DiagnosisOptions defaults;
    py::dict d;
    d["estimator"] = defaults.study.estimator;
    d["intervals"] = defaults.study.schedule.intervals;
    for (const auto& [name, field] : number_options()) d[py::str(name)] = defaults.*field;
    for (const auto& [name, field] : flag_options()) d[py::str(name)] = defaults.*field;
    return d;
  }, "the options diagnose() takes, with their defaults");

  m.def(
      "diagnose",
      [](const std::vector<SynchronisedPush>& pushes, const EffectLibrary* library, const py::kwargs& options) {
        const DiagnosisOptions o = diagnosis_options_from(options);
        const EffectLibrary standard = library ? EffectLibrary() : EffectLibrary::standard();
        const EffectLibrary& effects = library ? *library : standard;
        auto result = std::make_unique<DiagnosisResult>(without_gil([&] { return diagnose(pushes, effects, o); }));
        py::dict d = from_json(diagnosis_json(*result, o));
        d["findings"] = findings_text(*result);
        d["traces"] = summary_arrays(*result);
        return d;
      },
      py::arg("pushes"), py::arg("library") = nullptr, R"doc(
Diagnoses `pushes` (one object on one surface) as `pushpred diagnose` does: finds what the paper's method leaves
unexplained, tests the candidate effects of `library` (None: EffectLibrary.standard()), and reports the
prediction error before and after on held-out phases. Keyword options (diagnosis_options() lists them with their
defaults): estimator (the paper's relation estimator), intervals (of the schedule), and the diagnosis' own
(bic_threshold, ...).

Returns the content of diagnosis.json as a dict (effects, error_before, error_after, error_references, ... in mm
and degrees), plus findings (one line) and traces: residuals (per fit push: t_s [s], before/after/friction,
n x 3 [N, N, N m]) and test_phases (per held-out phase: t_s [s] since its start, error {method: predicted -
measured, n x 3 [m, m, rad]}).)doc");
}

}  // namespace pushpred::python
