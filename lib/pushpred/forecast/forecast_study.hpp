#pragma once
// The forecast scored on recorded pushes, leaving one push out at a time (`pushpred forecast-study`): per object and
// surface, each push is forecast by the object model learned from the object's other pushes alone (parameters and
// region calibration, object_model.hpp) from its start and its plan (recorded_forecast_case: the file name, the start
// pose, and when the tip starts moving), and compared with its recording over the whole push and at its end, beside
// two references that need no model: the object not moving, and the object following the planned tip rigidly
// (translating with it, not turning). The per-push best fit (the push's own parameters, fitted on its own recording)
// is reported as an oracle: no forecast can use it.
// Units: SI inside; the reports turn them into mm and degrees.
#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/forecast/object_model.hpp"

namespace pushpred {

/// One method's errors on one push. Trajectory means are over the recorded poses from the plan's start to the
/// recording's end; final is the last recorded pose. Coverage: the share of those poses inside the 90 % region.
struct ForecastErrors {
  double final_position_m = 0, final_yaw_rad = 0;
  double trajectory_position_m = 0, trajectory_yaw_rad = 0;
  bool has_regions = false;
  double coverage_position = 0, coverage_yaw = 0;  ///< shares of the recorded poses
  bool final_inside_position = false, final_inside_yaw = false;
  double median_radius_m = 0, median_yaw_halfwidth_rad = 0;  ///< over the push's recorded times
  double final_radius_m = 0, final_yaw_halfwidth_rad = 0;
  /// Where the yaw error builds up: the signed yaw error (predicted minus recorded) [rad] at the recorded pose nearest
  /// a quarter, a half and three quarters of the plan's time and at its end (the tip stops; kYawErrorStages), and at
  /// the recording's end (the final pose): what changes between the last two is the slide to rest.
  std::array<double, 4> yaw_error_at_stage_rad{{0, 0, 0, 0}};
  double final_yaw_error_signed_rad = 0;
};
/// The fractions of the plan's time at which ForecastErrors::yaw_error_at_stage_rad is taken.
inline constexpr std::array<double, 4> kYawErrorStages{{0.25, 0.5, 0.75, 1.0}};

/// The methods a study reports, in this order.
const std::vector<std::string>& forecast_study_methods();  ///< "forecast", "not_moving", "rigid_tip", "oracle_own_fit"

struct ForecastStudyPush {
  std::string name, object, surface;
  double recorded_travel_m = 0, recorded_turn_rad = 0;  ///< the recording's own final displacement and turn
  /// How far the recording turns after the plan's end (the tip stopped): its final yaw minus its yaw there [rad].
  double recorded_turn_after_tip_stop_rad = 0;
  /// The rod's friction the push's force sensor measured (RecordedForecastCase::measured_pusher_friction; NaN: not
  /// measured). No forecast uses it.
  double measured_pusher_friction = std::numeric_limits<double>::quiet_NaN();
  std::vector<ForecastErrors> errors;  ///< per method, forecast_study_methods() order
  ForecastParameters learned;          ///< the model's central parameters (without this push)
  PushFit own_fit;
  int training_pushes = 0;
  /// The fold's pressure rim weight (ObjectModel: w of the outline's limit surface, learned from the training pushes)
  /// and whether it was learned and kept (false: the uniform pressure, w = 0: the ellipsoid, `uniform`, too few
  /// pushes, or `chosen` preferring the uniform pressure in its cross-validation).
  double rim_weight = 0;
  bool rim_weight_learned = false;
  /// Whether the fold's model corrects its central forecast by the training pushes' leave-one-out errors
  /// (ObjectModel::residual_correction; with `--residual-correction chosen`, where that fold's choice kept it).
  bool residual_correction = false;
};

struct ForecastStudyOptions {
  int jobs = 1;
  int min_training_pushes = 2;
  LearnOptions learn;  ///< fewer other pushes of the same object and surface: the push is not forecast
};

/// Leave-one-push-out over `cases` (with `fits[i]` the own fit of `cases[i]`), grouped by object and surface. Pushes
/// of a group too small are listed in `skipped` with the reason.
std::vector<ForecastStudyPush> run_forecast_study(const std::vector<RecordedForecastCase>& cases,
                                                  const std::vector<PushFit>& fits, const ForecastStudyOptions& options,
                                                  std::vector<std::pair<std::string, std::string>>* skipped = nullptr);

/// The errors of `predicted` (rows at c.times_s) against the recording, with regions when given.
ForecastErrors forecast_errors(const RecordedForecastCase& c, const Eigen::MatrixX3d& predicted,
                               const Eigen::VectorXd* radius_m = nullptr,
                               const Eigen::VectorXd* yaw_halfwidth_rad = nullptr);

/// Recorded pushes read, turned into forecast cases and fitted (each push's own parameters), on `jobs` threads.
struct ForecastInputs {
  std::vector<RecordedForecastCase> cases;
  std::vector<PushFit> fits;
  /// Pushes left out on purpose, with the reason: a frozen force sensor (flagged by inspect; every study of the
  /// project leaves them out, so the forecast is scored on the same pushes), or a push that is not a
  /// constant-speed one.
  std::vector<std::pair<std::string, std::string>> excluded;
  std::vector<BatchFailure> failures;  ///< inputs that could not be read or used
};
/// `inputs`: files or folders (expand_inputs). `object`: the object to push on for every input (a user's own outline,
/// mass and inertia), or null for the dataset's (dataset_forecast_object, butter's outline from `data_folder`), with
/// the limit surface `limit_surface` (an own object keeps its own).
ForecastInputs load_forecast_inputs(const std::vector<std::string>& inputs, const std::filesystem::path& data_folder,
                                    int jobs, const ForecastObject* object = nullptr, bool show_progress = true,
                                    LimitSurfaceKind limit_surface = LimitSurfaceKind::Ellipsoid);

/// What the study takes from the predicted push besides its file name, for the reports.
std::string forecast_study_inputs_note();

}  // namespace pushpred
