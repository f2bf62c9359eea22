// The prediction study (the paper's alternating identification and prediction) and the prediction model itself.
// Poses: x [m], y [m], yaw [rad] in {R}; errors in mm and degrees, as the library reports them.
#include <optional>
#include <string>

#include "conversions.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/prediction/planned_force.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/prediction/prediction_system.hpp"
#include "pushpred/reports/prediction_summary.hpp"

namespace pushpred::python {
namespace {

/// How the observer meets the schedule (StudyOptions::observer_run, QFilterObserverOptions::start and ::output), by
/// the names the CLI takes.
struct ObserverReading {
  std::string run = "per-interval", start = "steady", output = "interval-mean";
};

StudyOptions study_options(int intervals, const std::string& span, double plan_rate_hz, const std::string& observer,
                           const std::string& estimator, double friction_coefficient, const ObserverReading& reading) {
  StudyOptions o;
  o.observer_run = parse_observer_run(reading.run);
  o.observer_options.start = parse_observer_start(reading.start);
  o.observer_options.output = parse_observer_output(reading.output);
  o.schedule.intervals = intervals;
  o.schedule.span = parse_schedule_span(span);
  o.plan_rate_hz = plan_rate_hz;
  o.observer = observer;
  o.estimator = estimator;
  o.friction_coefficient = friction_coefficient;
  return o;
}

}  // namespace

void bind_prediction(py::module_& m) {
  m.def("prediction_method_names", &prediction_method_names,
        "the study's prediction methods, in report order (dob, dob_velinit, simple, hold, const_velocity, ...)");

  m.def(
      "run_prediction_study",
      [](const SynchronisedPush& push, int intervals, const std::string& span, double plan_rate_hz,
         const std::string& observer, const std::string& estimator, double friction_coefficient,
         const std::string& observer_run, const std::string& observer_start, const std::string& observer_output) {
        const StudyOptions o = study_options(intervals, span, plan_rate_hz, observer, estimator, friction_coefficient,
                                             {observer_run, observer_start, observer_output});
        return study_dict(without_gil([&] { return run_prediction_study(push, o); }));
      },
      py::arg("push"), py::arg("intervals") = 4, py::arg("span") = "whole", py::arg("plan_rate_hz") = 10.0,
      py::arg("observer") = "dob", py::arg("estimator") = "rls", py::arg("friction_coefficient") = -1.0,
      py::arg("observer_run") = "per-interval", py::arg("observer_start") = "steady",
      py::arg("observer_output") = "interval-mean", R"doc(
The paper's prediction study on one push, as `pushpred predict` runs it. The push (span "whole" or "contact") is
split into `intervals` equal intervals; identify on the first, predict the second from the last measured pose,
add its data, predict the third, and so on. The planned force is the measured input sampled at plan_rate_hz
and held. observer: "dob" or "pid"; estimator: a relation_estimator_names() entry; friction_coefficient for the
`simple` baseline (< 0: the surface's value). observer_run ("per-interval" or "continuous"), observer_start ("steady"
or "rest") and observer_output ("interval-mean" or "point"): how the dob observer meets the schedule, as the CLI's
--observer-run, --observer-start, --observer-output (docs/reproduction.md).

Returns a dict: source, span, intervals_s [(t0, t1) in s], phases (one dict per prediction phase: phase, t0_s,
t1_s, relation (the fitted beta, eps used by `dob`), note, t_s [s], measured (n x 3: x [m], y [m], yaw [rad]),
predicted {method: n x 3, same units}, errors {method: x_mm_mean, x_mm_std, y_mm_mean, y_mm_std,
theta_deg_mean, theta_deg_std, final_pos_mm, final_theta_deg}, initial_velocity [m/s, m/s, rad/s],
method_parameters {method: {name: {value, std, unit, source}}} for the methods that report parameters, and
method_notes {method: text}, as in summary.json), identification (the observer's estimate on every identified
interval) and estimator_seconds.)doc");

  m.def(
      "study_summary",
      [](const std::vector<SynchronisedPush>& pushes, int intervals, const std::string& span, double plan_rate_hz,
         const std::string& observer, const std::string& estimator, double friction_coefficient,
         const std::string& observer_run, const std::string& observer_start, const std::string& observer_output) {
        const StudyOptions o = study_options(intervals, span, plan_rate_hz, observer, estimator, friction_coefficient,
                                             {observer_run, observer_start, observer_output});
        const nlohmann::json summary = without_gil([&] {
          Batch<PushStudy> batch;
          for (const auto& p : pushes) batch.results.push_back(run_prediction_study(p, o));
          return prediction_summary_json(batch, o);
        });
        return from_json(summary);
      },
      py::arg("pushes"), py::arg("intervals") = 4, py::arg("span") = "whole", py::arg("plan_rate_hz") = 10.0,
      py::arg("observer") = "dob", py::arg("estimator") = "rls", py::arg("friction_coefficient") = -1.0,
      py::arg("observer_run") = "per-interval", py::arg("observer_start") = "steady",
      py::arg("observer_output") = "interval-mean",
      "The summary.json of `pushpred predict` over `pushes`, as a dict (errors in mm and degrees).");

  m.def(
      "surface_friction_coefficient", &surface_friction_coefficient, py::arg("surface"),
      "Coulomb friction coefficient of a support surface for the `simple` baseline (abs: 0.14).");

  m.def(
      "plan_from_measurement",
      [](const SynchronisedPush& push, double t0_s, double t1_s, double rate_hz) {
        const PlannedForce plan = plan_from_measurement(push, t0_s, t1_s, rate_hz);
        py::dict d;
        d["t_s"] = array(plan.signal.times());
        d["u"] = array(plan.signal.values());
        d["t0_s"] = plan.t0_s;
        d["t1_s"] = plan.t1_s;
        d["rate_hz"] = plan.rate_hz;
        return d;
      },
      py::arg("push"), py::arg("t0_s"), py::arg("t1_s"), py::arg("rate_hz") = 10.0, R"doc(
The planned force of a prediction phase: the measured input sampled at rate_hz from t0_s and held (zero order).
Returns t_s (sample times [s]) and u (n x 3: f_x [N], f_y [N], torque about the centre [N m]).)doc");

  py::class_<PredictionModel>(m, "PredictionModel", R"doc(
The prediction phase's model of a planar rigid body, per channel c (x, y, rotation), M = (m, m, I):
M_c accel_c = u_c + beta_c u_c + eps_c - Coulomb friction (coulomb_force_N opposing the translational velocity;
holding a body at rest against a smaller force; regularised below coulomb_speed_scale_m_s only when CVODE integrates
it). With beta = eps = 0 and no friction it is Newton's law under the planned force.)doc")
      .def(py::init([](double mass_kg, double inertia_kgm2, const Eigen::Vector3d& beta, const Eigen::Vector3d& eps,
                       double coulomb_force_N, double coulomb_speed_scale_m_s) {
             PredictionModel model;
             model.mass_kg = mass_kg;
             model.inertia_kgm2 = inertia_kgm2;
             model.beta = beta;
             model.eps = eps;
             model.coulomb_force_N = coulomb_force_N;
             model.coulomb_speed_scale_m_s = coulomb_speed_scale_m_s;
             model.validate();
             return model;
           }),
           py::arg("mass_kg"), py::arg("inertia_kgm2"), py::arg("beta") = Eigen::Vector3d::Zero().eval(),
           py::arg("eps") = Eigen::Vector3d::Zero().eval(), py::arg("coulomb_force_N") = 0.0,
           py::arg("coulomb_speed_scale_m_s") = 1e-3)
      .def_readonly("mass_kg", &PredictionModel::mass_kg, "m [kg]")
      .def_readonly("inertia_kgm2", &PredictionModel::inertia_kgm2, "I [kg m^2]")
      .def_readonly("beta", &PredictionModel::beta, "beta per channel (x, y, rotation) [-]")
      .def_readonly("eps", &PredictionModel::eps, "eps per channel [N, N, N m]")
      .def_readonly("coulomb_force_N", &PredictionModel::coulomb_force_N, "Coulomb friction force [N] (0: none)")
      .def("__repr__",
           [](const PredictionModel& model) {
             return "PredictionModel(mass_kg=" + repr_number(model.mass_kg) +
                    ", inertia_kgm2=" + repr_number(model.inertia_kgm2) + ", beta=" + repr_vector(model.beta) +
                    ", eps=" + repr_vector(model.eps) + ", coulomb_force_N=" + repr_number(model.coulomb_force_N) +
                    ", coulomb_speed_scale_m_s=" + repr_number(model.coulomb_speed_scale_m_s) + ")";
           })
      .def_static(
          "from_relation",
          [](const SynchronisedPush& push, const py::dict& relation) {
            PredictionModel model = relation_prediction_model(push.shape, relation["beta"].cast<Eigen::Vector3d>(),
                                                              relation["eps"].cast<Eigen::Vector3d>());
            model.validate();
            return model;
          },
          py::arg("push"), py::arg("relation"),
          "The paper's `dob` model: the push's shape's mass and inertia, beta and eps from a relation dict.");

  m.def(
      "predict_poses",
      [](const PredictionModel& model, const SynchronisedPush& push, double t0_s, double t1_s, double plan_rate_hz,
         std::optional<Eigen::Vector3d> pose0, const Eigen::Vector3d& velocity0,
         std::optional<Eigen::VectorXd> output_times_s, const std::string& integrator) {
        if (integrator != "closed_form" && integrator != "cvode")
          throw InputError("predict_poses: integrator must be 'closed_form' or 'cvode', not '" + integrator + "'");
        const PlannedForce plan = plan_from_measurement(push, t0_s, t1_s, plan_rate_hz);
        const Eigen::Index first = push.index_at(t0_s);
        Eigen::VectorXd times;
        if (output_times_s) {
          times = *output_times_s;
        } else {
          const Eigen::Index last = std::min<Eigen::Index>(push.size() - 1, push.index_at(t1_s));
          times = push.t_s.segment(first, last - first + 1);
        }
        const Eigen::Vector3d start = pose0 ? *pose0 : Eigen::Vector3d(push.pose.row(first).transpose());
        return array(without_gil([&] {
          return integrator == "closed_form" ? predict_poses_exactly(model, plan, start, velocity0, times)
                                             : predict_poses(model, plan, start, velocity0, times);
        }));
      },
      py::arg("model"), py::arg("push"), py::arg("t0_s"), py::arg("t1_s"), py::arg("plan_rate_hz") = 10.0,
      py::arg("pose0") = py::none(), py::arg("velocity0") = Eigen::Vector3d::Zero().eval(),
      py::arg("output_times_s") = py::none(), py::arg("integrator") = "closed_form", R"doc(
Predicts the pose under `model` from t0_s to t1_s [s] with the push's measured input planned at plan_rate_hz
(plan_from_measurement). pose0 (x [m], y [m], yaw [rad]) defaults to the measured pose at t0_s, velocity0
[m/s, m/s, rad/s] to rest; output_times_s to the push's grid times in [t0_s, t1_s]. Returns n x 3 poses.
integrator "closed_form" (the default, what the study's dob, dob_velinit and simple methods use) solves the model
per plan step in closed form, Coulomb friction unregularised; "cvode" integrates it with CVODE, the friction
regularised below coulomb_speed_scale_m_s (predict_poses_exactly in prediction_system.hpp).)doc");
}

}  // namespace pushpred::python
