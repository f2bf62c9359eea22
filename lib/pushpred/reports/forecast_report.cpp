#include "pushpred/reports/forecast_report.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/reports/markdown_table.hpp"
#include "pushpred/reports/plotting.hpp"

namespace pushpred {
namespace {

constexpr double kMm = 1e3;
constexpr double kDeg = 180.0 / M_PI;

double mean_of(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

/// The aggregate of one method over some pushes.
nlohmann::json method_summary(const std::vector<const ForecastStudyPush*>& pushes, std::size_t m) {
  std::vector<double> fp, fy, tp, ty, cp, cy, cpf, cyf, rad, half, frad, fhalf;
  for (const auto* p : pushes) {
    const ForecastErrors& e = p->errors[m];
    fp.push_back(kMm * e.final_position_m);
    fy.push_back(kDeg * e.final_yaw_rad);
    tp.push_back(kMm * e.trajectory_position_m);
    ty.push_back(kDeg * e.trajectory_yaw_rad);
    if (e.has_regions) {
      cp.push_back(e.coverage_position);
      cy.push_back(e.coverage_yaw);
      cpf.push_back(e.final_inside_position ? 1.0 : 0.0);
      cyf.push_back(e.final_inside_yaw ? 1.0 : 0.0);
      rad.push_back(kMm * e.median_radius_m);
      half.push_back(kDeg * e.median_yaw_halfwidth_rad);
      frad.push_back(kMm * e.final_radius_m);
      fhalf.push_back(kDeg * e.final_yaw_halfwidth_rad);
    }
  }
  nlohmann::json j;
  j["final_pos_mm_mean"] = number_or_null(mean_of(fp));
  j["final_yaw_deg_mean"] = number_or_null(mean_of(fy));
  j["trajectory_pos_mm_mean"] = number_or_null(mean_of(tp));
  j["trajectory_yaw_deg_mean"] = number_or_null(mean_of(ty));
  j["coverage90_pos"] = number_or_null(mean_of(cp));
  j["coverage90_yaw"] = number_or_null(mean_of(cy));
  j["pushes"] = pushes.size();
  j["final_pos_mm_median"] = number_or_null(median(fp));
  j["final_yaw_deg_median"] = number_or_null(median(fy));
  j["coverage90_pos_final"] = number_or_null(mean_of(cpf));
  j["coverage90_yaw_final"] = number_or_null(mean_of(cyf));
  j["region90_radius_mm_median"] = number_or_null(median(rad));
  j["region90_yaw_halfwidth_deg_median"] = number_or_null(median(half));
  j["region90_final_radius_mm_median"] = number_or_null(median(frad));
  j["region90_final_yaw_halfwidth_deg_median"] = number_or_null(median(fhalf));
  return j;
}

std::string fixed(const nlohmann::json& v, int digits) {
  if (!v.is_number()) return "-";
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << v.get<double>();
  return s.str();
}

}  // namespace

std::string forecast_csv(const ForecastDistribution& d, const TipPlan& plan) {
  std::ostringstream out;
  out.precision(10);
  out << "t_s,x_mm,y_mm,yaw_deg,radius90_mm,yaw_halfwidth90_deg,tip_x_mm,tip_y_mm\n";
  Eigen::Vector2d tip, v;
  for (Eigen::Index k = 0; k < d.times_s.size(); ++k) {
    plan.evaluate(d.times_s(k), tip, v);
    out << d.times_s(k) << "," << kMm * d.mean(k, 0) << "," << kMm * d.mean(k, 1) << "," << kDeg * d.mean(k, 2) << ","
        << kMm * d.position_radius_m(k) << "," << kDeg * d.yaw_halfwidth_rad(k) << "," << kMm * tip.x() << ","
        << kMm * tip.y() << "\n";
  }
  return out.str();
}

nlohmann::json forecast_json(const ObjectModel& model, const TipPlan& plan, const Eigen::Vector3d& pose0,
                             const ForecastDistribution& d) {
  nlohmann::json j;
  j["format"] = "pushpred-forecast";
  j["version"] = 1;
  j["units"] = "mm, degrees, seconds since the plan's start; world frame of the start pose";
  j["object"] = model.object.name;
  j["surface"] = model.surface;
  j["parameters"] = {{"pusher_friction", model.parameters.pusher_friction},
                     {"torque_ratio_m", model.parameters.torque_ratio_m},
                     {"support_friction", model.parameters.support_friction}};
  j["start"] = {{"x_mm", kMm * pose0(0)},
                {"y_mm", kMm * pose0(1)},
                {"yaw_deg", kDeg * pose0(2)},
                {"tip_x_mm", kMm * plan.start_m().x()},
                {"tip_y_mm", kMm * plan.start_m().y()}};
  j["plan"] = {{"kind", plan.is_straight() ? "straight" : "path"},
               {"length_mm", kMm * plan.length_m()},
               {"end_time_s", plan.end_time_s()},
               {"end_tip_x_mm", kMm * plan.end_m().x()},
               {"end_tip_y_mm", kMm * plan.end_m().y()}};
  if (plan.is_straight())
    j["plan"]["direction"] = {plan.direction().x(), plan.direction().y()},
    j["plan"]["speed_mm_s"] = kMm * plan.speed_m_s();
  const Eigen::Index n = d.times_s.size();
  if (n > 0) {
    j["final"] = {{"t_s", d.times_s(n - 1)},
                  {"x_mm", kMm * d.mean(n - 1, 0)},
                  {"y_mm", kMm * d.mean(n - 1, 1)},
                  {"yaw_deg", kDeg * d.mean(n - 1, 2)},
                  {"radius90_mm", kMm * d.position_radius_m(n - 1)},
                  {"yaw_halfwidth90_deg", kDeg * d.yaw_halfwidth_rad(n - 1)}};
  }
  j["rest_time_s"] = d.run.rest_time_s;
  j["reached_rest"] = d.run.reached_rest;
  j["contact_time_s"] = d.run.contact_time_s;
  j["contact_sliding_fraction"] = d.run.sliding_fraction;
  j["regions"] = {{"level", 0.9},
                  {"position", "disc of radius90_mm about (x_mm, y_mm)"},
                  {"yaw", "yaw_deg +- yaw_halfwidth90_deg"},
                  {"calibration", model.regions.method},
                  {"calibration_pushes", model.regions.pushes}};
  nlohmann::json traj = nlohmann::json::array();
  for (Eigen::Index k = 0; k < n; ++k)
    traj.push_back({d.times_s(k), kMm * d.mean(k, 0), kMm * d.mean(k, 1), kDeg * d.mean(k, 2),
                    kMm * d.position_radius_m(k), kDeg * d.yaw_halfwidth_rad(k)});
  j["trajectory_columns"] = {"t_s", "x_mm", "y_mm", "yaw_deg", "radius90_mm", "yaw_halfwidth90_deg"};
  j["trajectory"] = traj;
  return j;
}

std::string forecast_outline_data(const ObjectModel& model, const ForecastDistribution& d, int count) {
  std::ostringstream out;
  out.precision(8);
  out << "# outline snapshots (x_mm,y_mm), one block per time (its plan time in the comment above it)\n";
  const std::vector<Eigen::Vector2d> outline = model.object.outline->drawing_m();
  const Eigen::Index n = d.times_s.size();
  if (n == 0) return out.str();
  std::vector<Eigen::Index> picks;
  for (int s = 0; s < count; ++s)
    picks.push_back(count == 1 ? n - 1 : (static_cast<Eigen::Index>(s) * (n - 1)) / (count - 1));
  picks.erase(std::unique(picks.begin(), picks.end()), picks.end());
  for (Eigen::Index k : picks) {
    const Eigen::Rotation2Dd R(d.mean(k, 2));
    const Eigen::Vector2d origin = d.mean.row(k).head<2>().transpose();
    out << "# t_s " << d.times_s(k) << "\n";
    for (std::size_t i = 0; i <= outline.size(); ++i) {
      const Eigen::Vector2d p = origin + R * outline[i % outline.size()];
      out << kMm * p.x() << "," << kMm * p.y() << "\n";
    }
    out << "\n\n";
  }
  return out.str();
}

std::string forecast_figure_script(const std::string& data_file, const std::string& csv_file, const std::string& png,
                                   const std::string& title) {
  std::ostringstream gp;
  gp << "# Top-down view of the forecast: the outline at several times, the 90 % position region (disc about the "
        "tracked centre), the centre's and the tip's paths. mm.\n"
     << png_terminal(png, 900, 900) << "set termoption noenhanced\nset size ratio -1\nset grid\nset key bottom right\n"
     << "set xlabel 'x [mm]'\nset ylabel 'y [mm]'\nset title " << gnuplot_quoted(title) << "\n"
     << "set datafile separator ','\n"
     << "plot '" << csv_file << "' every 10::1 using 2:3:5 with circles lc rgb '#9ecae1' fs transparent solid 0.25 "
     << "noborder title '90 % region (position)', \\\n"
     << "  '" << csv_file << "' every ::1 using 2:3 with lines lw 2 lc rgb '#08519c' title 'centre (forecast)', \\\n"
     << "  '" << csv_file << "' every ::1 using 7:8 with lines lw 2 dt 2 lc rgb '#cb181d' title 'tip (plan)', \\\n"
     << "  '" << data_file << "' using 1:2 with lines lw 1 lc rgb '#252525' title 'outline'\n";
  return gp.str();
}

nlohmann::json forecast_study_summary(const std::vector<ForecastStudyPush>& pushes,
                                      const std::vector<std::pair<std::string, std::string>>& excluded,
                                      const std::vector<BatchFailure>& failures) {
  nlohmann::json j;
  j["format"] = "pushpred-forecast-study";
  j["version"] = 1;
  j["units"] =
      "mm and degrees; coverage90: share of the recorded poses inside the 90 % region (per push, then averaged)";
  j["inputs_note"] = forecast_study_inputs_note();
  const auto& methods = forecast_study_methods();
  std::vector<const ForecastStudyPush*> all;
  std::set<std::string> surfaces;
  for (const auto& p : pushes) {
    all.push_back(&p);
    surfaces.insert(p.surface);
  }
  nlohmann::json overall;
  for (std::size_t m = 0; m < methods.size(); ++m) overall[methods[m]] = method_summary(all, m);
  j["methods"] = overall;
  std::map<std::string, std::vector<const ForecastStudyPush*>> by_object;
  for (const auto& p : pushes) by_object[surfaces.size() > 1 ? p.object + "/" + p.surface : p.object].push_back(&p);
  nlohmann::json objects;
  for (const auto& [name, list] : by_object) {
    nlohmann::json o;
    for (std::size_t m = 0; m < methods.size(); ++m) o[methods[m]] = method_summary(list, m);
    const double fp =
        o["forecast"]["final_pos_mm_mean"].is_number() ? o["forecast"]["final_pos_mm_mean"].get<double>() : 0;
    const double still =
        o["not_moving"]["final_pos_mm_mean"].is_number() ? o["not_moving"]["final_pos_mm_mean"].get<double>() : 0;
    o["not_moving_over_forecast_final_pos"] = number_or_null(fp > 0 ? still / fp : std::nan(""));
    objects[name] = o;
  }
  j["objects"] = objects;
  // Per push, what its fold learned from the others beyond the parameters (pushes.csv has them too).
  nlohmann::json folds = nlohmann::json::array();
  for (const auto& p : pushes)
    folds.push_back({{"push", p.name},
                     {"object", p.object},
                     {"surface", p.surface},
                     {"training_pushes", p.training_pushes},
                     {"rim_weight", p.rim_weight},
                     {"rim_weight_learned", p.rim_weight_learned},
                     {"residual_correction", p.residual_correction}});
  j["folds"] = folds;
  nlohmann::json ex = nlohmann::json::array();
  for (const auto& e : excluded) ex.push_back({{"push", e.first}, {"reason", e.second}});
  j["excluded"] = ex;
  nlohmann::json fl = nlohmann::json::array();
  for (const auto& f : failures) fl.push_back({{"source", f.source}, {"reason", f.reason}});
  j["failures"] = fl;
  return j;
}

std::string forecast_study_csv(const std::vector<ForecastStudyPush>& pushes) {
  std::ostringstream out;
  out.precision(8);
  out << "push,object,surface,method,final_pos_mm,final_yaw_deg,trajectory_pos_mm,trajectory_yaw_deg,coverage90_pos,"
         "coverage90_yaw,final_radius90_mm,final_yaw_halfwidth90_deg,recorded_travel_mm,recorded_turn_deg,"
         "learned_pusher_friction,learned_torque_ratio_mm,learned_support_friction,own_pusher_friction,"
         "own_torque_ratio_mm,own_support_friction,fold_rim_weight,fold_rim_weight_learned,yaw_error_quarter_deg,"
         "yaw_error_half_deg,yaw_error_three_quarters_deg,yaw_error_tip_stop_deg,yaw_error_final_deg,"
         "recorded_turn_after_tip_stop_deg,measured_pusher_friction\n";
  const auto& methods = forecast_study_methods();
  for (const auto& p : pushes)
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const ForecastErrors& e = p.errors[m];
      out << p.name << "," << p.object << "," << p.surface << "," << methods[m] << "," << kMm * e.final_position_m
          << "," << kDeg * e.final_yaw_rad << "," << kMm * e.trajectory_position_m << "," << kDeg * e.trajectory_yaw_rad
          << ",";
      if (e.has_regions)
        out << e.coverage_position << "," << e.coverage_yaw << "," << kMm * e.final_radius_m << ","
            << kDeg * e.final_yaw_halfwidth_rad;
      else
        out << ",,,";
      out << "," << kMm * p.recorded_travel_m << "," << kDeg * p.recorded_turn_rad << "," << p.learned.pusher_friction
          << "," << kMm * p.learned.torque_ratio_m << "," << p.learned.support_friction << ","
          << p.own_fit.parameters.pusher_friction << "," << kMm * p.own_fit.parameters.torque_ratio_m << ","
          << p.own_fit.parameters.support_friction << "," << p.rim_weight << "," << (p.rim_weight_learned ? 1 : 0);
      for (double stage : e.yaw_error_at_stage_rad) out << "," << kDeg * stage;
      out << "," << kDeg * e.final_yaw_error_signed_rad << "," << kDeg * p.recorded_turn_after_tip_stop_rad << ",";
      if (std::isfinite(p.measured_pusher_friction)) out << p.measured_pusher_friction;
      out << "\n";
    }
  return out.str();
}

std::string forecast_study_tables(const nlohmann::json& s) {
  std::ostringstream md;
  md << "# Forecast study (leave one push out)\n\n" << s.at("inputs_note").get<std::string>() << "\n\n";
  auto row = [&](const std::string& label, const nlohmann::json& m) {
    md << markdown_row({label, std::to_string(m.at("pushes").get<std::size_t>()), fixed(m.at("final_pos_mm_mean"), 2),
                        fixed(m.at("final_yaw_deg_mean"), 2), fixed(m.at("final_pos_mm_median"), 2),
                        fixed(m.at("final_yaw_deg_median"), 2), fixed(m.at("trajectory_pos_mm_mean"), 2),
                        fixed(m.at("trajectory_yaw_deg_mean"), 2), fixed(m.at("coverage90_pos"), 3),
                        fixed(m.at("coverage90_yaw"), 3), fixed(m.at("coverage90_pos_final"), 3),
                        fixed(m.at("coverage90_yaw_final"), 3), fixed(m.at("region90_radius_mm_median"), 2),
                        fixed(m.at("region90_yaw_halfwidth_deg_median"), 2)});
  };
  const std::string head =
      markdown_header({"", "pushes", "final mm", "final deg", "final mm (median)", "final deg (median)",
                       "trajectory mm", "trajectory deg", "cov90 pos", "cov90 yaw", "cov90 pos (final)",
                       "cov90 yaw (final)", "region radius mm (median)", "region yaw deg (median)"});
  md << "## All pushes\n\n" << head;
  for (const auto& [name, m] : s.at("methods").items()) row(name, m);
  md << "\n## Per object\n\n" << head;
  for (const auto& [object, o] : s.at("objects").items())
    for (const auto& method : forecast_study_methods()) row(object + ": " + method, o.at(method));
  if (!s.at("excluded").empty()) {
    md << "\n## Not forecast\n\n";
    for (const auto& e : s.at("excluded"))
      md << "- " << e.at("push").get<std::string>() << ": " << e.at("reason").get<std::string>() << "\n";
  }
  return md.str();
}

std::string forecast_study_figure_script(const std::string& png) {
  std::ostringstream gp;
  gp << "# Final position error per push: the forecast against not moving and rigid tip-following (pushes.csv). mm.\n"
     << png_terminal(png, 1000, 600) << "set termoption noenhanced\nset datafile separator ','\nset grid\n"
     << "set logscale y\nset ylabel 'final position error [mm]'\nset xlabel 'push (input order)'\nset key top left\n"
     << "plot 'pushes.csv' every ::1 using ($0/4):(strcol(4) eq 'forecast' ? $5 : 1/0) with points pt 7 ps 0.8 "
        "title 'forecast', \\\n"
     << "  '' every ::1 using ($0/4):(strcol(4) eq 'not_moving' ? $5 : 1/0) with points pt 1 title 'not moving', \\\n"
     << "  '' every ::1 using ($0/4):(strcol(4) eq 'rigid_tip' ? $5 : 1/0) with points pt 2 title 'rigid tip', \\\n"
     << "  '' every ::1 using ($0/4):(strcol(4) eq 'oracle_own_fit' ? $5 : 1/0) with points pt 6 "
        "title 'own fit (oracle)'\n";
  return gp.str();
}

}  // namespace pushpred
