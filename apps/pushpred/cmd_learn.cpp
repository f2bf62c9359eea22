// `pushpred learn PUSHES... --out object.json`: identifies one object's forecast model (its parameters, their
// uncertainty and push-to-push spread, the calibration of its 90 % regions) from recorded pushes of it on one surface,
// into a versioned JSON file (docs/forecast.md). The outline is the dataset's (butter's from the data folder) unless
// --outline, --circle or --ellipse give a user's own, with --mass and --inertia.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>

#include "commands.hpp"
#include "flags.hpp"
#include "learn_arguments.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/forecast/forecast_study.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred::app {
namespace {

struct LearnArgs {
  std::vector<std::string> files;
  std::string out, data, outline_file, ellipse, name;
  double circle_m = 0, mass_kg = 0, inertia_kgm2 = 0;
  int jobs = default_jobs();
  LearnArguments learning;
};

/// The user's own object, or null for the dataset's.
std::unique_ptr<ForecastObject> own_object(const LearnArgs& a) {
  const int given = (!a.outline_file.empty()) + (a.circle_m > 0) + (!a.ellipse.empty());
  if (given == 0) {
    if (a.mass_kg > 0 || a.inertia_kgm2 > 0)
      throw InputError("--mass and --inertia go with an outline of one's own (--outline, --circle or --ellipse)");
    if (!a.name.empty())
      throw InputError(
          "--name goes with an outline of one's own (--outline, --circle or --ellipse); the dataset's "
          "objects keep their names");
    return nullptr;
  }
  if (given > 1) throw InputError("give one outline: --outline, --circle or --ellipse");
  if (!(a.mass_kg > 0) || !(a.inertia_kgm2 > 0))
    throw InputError("an outline of one's own needs --mass KG and --inertia KGM2 (about the mass centre)");
  if (!a.name.empty() && !is_shape_name(a.name))
    throw InputError("--name: '" + plain_text(a.name) +
                     "' is not a name an object may have: letters and digits only, as a shape's name (the dataset's "
                     "file names carry it as shape=NAME)");
  auto o = std::make_unique<ForecastObject>();
  o->name = a.name.empty() ? "object" : a.name;
  o->mass_kg = a.mass_kg;
  o->inertia_kgm2 = a.inertia_kgm2;
  if (!a.outline_file.empty()) {
    o->outline = std::make_shared<const ForecastOutline>(
        read_outline_csv(a.outline_file, "polygon file: " + std::filesystem::path(a.outline_file).filename().string()));
  } else if (a.circle_m > 0) {
    o->outline = std::make_shared<const ForecastOutline>(ForecastOutline::ellipse(a.circle_m, a.circle_m));
  } else {
    double ax = 0, by = 0;
    char comma = 0;
    std::istringstream s(a.ellipse);
    // Nothing may follow B ("0.05,0.03,0.01" is not an ellipse), and both are finite.
    if (!(s >> ax >> comma >> by) || comma != ',' || !(s >> std::ws).eof() || !(ax > 0) || !(by > 0) ||
        !std::isfinite(ax) || !std::isfinite(by))
      throw InputError("--ellipse: expected A,B (semi-axes in metres, positive), got '" + a.ellipse + "'");
    o->outline = std::make_shared<const ForecastOutline>(ForecastOutline::ellipse(ax, by));
  }
  // A size, mass and inertia a pushed tabletop object can have (reading/physical_bounds.hpp), named by the flags.
  const std::string outline_flag = !a.outline_file.empty() ? "--outline " + a.outline_file
                                   : a.circle_m > 0        ? std::string("--circle")
                                                           : std::string("--ellipse");
  check_outline_size(o->outline->size(), outline_flag);
  check_mass_and_inertia(o->outline->size(), a.mass_kg, a.inertia_kgm2, "--mass", "--inertia");
  o->centre_of_friction_m = o->outline->area_centroid_m();
  use_limit_surface(*o, limit_surface_named(a.learning.limit_surface));
  o->validate();
  return o;
}

int run_learn(const LearnArgs& a) {
  if (a.out.empty()) throw InputError("--out: empty path; it names the object file to write");
  const std::filesystem::path out(a.out);
  std::error_code ec;
  if (std::filesystem::is_directory(out, ec))
    throw InputError(about(a.out, "is a folder; --out names the object file to write"));
  const std::filesystem::path parent = out.has_parent_path() ? out.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(parent, ec)) throw InputError(about(a.out, "its folder does not exist"));
  const std::unique_ptr<ForecastObject> own = own_object(a);
  const std::filesystem::path data = data_folder_if_any(a.data.empty() ? std::nullopt : std::optional(a.data));
  ForecastInputs in =
      load_forecast_inputs(a.files, data, a.jobs, own.get(), true, limit_surface_named(a.learning.limit_surface));
  for (const auto& e : in.excluded) std::cerr << "excluded " << e.first << ": " << e.second << "\n";
  std::set<std::pair<std::string, std::string>> groups;
  for (const auto& c : in.cases) groups.insert({c.object, c.surface});
  if (groups.size() > 1) {
    std::string list;
    for (const auto& g : groups) list += (list.empty() ? "" : ", ") + g.first + " on " + g.second;
    report_failures(in.failures, in.cases.size());
    throw InputError("the pushes are of several objects or surfaces (" + list +
                     "): learn one at a time; nothing written");
  }
  if (in.cases.empty()) {
    const int code = report_failures(in.failures, 0);
    std::cerr << "pushpred: error: no push to learn from; nothing written\n";
    return code == 0 ? kExitNothingDone : code;
  }
  const RecordedForecastCase& first = in.cases.front();
  const ShapeInfo& shape = ShapeTable::known().find(first.object);
  // An own shape's outline is written into the object file (which then needs no shape file to be read).
  const std::string source = own                   ? first.forecast_object.outline->description()
                             : shape.own           ? "shape file: " + first.object
                             : shape.has_outline() ? "shape table: " + first.object
                                                   : "data folder: butter_outline.csv";
  LearnOptions options;
  a.learning.apply_to(options);
  options.jobs = a.jobs;
  const ObjectModel model =
      learn_object_model(first.forecast_object, first.surface, source, in.cases, in.fits, options);
  write_text_atomically(out, json_text(object_model_to_json(model)));
  std::printf(
      "learned %s on %s from %zu pushes: mu_p %.3f (push-to-push sd %.3f), c %.1f mm (sd %.1f), mu_s %.3f "
      "(sd %.3f); 90 %% regions at the end: k_pos %.2f, k_yaw %.2f (%d pushes)\n",
      model.object.name.c_str(), model.surface.c_str(), model.pushes.size(), model.parameters.pusher_friction,
      model.push_to_push_sd(0), 1e3 * model.parameters.torque_ratio_m, 1e3 * model.push_to_push_sd(1),
      model.parameters.support_friction, model.push_to_push_sd(2), model.regions.position_scale[2],
      model.regions.yaw_scale[2], model.regions.pushes);
  if (model.centre_of_friction_pushes > 0)
    std::printf("centre of friction (x, y) in the body frame: %.2f +- %.2f, %.2f +- %.2f mm, learned from %d pushes\n",
                1e3 * model.object.centre_of_friction_m.x(), 1e3 * model.centre_of_friction_standard_error_m.x(),
                1e3 * model.object.centre_of_friction_m.y(), 1e3 * model.centre_of_friction_standard_error_m.y(),
                model.centre_of_friction_pushes);
  else
    std::printf("centre of friction (x, y) in the body frame: %.2f, %.2f mm, %s\n",
                1e3 * model.object.centre_of_friction_m.x(), 1e3 * model.object.centre_of_friction_m.y(),
                model.centre_of_friction_method.c_str());
  std::printf("limit surface: %s\n", model.object.limit_surface == LimitSurfaceKind::Outline
                                         ? "the outline's pressure (c is not fitted)"
                                         : "ellipsoid of ratio c");
  if (model.object.limit_surface == LimitSurfaceKind::Outline) {
    if (model.pressure_rim_weight_pushes > 0)
      std::printf("pressure rim weight: %.3f +- %.3f (jackknife standard error), learned from %d pushes\n",
                  model.object.pressure_rim_weight, model.pressure_rim_weight_standard_error,
                  model.pressure_rim_weight_pushes);
    else
      std::printf("pressure rim weight: %.3f, %s\n", model.object.pressure_rim_weight,
                  model.pressure_shape_method.c_str());
  }
  {
    double position = 0, yaw = 0;
    for (const PushFit& f : model.pushes) {
      position += f.final_position_m / static_cast<double>(model.pushes.size());
      yaw += f.final_yaw_rad / static_cast<double>(model.pushes.size());
    }
    std::printf("the learned pushes' own fits (each push's own parameters) at the end: %.2f mm, %.2f deg mean\n",
                1e3 * position, yaw * 180 / M_PI);
  }
  if (model.similarity_averaged)
    std::printf("similarity weighting: averaged over the bandwidths 0, 2, 1 and 0.5\n");
  else
    std::printf("similarity weighting: one bandwidth, %g (0: all alike)\n", model.similarity_bandwidth);
  if (model.trend.active()) {
    std::printf(
        "parameter trend over the plan (ridge %g), change of the logarithm per 20 deg of angle, 15 mm of "
        "contact x and y, e-fold of speed:\n",
        model.trend.ridge);
    for (int i = 0; i < 3; ++i)
      std::printf("  %s: %+.2f, %+.2f, %+.2f, %+.2f\n", ForecastParameters::name(i), model.trend.slope(i, 0),
                  model.trend.slope(i, 1), model.trend.slope(i, 2), model.trend.slope(i, 3));
  } else {
    std::printf("parameter trend over the plan: none\n");
  }
  std::printf("residual correction: %s\n", model.residual_correction_method.c_str());
  std::printf("pusher friction: %s\n", model.pusher_friction_method.c_str());
  std::cout << "wrote " << a.out << "\n";
  return report_failures(in.failures, in.cases.size());
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<LearnArgs>();
  auto* sub = app.add_subcommand("learn", "Learn an object's forecast model from recorded pushes into object.json");
  add_recordings(*sub, a->files);
  sub->add_option("--out", a->out, "The object file to write (JSON)")->required();
  sub->add_option("--data", a->data, "Data folder (butter's outline); default: PUSHPRED_DATA or ../shared/data/mcube");
  add_shapes(*sub);
  sub->add_option("--outline", a->outline_file, "The object's own outline: CSV of x_m,y_m, counter-clockwise");
  sub->add_option("--circle", a->circle_m,
                  "The object's own outline: a circle of this radius [m]; an own outline is 1 mm to 2 m across")
      ->check(kPositiveNumber);
  sub->add_option("--ellipse", a->ellipse, "The object's own outline: an ellipse of semi-axes A,B [m]");
  sub->add_option("--mass", a->mass_kg, "Mass of one's own object [kg]")->check(kPositiveNumber);
  sub->add_option("--inertia", a->inertia_kgm2, "Moment of inertia of one's own object about its mass centre [kg m^2]")
      ->check(kPositiveNumber);
  sub->add_option("--name", a->name, "Name of one's own object: letters and digits only, as a shape's");
  a->learning.add_to(*sub);
  add_jobs(
      *sub, a->jobs,
      "Pushes fitted (and the rim weight's jackknife refits run) in parallel (default: all cores); the output does "
      "not depend on it");
  sub->callback([a, &run] { run = [a] { return run_learn(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
