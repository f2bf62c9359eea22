// The whole-push forecast: an object model learned from recorded pushes (or read from an object file) forecasts a
// planned push, or many candidate plans at once for a planner; numpy in, numpy out, SI units (metres, radians).
#include <optional>
#include <string>

#include "conversions.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/forecast/forecast_study.hpp"

namespace pushpred::python {
namespace {

std::filesystem::path data_folder_or_empty(const std::optional<std::string>& data) {
  try {
    return resolve_data_folder(data);
  } catch (const InputError&) {
    if (data) throw;
    return {};  // only butter's outline needs it, and says so by name
  }
}

Eigen::Vector3d pose3(const Eigen::VectorXd& v, const char* what) {
  if (v.size() != 3 || !v.allFinite()) throw InputError(std::string(what) + ": expected 3 finite numbers (x, y, yaw)");
  return v;
}

TipPlan plan_from(const std::optional<Eigen::VectorXd>& tip, const std::optional<Eigen::VectorXd>& direction,
                  std::optional<double> speed, double length, const std::optional<Eigen::VectorXd>& path_times,
                  const std::optional<Eigen::MatrixXd>& path_points) {
  if (path_times || path_points) {
    if (!path_times || !path_points || tip || direction || speed)
      throw InputError("give either tip, direction and speed (a straight push) or path_times and path_points");
    if (path_points->cols() != 2) throw InputError("path_points: expected an n x 2 array");
    return TipPlan::waypoints(*path_times, *path_points);
  }
  if (!tip || !direction || !speed) throw InputError("a straight push needs tip, direction and speed");
  if (tip->size() != 2 || direction->size() != 2) throw InputError("tip and direction: 2 numbers each");
  return TipPlan::straight(*tip, *direction, *speed, length);
}

py::dict distribution_dict(const ForecastDistribution& d) {
  py::dict out;
  out["t_s"] = array(d.times_s);
  out["pose"] = array(d.mean);
  out["radius90_m"] = array(d.position_radius_m);
  out["yaw_halfwidth90_rad"] = array(d.yaw_halfwidth_rad);
  out["position_spread_m"] = array(d.position_spread_m);
  out["yaw_spread_rad"] = array(d.yaw_spread_rad);
  out["rest_time_s"] = d.run.rest_time_s;
  out["reached_rest"] = d.run.reached_rest;
  if (!d.members.empty()) {
    py::list members;
    for (const auto& m : d.members) members.append(array(m));
    out["samples"] = members;
  }
  return out;
}

}  // namespace

void bind_forecast(py::module_& m) {
  py::class_<ObjectModel>(m, "ObjectModel", R"doc(
A learned object (docs/forecast.md): parameters, their push-to-push spread, the learned pushes' own parameters and
the calibration of the 90 % regions. Made by learn_object_model() or read_object_model(); to_dict() gives the object
file's content.)doc")
      .def_property_readonly("name", [](const ObjectModel& o) { return o.object.name; })
      .def_property_readonly("surface", [](const ObjectModel& o) { return o.surface; })
      .def_property_readonly("parameters",
                             [](const ObjectModel& o) {
                               py::dict d;
                               d["pusher_friction"] = o.parameters.pusher_friction;
                               d["torque_ratio_m"] = o.parameters.torque_ratio_m;
                               d["support_friction"] = o.parameters.support_friction;
                               return d;
                             })
      .def_property_readonly(
          "centre_of_friction_m", [](const ObjectModel& o) { return Eigen::Vector2d(o.object.centre_of_friction_m); },
          "The centre of friction in the body frame [m]: learned jointly over the pushes (see "
          "centre_of_friction_pushes), or the outline's centroid")
      .def_property_readonly(
          "centre_of_friction_standard_error_m",
          [](const ObjectModel& o) { return Eigen::Vector2d(o.centre_of_friction_standard_error_m); })
      .def_property_readonly(
          "centre_of_friction_pushes", [](const ObjectModel& o) { return o.centre_of_friction_pushes; },
          "How many pushes the centre of friction was learned from (0: not learned)")
      .def_property_readonly(
          "limit_surface", [](const ObjectModel& o) { return std::string(limit_surface_name(o.object.limit_surface)); },
          "\"ellipsoid\" or \"outline\"")
      .def_property_readonly(
          "pressure_rim_weight", [](const ObjectModel& o) { return o.object.pressure_rim_weight; },
          "The support pressure's rim weight under the outline's limit surface (0: uniform; > 0 loads the rim, < 0 "
          "the middle): learned (see pressure_rim_weight_pushes) or 0")
      .def_property_readonly(
          "pressure_rim_weight_standard_error",
          [](const ObjectModel& o) { return o.pressure_rim_weight_standard_error; },
          "The rim weight's standard error: the jackknife's over the learned pushes (each left out, the rim weight "
          "refitted on the others); 0 when it is not learned")
      .def_property_readonly(
          "pressure_rim_weight_pushes", [](const ObjectModel& o) { return o.pressure_rim_weight_pushes; },
          "How many pushes the rim weight was learned from (0: not learned)")
      .def("to_dict", [](const ObjectModel& o) { return from_json(object_model_to_json(o)); })
      .def(
          "forecast",
          [](const ObjectModel& model, const Eigen::VectorXd& object_pose, std::optional<Eigen::VectorXd> tip,
             std::optional<Eigen::VectorXd> direction, std::optional<double> speed_m_s, double length_m,
             std::optional<Eigen::VectorXd> times_s, std::optional<Eigen::VectorXd> path_times_s,
             std::optional<Eigen::MatrixXd> path_points_m, bool samples) {
            const Eigen::Vector3d pose0 = pose3(object_pose, "object_pose");
            const TipPlan plan = plan_from(tip, direction, speed_m_s, length_m, path_times_s, path_points_m);
            return distribution_dict(without_gil([&] {
              const Eigen::VectorXd t = times_s ? *times_s : forecast_output_times(model, plan, pose0);
              return forecast_distribution(model, plan, pose0, t, samples);
            }));
          },
          py::arg("object_pose"), py::arg("tip") = py::none(), py::arg("direction") = py::none(),
          py::arg("speed_m_s") = py::none(), py::arg("length_m") = 0.05, py::arg("times_s") = py::none(),
          py::arg("path_times_s") = py::none(), py::arg("path_points_m") = py::none(), py::arg("samples") = false,
          R"doc(
Forecasts a push from the object at rest at object_pose (x, y, yaw) along a straight plan (tip start, direction,
speed_m_s, length_m, with the rig's speed ramps) or a time-stamped path (path_times_s from 0, path_points_m n x 2).
times_s: output times since the plan's start (default: every 0.01 s until rest). Returns a dict: t_s, pose (n x 3),
radius90_m and yaw_halfwidth90_rad (the 90 % regions), the ensemble's spreads, rest_time_s, and with samples=True
the learned pushes' own trajectories (samples).)doc")
      .def(
          "forecast_batch",
          [](const ObjectModel& model, const Eigen::VectorXd& object_pose, const Eigen::MatrixXd& tips,
             const Eigen::MatrixXd& directions, const Eigen::VectorXd& speeds_m_s,
             std::optional<Eigen::VectorXd> lengths_m) {
            const Eigen::Vector3d pose0 = pose3(object_pose, "object_pose");
            const Eigen::Index n = tips.rows();
            if (tips.cols() != 2 || directions.cols() != 2 || directions.rows() != n || speeds_m_s.size() != n ||
                (lengths_m && lengths_m->size() != n))
              throw InputError("forecast_batch: tips and directions n x 2, speeds_m_s (and lengths_m) n, for n plans");
            std::vector<TipPlan> plans;
            for (Eigen::Index i = 0; i < n; ++i)
              plans.push_back(TipPlan::straight(tips.row(i).transpose(), directions.row(i).transpose(), speeds_m_s(i),
                                                lengths_m ? (*lengths_m)(i) : 0.05));
            const BatchForecast b = without_gil([&] { return forecast_batch(model, plans, pose0); });
            py::dict out;
            out["final_pose"] = array(b.final_pose);
            out["final_radius90_m"] = array(b.final_position_radius_m);
            out["final_yaw_halfwidth90_rad"] = array(b.final_yaw_halfwidth_rad);
            out["rest_time_s"] = array(b.rest_time_s);
            return out;
          },
          py::arg("object_pose"), py::arg("tips"), py::arg("directions"), py::arg("speeds_m_s"),
          py::arg("lengths_m") = py::none(), R"doc(
Forecasts many straight candidate pushes from one start at once (a planner's loop): row i of tips, directions,
speeds_m_s (and lengths_m, default 0.05 m) is one plan. Returns final_pose (n x 3), final_radius90_m,
final_yaw_halfwidth90_rad and rest_time_s, one row per plan.)doc");

  m.def(
      "read_object_model",
      [](const std::filesystem::path& path, std::optional<std::string> data) {
        return read_object_model(path, data_folder_or_empty(data));
      },
      py::arg("path"), py::arg("data") = py::none(), "Reads an object file written by `pushpred learn`.");
  m.def(
      "object_model_from_dict",
      [](const py::dict& d, std::optional<std::string> data) {
        return object_model_from_json(to_json(d, "object model"), "object model", data_folder_or_empty(data));
      },
      py::arg("model"), py::arg("data") = py::none(), "An object model from a dict in the object file's format.");
  m.def(
      "learn_object_model",
      [](const std::vector<std::string>& files, std::optional<std::string> data, int jobs,
         const std::string& limit_surface, const std::string& pressure_shape, const std::string& similarity,
         const std::string& central, const std::string& residual_correction, const std::string& pusher_friction) {
        if (jobs < 1) throw InputError("learn_object_model: jobs must be at least 1, got " + std::to_string(jobs));
        const std::filesystem::path folder = data_folder_or_empty(data);
        const LimitSurfaceKind kind = limit_surface_named(limit_surface);
        LearnOptions options;
        set_pressure_shape_choice(options, pressure_shape);
        set_similarity_choice(options, similarity);
        options.central = central_forecast_named(central);
        options.residual_correction = residual_correction_named(residual_correction);
        options.pusher_friction = pusher_friction_named(pusher_friction);
        options.jobs = jobs;
        return without_gil([&] {
          const ForecastInputs in = load_forecast_inputs(files, folder, jobs, nullptr, false, kind);
          if (!in.failures.empty()) throw InputError(about(in.failures.front().source, in.failures.front().reason));
          if (in.cases.empty()) throw InputError("learn_object_model: no push to learn from");
          for (const auto& c : in.cases)
            if (c.object != in.cases.front().object || c.surface != in.cases.front().surface)
              throw InputError("learn_object_model: the pushes are of several objects or surfaces");
          const RecordedForecastCase& first = in.cases.front();
          const ShapeInfo& shape = ShapeTable::known().find(first.object);
          const std::string source = shape.own             ? "shape file: " + first.object
                                     : shape.has_outline() ? "shape table: " + first.object
                                                           : "data folder: butter_outline.csv";
          return learn_object_model(first.forecast_object, first.surface, source, in.cases, in.fits, options);
        });
      },
      py::arg("files"), py::arg("data") = py::none(), py::arg("jobs") = 1, py::arg("limit_surface") = "ellipsoid",
      py::arg("pressure_shape") = kPressureShapeDefaultChoice, py::arg("similarity") = kSimilarityDefaultChoice,
      py::arg("central") = kCentralForecastDefaultChoice,
      py::arg("residual_correction") = kResidualCorrectionDefaultChoice,
      py::arg("pusher_friction") = kPusherFrictionDefaultChoice,
      "Learns one object's model from recorded pushes of it on one surface, as `pushpred learn` does (frozen force "
      "sensors left out); limit_surface \"ellipsoid\" (default) or \"outline\" as its --limit-surface, "
      "pressure_shape \"chosen\" (default), \"learned\" or \"uniform\" as its --pressure-shape, similarity "
      "\"chosen\" or \"averaged\" as its --similarity, central \"ensemble_mean\", \"ensemble_median\" or "
      "\"median\" as its --central, residual_correction \"none\", \"loo\" or \"chosen\" as its "
      "--residual-correction, pusher_friction \"fitted\" or \"measured\" as its --pusher-friction.");
}

}  // namespace pushpred::python
