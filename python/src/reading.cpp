// Reading and preprocessing: pushpred.load_push gives a Push, the synchronised record every later stage reads.
#include <optional>
#include <string>
#include <variant>

#include "conversions.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/jobs/inspection_job.hpp"
#include "pushpred/reading/recording.hpp"

namespace pushpred::python {
namespace {

py::dict stream_dict(const TimedStream& s, const char* a, const char* b, const char* c) {
  py::dict d;
  d["t_s"] = array(s.t_s);
  d[a] = array(s.values.col(0));
  d[b] = array(s.values.col(1));
  d[c] = array(s.values.col(2));
  return d;
}

py::dict parameters_dict(const PushParameters& p) {
  py::dict d;
  d["surface"] = p.surface;
  d["shape"] = p.shape;
  d["acceleration_m_s2"] = p.acceleration_m_s2;
  d["speed_m_s"] = p.speed_m_s;
  d["contact_side"] = p.contact_side;
  d["contact_position"] = p.contact_position;
  d["angle_rad"] = p.angle_rad;
  return d;
}

py::dict shape_dict(const ShapeInfo& s) {
  static const char* geometry[] = {"rectangle", "right_triangle", "ellipse", "hexagon", "unlisted", "polygon"};
  py::dict d;
  d["name"] = s.name;
  d["mass_kg"] = s.mass_kg;
  d["inertia_kgm2"] = s.inertia_kgm2;
  d["centroid_m"] = array(s.centroid_m);
  d["geometry"] = geometry[static_cast<int>(s.geometry)];
  d["dim1_m"] = s.dim1_m;
  d["dim2_m"] = s.dim2_m;
  d["own"] = s.own;
  if (s.geometry == Geometry::Polygon) {
    Eigen::MatrixX2d v(static_cast<Eigen::Index>(s.vertices_m.size()), 2);
    for (size_t i = 0; i < s.vertices_m.size(); ++i) v.row(static_cast<Eigen::Index>(i)) = s.vertices_m[i].transpose();
    d["vertices_m"] = array(v);
  }
  return d;
}

/// A shape argument: a name (empty: the file name's) or a dict in the shape file's JSON form (docs/own-objects.md).
using ShapeArgument = std::variant<std::string, py::dict>;

/// The own shape a dict describes, checked; InputError naming the Python argument `argument` otherwise.
std::optional<ShapeInfo> own_shape(const ShapeArgument& shape, const std::string& argument) {
  if (const auto* d = std::get_if<py::dict>(&shape)) {
    return shape_from_json_text(json_text_of(*d, argument), argument);
  }
  return std::nullopt;
}

const std::string& shape_name(const ShapeArgument& shape) {
  static const std::string none;
  const auto* s = std::get_if<std::string>(&shape);
  return s ? *s : none;
}

/// A stream from Python columns: rows [t_s, a, b, c], as the reader checks and repairs them.
TimedStream stream_from(const std::string& source, const std::string& name, const Eigen::MatrixXd& rows,
                        std::vector<StreamRepair>& repairs) {
  return condition_stream(source, name, rows, ReadOptions{}, repairs);
}

}  // namespace

void bind_reading(py::module_& m) {
  py::class_<SynchronisedPush>(m, "Push", R"doc(
One recorded push on a uniform time grid (the library's SynchronisedPush); made by load_push() or
push_from_streams(). Arrays are read-only numpy views, one row per grid sample.

Frames and signs: positions in the reference frame {R} (the paper's x-y frame) in metres, angles in radians
(object yaw unwrapped, counter-clockwise positive), forces in newtons, torques in newton metres about the
vertical axis (counter-clockwise positive). force_N is f_C, the force the pusher applies to the object (the
negative of the sensor reading). t_s counts from t0_unix_s.)doc")
      .def_readonly("source", &SynchronisedPush::source, "file the push was read from")
      .def_readonly("rate_hz", &SynchronisedPush::rate_hz, "grid rate [Hz]")
      .def_readonly("t0_unix_s", &SynchronisedPush::t0_unix_s, "Unix time of t_s = 0 [s]")
      .def_readonly("t_s", &SynchronisedPush::t_s, "grid times since t0_unix_s [s], n")
      .def_readonly("pose", &SynchronisedPush::pose, "object centre x [m], y [m], yaw [rad] (unwrapped), n x 3, {R}")
      .def_property_readonly("x_m", [](const SynchronisedPush& p) { return array(p.pose.col(0)); },
                             "object centre x [m], {R}")
      .def_property_readonly("y_m", [](const SynchronisedPush& p) { return array(p.pose.col(1)); },
                             "object centre y [m], {R}")
      .def_property_readonly("yaw_rad", [](const SynchronisedPush& p) { return array(p.pose.col(2)); },
                             "object yaw [rad], unwrapped, counter-clockwise positive")
      .def_readonly("tip_m", &SynchronisedPush::tip_m, "pusher tip position r_C [m], n x 2, {R}")
      .def_readonly("tip_yaw_rad", &SynchronisedPush::tip_yaw_rad, "tip orientation theta_tip [rad]")
      .def_readonly("force_N", &SynchronisedPush::force_N, "f_C, the force on the object [N], n x 2, {R}")
      .def_readonly("tip_torque_Nm", &SynchronisedPush::tip_torque_Nm, "T_C, minus the measured tz [N m]")
      .def_readonly("lever_m", &SynchronisedPush::lever_m, "r_m = r_C - r_O [m], n x 2, {R}")
      .def_readonly("torque_about_centre_Nm", &SynchronisedPush::torque_about_centre_Nm,
                    "T_C + r_m x f_C, the pusher's torque about the object centre [N m]")
      .def_property_readonly("in_contact", [](const SynchronisedPush& p) { return bool_array(p.in_contact); },
                             "contact per grid sample (bool)")
      .def_readonly("has_contact", &SynchronisedPush::has_contact)
      .def_readonly("contact_start_s", &SynchronisedPush::contact_start_s, "first grid time in contact [s]")
      .def_readonly("contact_end_s", &SynchronisedPush::contact_end_s, "last grid time in contact [s]")
      .def_property_readonly("parameters", [](const SynchronisedPush& p) { return parameters_dict(p.push); },
                             "push parameters from the file name (surface, shape, acceleration_m_s2, speed_m_s, ...)")
      .def_property_readonly("shape", [](const SynchronisedPush& p) { return shape_dict(p.shape); },
                             "the object: mass_kg, inertia_kgm2, outline dimensions [m]")
      .def_property_readonly("flags", [](const SynchronisedPush& p) { return p.flags.names(); },
                             "what preprocessing flagged (frozen_force_sensor, barely_moves, ...)")
      .def_property_readonly("repairs",
                             [](const SynchronisedPush& p) {
                               py::list out;
                               for (const auto& r : p.repairs) out.append(py::make_tuple(r.stream, r.what));
                               return out;
                             },
                             "the reader's and preprocessing's repairs, as (stream, what) pairs")
      .def_readonly("object_glitches", &SynchronisedPush::object_glitches)
      .def_readonly("tip_glitches", &SynchronisedPush::tip_glitches)
      .def_property_readonly("duration_s", &SynchronisedPush::duration_s, "last grid time [s]")
      .def("__len__", &SynchronisedPush::size)
      .def("applied_input", [](const SynchronisedPush& p) { return array(p.applied_input()); },
           "the paper's input u = [f_Cx [N], f_Cy [N], T_C + r_m x f_C [N m]], n x 3")
      .def("index_at", &SynchronisedPush::index_at, py::arg("t_s"),
           "index of the first grid sample at or after t_s [s] (clamped to the grid)")
      .def("__repr__", [](const SynchronisedPush& p) {
        return "<pushpred.Push " + p.source + ": " + std::to_string(p.size()) + " samples at " +
               std::to_string(static_cast<int>(p.rate_hz)) + " Hz, shape " + p.shape.name + ">";
      });

  m.def(
      "load_push",
      [](const std::filesystem::path& path, const ShapeArgument& shape, double rate_hz) {
        PreprocessOptions options;
        options.rate_hz = rate_hz;
        const std::optional<ShapeInfo> own = own_shape(shape, "shape");
        return without_gil([&] {
          if (!own) return load_push(path, shape_name(shape), options);
          return synchronise(read_recording(path), *own, options);
        });
      },
      py::arg("path"), py::arg("shape") = "", py::arg("rate_hz") = 250.0, R"doc(
Reads an MCube recording (HDF5 or JSON) and synchronises its three streams onto a uniform grid of rate_hz [Hz].
shape overrides the shape named by the file name (needed for files not named like the dataset's): a name from
pushpred.shapes(), or an own object as a dict {"name", "mass_kg", "inertia_kgm2", "centroid_m" (optional),
"outline": {"kind": "polygon", "vertices_m": [[x, y], ...]} | {"kind": "circle", "radius_m"} | {"kind": "ellipse",
"semi_axes_m": [a, b]} | {"kind": "rectangle", "sides_m": [x, y]}} (SI units, body frame; docs/own-objects.md).
Raises InputError naming the file (or the shape argument) and the problem for anything malformed.)doc");

  m.def(
      "read_recording",
      [](const std::filesystem::path& path) {
        const Recording r = without_gil([&] { return read_recording(path); });
        py::dict d;
        d["source"] = r.source;
        d["parameters"] = r.push ? py::object(parameters_dict(*r.push)) : py::none();
        d["tip_pose"] = stream_dict(r.tip_pose, "x_m", "y_m", "yaw_rad");
        d["object_pose"] = stream_dict(r.object_pose, "x_m", "y_m", "yaw_rad");
        d["ft_wrench"] = stream_dict(r.ft_wrench, "fx_N", "fy_N", "tz_Nm");
        py::list repairs;
        for (const auto& rep : r.repairs) repairs.append(py::make_tuple(rep.stream, rep.what));
        d["repairs"] = repairs;
        return d;
      },
      py::arg("path"), R"doc(
The three streams of a recording as stored (robot frame, Unix time stamps t_s [s], object yaw wrapped, ft_wrench
the reaction on the pusher), after only the reader's repairs: a dict with tip_pose, object_pose, ft_wrench (each a
dict of arrays), parameters (from the file name, or None) and repairs.)doc");

  m.def(
      "push_from_streams",
      [](const Eigen::MatrixXd& tip_pose, const Eigen::MatrixXd& object_pose, const Eigen::MatrixXd& ft_wrench,
         const ShapeArgument& shape, const std::string& source, double rate_hz) {
        const std::optional<ShapeInfo> own = own_shape(shape, "shape");
        return without_gil([&] {
          Recording r;
          r.source = source;
          r.push = parse_push_filename(source);
          r.tip_pose = stream_from(source, "tip_pose", tip_pose, r.repairs);
          r.object_pose = stream_from(source, "object_pose", object_pose, r.repairs);
          r.ft_wrench = stream_from(source, "ft_wrench", ft_wrench, r.repairs);
          PreprocessOptions options;
          options.rate_hz = rate_hz;
          return synchronise(r, own ? *own : shape_for(r, shape_name(shape)), options);
        });
      },
      py::arg("tip_pose"), py::arg("object_pose"), py::arg("ft_wrench"), py::arg("shape") = "",
      py::arg("source") = "arrays", py::arg("rate_hz") = 250.0, R"doc(
A Push from your own streams, each an n x 4 array of rows [t [s, Unix], a, b, c] in the robot frame:
tip_pose and object_pose (x [m], y [m], yaw [rad]) and ft_wrench (fx [N], fy [N], tz [N m], the reaction on the
pusher as the sensor reads it). shape names an object of pushpred.shapes(), or is an own object's dict (as
load_push's); it may be left empty when source is a dataset file name. The streams are checked, repaired and synchronised as a file's are.)doc");

  m.def(
      "shapes",
      [] {
        py::dict d;
        for (const auto& s : ShapeTable::known().shapes()) d[py::str(s.name)] = shape_dict(s);
        return d;
      },
      "the known shapes: the dataset's and those given to use_shapes; name -> mass_kg, inertia_kgm2, centroid_m, "
      "geometry, dimensions [m], own, vertices_m (polygons)");

  m.def(
      "use_shapes",
      [](const std::variant<std::filesystem::path, py::dict, py::list>& shapes) {
        ShapeTable own;
        if (const auto* path = std::get_if<std::filesystem::path>(&shapes)) {
          own = ShapeTable::from_file(*path);
        } else {
          const py::object value = std::holds_alternative<py::dict>(shapes) ? py::object(std::get<py::dict>(shapes))
                                                                            : py::object(std::get<py::list>(shapes));
          own = ShapeTable::from_json_text(json_text_of(value, "shapes"), "shapes");
        }
        ShapeTable::use_own_shapes(own);
      },
      py::arg("shapes"), R"doc(
Adds own objects to the known shapes for the rest of the process, as the program's --shapes FILE: a shape file
(CSV or JSON, docs/own-objects.md), one shape dict (as load_push's shape) or a list of them. A shape of a known
name replaces it; every later lookup by name (a file name's shape=, shape="name", simulate's shape) finds them.
Raises InputError naming the file or the argument and the problem.)doc");

  m.def(
      "shape_from_dict", [](const py::dict& shape) { return shape_dict(*own_shape(shape, "shape")); }, py::arg("shape"),
      "An own object's dict (as load_push's shape) checked and completed: its dict as shapes() gives it.");

  m.def(
      "parse_push_filename",
      [](const std::filesystem::path& name) -> py::object {
        const auto p = parse_push_filename(name.string());
        return p ? py::object(parameters_dict(*p)) : py::none();
      },
      py::arg("filename"), "the push parameters of an MCube file name, or None when it does not follow the pattern");

  m.def(
      "data_folder",
      [](std::optional<std::filesystem::path> folder) {
        return resolve_data_folder(folder ? std::optional<std::string>(folder->string()) : std::nullopt).string();
      },
      py::arg("folder") = py::none(), R"doc(
The real-recordings folder: folder when given, else $PUSHPRED_DATA, else the folder fixed at build time
(../shared/data/mcube beside the source tree). Raises InputError naming every place tried when none exists.)doc");

  m.def(
      "list_recordings",
      [](const std::filesystem::path& folder, const std::string& surface) {
        std::vector<std::string> out;
        for (const auto& p : list_recordings(folder, surface)) out.push_back(p.string());
        return out;
      },
      py::arg("folder"), py::arg("surface") = "", "recordings (*.h5, *.json) below folder[/surface], sorted by name");

  m.def(
      "inspect",
      [](const SynchronisedPush& push) {
        const Inspection i = inspect(push);
        py::dict d;
        d["source"] = i.source;
        d["surface"] = i.surface;
        d["shape"] = i.shape;
        d["duration_s"] = i.duration_s;
        d["object_rate_hz"] = i.object_rate_hz;
        d["force_rate_hz"] = i.force_rate_hz;
        d["tip_rate_hz"] = i.tip_rate_hz;
        d["has_contact"] = i.has_contact;
        d["contact_start_s"] = i.contact_start_s;
        d["contact_end_s"] = i.contact_end_s;
        d["glitches_removed"] = i.glitches_removed;
        d["repairs"] = i.repairs;
        d["flags"] = i.flags;
        d["travel_mm"] = i.travel_mm;
        d["rotation_deg"] = i.rotation_deg;
        d["mean_contact_force_N"] = i.mean_contact_force_N;
        d["max_tip_yaw_deg"] = i.max_tip_yaw_deg;
        return d;
      },
      py::arg("push"), "what `pushpred inspect` reports for one push (travel in mm, rotation in degrees, force in N)");
}

}  // namespace pushpred::python
