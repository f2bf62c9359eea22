#pragma once
// What `forecast` and `forecast-study` write: the forecast trajectory with its 90 % regions (CSV, JSON, mm and
// degrees), the top-down figure's data and gnuplot script, and the study's summary.json, per-push CSV and tables.md.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/forecast/forecast_study.hpp"

namespace pushpred {

/// The forecast as CSV: t_s, x_mm, y_mm, yaw_deg, radius90_mm, yaw_halfwidth90_deg, tip_x_mm, tip_y_mm.
std::string forecast_csv(const ForecastDistribution& d, const TipPlan& plan);
/// The forecast as JSON: the inputs (object, plan, start), the final pose and its region, the trajectory.
nlohmann::json forecast_json(const ObjectModel& model, const TipPlan& plan, const Eigen::Vector3d& pose0,
                             const ForecastDistribution& d);
/// The top-down figure's data (`snapshots`: outline polygons in mm, one block per snapshot) and its gnuplot script
/// drawing `png`: the outline at about `count` times with the 90 % disc about its centre, the tip path, the centre's
/// path. `title` is shown on top.
std::string forecast_outline_data(const ObjectModel& model, const ForecastDistribution& d, int count = 8);
std::string forecast_figure_script(const std::string& data_file, const std::string& csv_file, const std::string& png,
                                   const std::string& title);

/// The study's summary: per method and overall, and per object, the means of the errors (mm, degrees), coverages and
/// counts (docs/forecast.md lists the keys), with the note on what of each push is used, and per push (`folds`) what
/// its fold learned beyond the parameters: the pressure's rim weight and whether it was learned.
nlohmann::json forecast_study_summary(const std::vector<ForecastStudyPush>& pushes,
                                      const std::vector<std::pair<std::string, std::string>>& excluded,
                                      const std::vector<BatchFailure>& failures);
/// One row per push and method.
std::string forecast_study_csv(const std::vector<ForecastStudyPush>& pushes);
/// The summary as Markdown tables.
std::string forecast_study_tables(const nlohmann::json& summary);
/// A figure of the final errors per push (forecast against not moving), data in pushes.csv.
std::string forecast_study_figure_script(const std::string& png);

}  // namespace pushpred
