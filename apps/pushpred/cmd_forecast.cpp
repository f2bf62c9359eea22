// `pushpred forecast --model object.json --object-pose X,Y,YAW --tip X,Y (--direction DEG --speed MM_S [--length MM]
// | --path FILE) --out DIR`: the whole push forecast from a learned object model (docs/forecast.md): forecast.csv and
// forecast.json (the trajectory to rest with its 90 % regions, mm and degrees), samples.csv with --samples (the
// ensemble's trajectories), and the top-down figure (forecast.gp, forecast.png where gnuplot is installed). All or
// nothing (StagedOutput).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/reading/text_files.hpp"
#include "pushpred/reports/forecast_report.hpp"
#include "pushpred/reports/plotting.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred::app {
namespace {

struct ForecastArgs {
  std::string model, out, data, pose, tip, path;
  double direction_deg = NAN, speed_mm_s = 0, length_mm = 50, step_s = 0.01;
  bool samples = false;
};

std::vector<double> numbers(const std::string& text, std::size_t count, const std::string& flag) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string part;
  while (std::getline(s, part, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(part, &used));
      if (used != part.size() || !std::isfinite(v.back())) throw std::invalid_argument(part);
    } catch (const std::exception&) {
      throw InputError(flag + ": '" + text + "' is not " + std::to_string(count) + " numbers separated by commas");
    }
  }
  if (v.size() != count)
    throw InputError(flag + ": expected " + std::to_string(count) + " numbers separated by commas, got '" + text + "'");
  return v;
}

/// A path file: rows t_s,x_mm,y_mm of three finite numbers (an optional header line starting with "t"; blank lines and
/// # comments allowed), times from 0 increasing. Errors name the file and line (reading/text_files.hpp).
TipPlan read_path_file(const std::string& file) {
  std::vector<double> t, x, y;
  bool first = true;
  for_each_csv_row(
      read_text_file(file, "a tip path file"), file, [&](const std::string& line, const std::string& where) {
        const bool header = first && line.rfind("t", 0) == 0;
        first = false;
        if (header) return;
        std::vector<std::string> fields;
        std::stringstream s(line);
        std::string field;
        while (std::getline(s, field, ',')) fields.push_back(field);
        if (fields.size() != 3)
          throw InputError(about(where, "expected three numbers t_s,x_mm,y_mm, got '" + plain_text(line) + "'"));
        double v[3];
        for (std::size_t k = 0; k < 3; ++k) {
          try {
            std::size_t used = 0;
            v[k] = std::stod(fields[k], &used);
            if (used != fields[k].size()) throw std::invalid_argument(fields[k]);
          } catch (const std::exception&) {
            throw InputError(about(where, "'" + plain_text(fields[k]) + "' is not a number"));
          }
          if (!std::isfinite(v[k])) throw InputError(about(where, "'" + plain_text(fields[k]) + "' is not finite"));
        }
        t.push_back(v[0]);
        x.push_back(1e-3 * v[1]);
        y.push_back(1e-3 * v[2]);
      });
  Eigen::VectorXd times = Eigen::Map<Eigen::VectorXd>(t.data(), static_cast<Eigen::Index>(t.size()));
  Eigen::MatrixX2d p(static_cast<Eigen::Index>(t.size()), 2);
  for (std::size_t k = 0; k < t.size(); ++k) p.row(static_cast<Eigen::Index>(k)) << x[k], y[k];
  try {
    return TipPlan::waypoints(times, p);
  } catch (const InputError& e) {
    throw InputError(about(file, e.what()));
  }
}

int run_forecast(const ForecastArgs& a) {
  const bool straight = !std::isnan(a.direction_deg) || a.speed_mm_s > 0;
  if (straight == !a.path.empty())
    throw InputError("give the plan either as --direction and --speed (a straight push) or as --path FILE, not both");
  if (straight && (std::isnan(a.direction_deg) || !(a.speed_mm_s > 0)))
    throw InputError("a straight push needs both --direction DEG and --speed MM_S");
  const std::vector<double> pose = numbers(a.pose, 3, "--object-pose");
  const std::vector<double> tip = a.tip.empty() ? std::vector<double>() : numbers(a.tip, 2, "--tip");
  if (straight && tip.empty()) throw InputError("a straight push needs --tip X_MM,Y_MM (where the tip starts)");
  // Within a recording's plausible positions (10 m from the robot) and a turn of yaw: 1e300 mm gave a forecast that
  // was not finite, blamed on the object model, or one of an object the tip never reached.
  check_plausible_pose(Eigen::Vector3d(1e-3 * pose[0], 1e-3 * pose[1], pose[2] * M_PI / 180), "--object-pose");
  if (!tip.empty()) check_plausible_position(1e-3 * Eigen::Vector2d(tip[0], tip[1]), "--tip");
  const std::filesystem::path data = data_folder_if_any(a.data.empty() ? std::nullopt : std::optional(a.data));
  StagedOutput out(a.out);  // checks the destination before any work
  const ObjectModel model = read_object_model(a.model, data);
  const auto straight_plan = [&] {
    try {
      return TipPlan::straight(
          1e-3 * Eigen::Vector2d(tip[0], tip[1]),
          Eigen::Vector2d(std::cos(a.direction_deg * M_PI / 180), std::sin(a.direction_deg * M_PI / 180)),
          1e-3 * a.speed_mm_s, 1e-3 * a.length_mm);
    } catch (const InputError& e) {
      throw InputError(std::string("--tip, --direction, --speed, --length: ") + e.what());
    }
  };
  TipPlan plan = straight ? straight_plan() : read_path_file(a.path);
  if (!straight && !tip.empty() && (plan.start_m() - 1e-3 * Eigen::Vector2d(tip[0], tip[1])).norm() > 1e-6)
    throw InputError(about(a.path, "the path does not start at --tip (leave --tip out with --path)"));
  const Eigen::Vector3d pose0(1e-3 * pose[0], 1e-3 * pose[1], pose[2] * M_PI / 180);
  const Eigen::VectorXd times = forecast_output_times(model, plan, pose0, a.step_s);
  const ForecastDistribution d = forecast_distribution(model, plan, pose0, times, a.samples);
  // An object model whose numbers are far out of range (a region scale of 1e300) gives an infinite forecast.
  if (!d.mean.allFinite() || !d.position_radius_m.allFinite() || !d.yaw_halfwidth_rad.allFinite())
    throw InputError(about(a.model, "the forecast from this object model is not finite: its numbers are out of range"));
  write_text_atomically(out.path("forecast.csv"), forecast_csv(d, plan));
  write_text_atomically(out.path("forecast.json"), json_text(forecast_json(model, plan, pose0, d)));
  if (a.samples) {
    std::ostringstream s;
    s.precision(10);
    s << "member,push,t_s,x_mm,y_mm,yaw_deg\n";
    for (std::size_t m = 0; m < d.members.size(); ++m)
      for (Eigen::Index k = 0; k < times.size(); ++k)
        s << m << "," << model.pushes[m].name << "," << times(k) << "," << 1e3 * d.members[m](k, 0) << ","
          << 1e3 * d.members[m](k, 1) << "," << d.members[m](k, 2) * 180 / M_PI << "\n";
    write_text_atomically(out.path("samples.csv"), s.str());
  }
  write_text_atomically(out.path("outline.dat"), forecast_outline_data(model, d));
  write_text_atomically(out.path("forecast.gp"),
                        forecast_figure_script("outline.dat", "forecast.csv", "forecast.png",
                                               "forecast: " + model.object.name + " on " + model.surface));
  const PlotRun drawn = run_gnuplot(out.path("forecast.gp"));
  out.commit();
  const Eigen::Index n = times.size() - 1;
  std::printf(
      "final pose x %.1f mm, y %.1f mm, yaw %.1f deg (90 %% region: %.1f mm, +-%.1f deg), at rest after %.2f s\n",
      1e3 * d.mean(n, 0), 1e3 * d.mean(n, 1), d.mean(n, 2) * 180 / M_PI, 1e3 * d.position_radius_m(n),
      d.yaw_halfwidth_rad(n) * 180 / M_PI, d.run.rest_time_s);
  if (!drawn.drawn) std::cout << "note: " << drawn.note << "\n";
  std::cout << "wrote " << a.out << "/forecast.csv, forecast.json" << (a.samples ? ", samples.csv" : "")
            << ", forecast.gp" << (drawn.drawn ? ", forecast.png" : "") << "\n";
  return 0;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<ForecastArgs>();
  auto* sub =
      app.add_subcommand("forecast", "Forecast a whole push from an object model, a start and a planned tip path");
  sub->add_option("--model", a->model, "Object model written by `pushpred learn` (object.json)")->required();
  sub->add_option("--object-pose", a->pose, "Object's start pose X_MM,Y_MM,YAW_DEG (at rest)")->required();
  sub->add_option("--tip", a->tip, "Tip's start X_MM,Y_MM (a straight push)");
  sub->add_option("--direction", a->direction_deg, "Straight push: direction [deg, world frame], -360 to 360")
      ->check(finite_number_in(-360, 360));
  sub->add_option("--speed", a->speed_mm_s, "Straight push: cruise speed [mm/s]")->check(kPositiveNumber);
  sub->add_option("--length", a->length_mm, "Straight push: length [mm] (default 50)")->check(kPositiveNumber);
  sub->add_option("--path", a->path, "Time-stamped tip path: CSV of t_s,x_mm,y_mm from t = 0");
  sub->add_option("--step", a->step_s, "Output step [s] (default 0.01)")->check(kPositiveNumber);
  sub->add_flag("--samples", a->samples, "Also write samples.csv: the ensemble's trajectories");
  sub->add_option("--data", a->data, "Data folder (butter's outline); default: PUSHPRED_DATA or ../shared/data/mcube");
  add_shapes(*sub);
  add_out_folder(*sub, a->out);
  sub->callback([a, &run] { run = [a] { return run_forecast(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
