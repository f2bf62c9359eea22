#pragma once
// A learned object: what `pushpred learn` identifies from recorded pushes of one object on one surface and keeps in
// a versioned JSON file (docs/forecast.md, "The object file"), and the forecast with its predictive distribution.
//
// Learning (units SI, frames as forecast_model.hpp):
// - per push: the parameters (mu_p, c, mu_s) that make the forecast of that push from its start best follow its
//   recorded trajectory (Ceres, numeric derivatives, from the best of a coarse grid), with their standard errors;
// - the centre of friction: one for the object, fitted jointly over its pushes with each push's own parameters
//   (fit_centre_of_friction), kept when it forecasts the learned pushes better in cross-validation; with the
//   outline's limit surface the pressure's rim weight with it, kept the same way;
// - the object's parameters: the per-push values' median (in logarithms), the push-to-push spread (the per-push
//   values' robust standard deviation) and the median's standard error;
// - the predictive regions: a forecast runs the object's parameters (the central forecast) and every learned push's
//   own (the ensemble); the 90 % region at each time is a disc of radius k_pos sqrt(s_pos^2 + floor_pos^2) about the
//   central position and k_yaw sqrt(s_yaw^2 + floor_yaw^2) about its yaw, with s the ensemble's RMS spread about the
//   central forecast. k is calibrated on the learned pushes alone, leaving each out in turn: k is the quantile, at
//   the split-conformal level 0.9 (1 + 1/n) for n pushes, of its held-out error over the spread the others predict
//   (each push weighted equally), one k per third of the planned push.
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <limits>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pushpred/forecast/forecast_model.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// The version of the object file this library writes; it reads every version up to it (version 1 files have no
/// "centre_of_friction" block: their centre of friction is the one in "object", the outline's centroid; versions 1
/// and 2 have no "parameter_trend": their parameters do not follow the plan; versions 1 to 3 have no
/// "limit_surface": theirs is the ellipsoid; versions 1 to 4 have no "pressure_shape": their pressure's rim weight
/// is 0, uniform; versions 1 to 5 have no "similarity_weighting": theirs is one chosen bandwidth; versions 1 to 6
/// have no "residual_correction" nor the pushes' "loo_final_error": their central forecast is not corrected).
inline constexpr int kObjectModelVersion = 7;

/// How a recorded push's object turns under its contact force, identified from its force sensor and motion alone
/// (identify_torque_ratio, limit_surface_identification.hpp). On the ellipsoidal limit surface the twist about the
/// centre of friction is v = k f, omega = k m / c^2 for the support's friction wrench (f, m); with the recorded contact
/// force as that wrench (quasi-static), k = v . f / |f|^2 per sample, and the recorded turn fixes
/// c^2 = sum_j k_j m_j / sum_j omega_j over the samples where the rod pushes: the c under which the recorded force
/// turns the object as it turned. The rod's friction does not enter: the force's direction is the sensor's.
struct TorqueRatioIdentification {
  /// c [m]: NaN where the push does not identify it (fewer than kMinSamples samples, a recorded turn over them under
  /// kMinTurn_rad, or a moment whose turn has the other sign than the recorded one).
  double torque_ratio_m = std::numeric_limits<double>::quiet_NaN();
  double turn_rad = 0;     ///< the recorded turn over the samples used (sum of omega dt)
  double moment_term = 0;  ///< sum of k_j m_j dt [m^2 rad]: the turn c = 1 m would give
  int samples = 0;         ///< samples used
  /// c [m] identified in the same way over the first and the second half of the samples' span of tip travel (20-55 %
  /// and 55-90 %): how reproducible the identification is within one push (NaN where a half does not identify it).
  double first_half_torque_ratio_m = std::numeric_limits<double>::quiet_NaN();
  double second_half_torque_ratio_m = std::numeric_limits<double>::quiet_NaN();
  static constexpr int kMinSamples = 10;
  static constexpr double kMinTurn_rad = 1.0 * 3.14159265358979323846 / 180;
};

/// A recorded push as the forecast sees it: the start (object and tip at rest, when the tip starts moving), the plan
/// made from the file name and the start alone, and the recorded trajectory after it.
struct RecordedForecastCase {
  std::string name;  ///< the file's stem
  std::string object, surface;
  ForecastObject forecast_object;
  TipPlan plan;
  Eigen::Vector3d start_pose = Eigen::Vector3d::Zero();
  double start_time_s = 0;       ///< the plan's start on the push's clock (SynchronisedPush::t_s)
  Eigen::VectorXd times_s;       ///< plan time of each recorded pose, from 0 to the recording's end
  Eigen::MatrixX3d truth;        ///< the recorded poses there
  std::string direction_source;  ///< how the push direction was found
  /// The rod's friction as the push's force sensor measured it (measured_pusher_friction, set by
  /// recorded_forecast_case): NaN where the recorded contact hardly slid.
  double measured_pusher_friction = std::numeric_limits<double>::quiet_NaN();
  /// How the push's object turned under its recorded contact force (identify_torque_ratio, set by
  /// recorded_forecast_case). No forecast uses it.
  TorqueRatioIdentification identified_torque_ratio;
};

/// The forecast object of a dataset shape: the shape table's mass, inertia, centroid and outline, or for `butter` the
/// outline in `data_folder`/butter_outline.csv (read at run time). InputError naming the file when it is unreadable.
ForecastObject dataset_forecast_object(const ShapeInfo& shape, const std::filesystem::path& data_folder);

/// Reads an outline polygon from a CSV file of x_m,y_m rows (a header line and # comments allowed), counter-clockwise.
/// InputError naming the file and line for bad content.
ForecastOutline read_outline_csv(const std::filesystem::path& path, const std::string& description);

/// The case of a recorded push. The plan: straight, 50 mm (`push_length_m`) at the file name's speed, from the tip's
/// rest position, along the inward normal at the file name's contact side and position rotated by its angle
/// (dataset_push_direction_body; butter: perimeter_push_direction_body), in the object's frame
/// at the start. The one thing taken from the push's own motion is when the tip starts moving: the first time it is
/// 0.5 mm from its rest position, less the time the plan takes to cover 0.5 mm. InputError when the push has no
/// file-name parameters, an acceleration push, or a tip that never moves.
RecordedForecastCase recorded_forecast_case(const SynchronisedPush& push, const ForecastObject& object,
                                            double push_length_m = 0.05);

/// The samples of a recorded push where its rod pushes the object: from 20 % to 90 % of the plan's length of tip
/// travel (away from the speed ramps), with the rod (ForecastSettings::rod_radius_m) within 1.5 mm of touching the
/// outline. measured_pusher_friction and identify_torque_ratio read the contact force there. The thresholds are set
/// from the rig, not fitted.
class RodContactSamples {
 public:
  static constexpr double kFrom = 0.2, kTo = 0.9;  ///< of the plan's length of tip travel
  static constexpr double kTouch_m = 1.5e-3;       ///< the rod's largest gap to the outline
  struct Sample {
    double progress = 0;       ///< of the plan's length of tip travel
    Eigen::Matrix2d R;         ///< the object's recorded rotation, body to world
    Outline::Closest closest;  ///< the outline's point nearest the tip, body frame
  };
  /// `c` is the push's case; it must have an outline.
  RodContactSamples(const SynchronisedPush& push, const RecordedForecastCase& c);
  /// Sample j of `push` when the rod pushes there. Reads the samples in increasing order fastest (the outline search
  /// starts at the last contact).
  std::optional<Sample> at(Eigen::Index j);

 private:
  const SynchronisedPush& push_;
  const ForecastOutline& outline_;
  Eigen::Vector2d direction_, tip0_;
  double length_m_, touch_m_;
  int hint_ = -1;
};

/// The rod's friction as a recorded push's force sensor measured it: the median over the recorded samples where the
/// contact slides of |tangential| / normal contact force, in the frame of the outline's normal at the contact point
/// nearest the tip. A sample counts where the rod pushes (RodContactSamples) with at least 0.5 N and slides: the tip's velocity relative to the object's material point at the contact, along the outline,
/// exceeds 15 % of the plan's speed. NaN with fewer than 10 such samples. `c` is the push's case (its plan and
/// object); recorded_forecast_case sets its measured_pusher_friction so. The thresholds are set from the rig (0.5 N
/// is a few times the sensor's noise), not fitted.
double measured_pusher_friction(const SynchronisedPush& push, const RecordedForecastCase& c);

/// Identifies c (TorqueRatioIdentification) from `push`'s recorded force and motion about `c`'s object's centre of
/// friction, over the samples where the rod pushes (RodContactSamples) with at least 0.5 N (measured_pusher_friction's
/// threshold, set from the rig). Velocities are central
/// differences over +-10 ms.
TorqueRatioIdentification identify_torque_ratio(const SynchronisedPush& push, const RecordedForecastCase& c);

/// Where and how a plan pushes, in the object's frame at its start: what the push-to-push variation of the parameters
/// is modelled on (learned pushes that push alike weigh more in a forecast, see ObjectModel::similarity_bandwidth).
struct PushDescriptor {
  Eigen::Vector2d contact_body_m = Eigen::Vector2d::Zero();  ///< the outline point nearest the tip's start
  double angle_rad = 0;  ///< the push direction's angle from the inward normal there, counter-clockwise
  double log_speed = 0;  ///< ln(mean speed of the plan [m/s])
};
PushDescriptor describe_push(const ForecastObject& object, const TipPlan& plan, const Eigen::Vector3d& pose0);
/// The squared distance of two descriptors in units of their fixed scales: 20 degrees of angle (the dataset's step in
/// push angle), 15 mm of contact point, a factor e of speed. The scales are set by physics, not fitted.
double descriptor_distance2(const PushDescriptor& a, const PushDescriptor& b);

/// The features a parameter trend is linear in: the push angle over 20 degrees, the contact point's body x and y over
/// 15 mm, ln(speed) (the descriptor_distance2 scales).
inline constexpr int kTrendFeatures = 4;
Eigen::Matrix<double, kTrendFeatures, 1> trend_features(const PushDescriptor& d);

/// How the learned pushes' parameters follow the plan: the logarithms of (mu_p, c, mu_s) linear in trend_features,
/// fitted by ridge regression over the learned pushes. A forecast moves each learned push's parameters along the
/// trend from where that push pushed to where the plan pushes (by at most `max_shift_log` e-folds, so that a plan
/// beyond the learned ones does not extrapolate far), and the ensemble then spreads about the trend.
struct ParameterTrend {
  /// The ridge weight lambda of (1/n) sum of squared residuals + lambda |slope|^2 (features as trend_features);
  /// 0: no trend (all slopes zero).
  double ridge = 0;
  Eigen::Matrix<double, 3, kTrendFeatures> slope = Eigen::Matrix<double, 3, kTrendFeatures>::Zero();
  double max_shift_log = 1.0;
  bool active() const { return ridge > 0; }
};

/// One push's own parameters: the best fit of the forecast to its recorded trajectory.
struct PushFit {
  std::string name;
  PushDescriptor descriptor;
  ForecastParameters parameters;
  Eigen::Vector3d standard_error = Eigen::Vector3d::Zero();  ///< of mu_p, c [m], mu_s
  double rms_position_m = 0, rms_yaw_rad = 0;                ///< of the fitted forecast against the recording
  double final_position_m = 0, final_yaw_rad = 0;
  int evaluations = 0;
  /// The push's leave-one-out final error inside learn (its forecast by the other learned pushes' ensemble minus its
  /// recorded final pose) in the frame of its plan: along the push direction [m], across it (counter-clockwise of
  /// it) [m], and yaw [rad]. What the residual correction (ObjectModel::residual_correction) averages; 0 until learn
  /// sets it (with three or more pushes).
  Eigen::Vector3d loo_final_error = Eigen::Vector3d::Zero();
};

struct FitOptions {
  double position_scale_m = 1e-3;     ///< a residual of 1 mm ...
  double yaw_scale_rad = M_PI / 180;  ///< ... weighs as 1 degree
  int residual_times = 60;            ///< recorded poses used, evenly spread over the push
  /// A weak prior on the logarithms of (mu_p, c / c_uniform, mu_s) about (ln 0.25, 0, ln 0.4), this many e-folds wide
  /// per standard deviation (0: none), so that a parameter a push barely informs stays near physics rather than at
  /// a bound. The width 1 was chosen on simulated pushes (seeds 271000-271015, docs/forecast.md), not on real ones.
  double prior_width_log = 1.0;
  /// > 0: the rod's friction mu_p is held at this value (LearnOptions::pusher_friction "measured") and only c and
  /// mu_s are fitted; 0: mu_p is fitted too.
  double held_pusher_friction = 0;
  ForecastSettings settings;
};

/// Fits the case's own parameters (bounded: mu_p 0.02-2, c 0.15-2.5 times the uniform-pressure value, mu_s 0.05-1.5;
/// with the weak prior of FitOptions::prior_width_log).
PushFit fit_push_parameters(const RecordedForecastCase& c, const FitOptions& options = {});

/// The object's centre of friction (the centre of its support pressure) fitted jointly over pushes of one object on
/// one surface, with each push's own parameters under it: a property of the object on the surface, so one for all
/// its pushes. A single push barely tells an offset centre from the rod's friction (both turn it one way); pushes
/// from several sides and angles do. Ceres over all pushes' trajectory residuals at once (each push's block as in
/// fit_push_parameters, from its own fit), with a Gaussian prior about the starting centre and a bound around it.
struct CentreOfFrictionFit {
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();  ///< body frame
  Eigen::Vector2d standard_error_m = Eigen::Vector2d::Zero();
  /// The pressure's rim weight (ForecastObject::pressure_rim_weight) and its standard error (0 when not fitted).
  double rim_weight = 0, rim_weight_standard_error = 0;
  std::vector<PushFit> fits;  ///< each push's own parameters under the fitted centre (same order as the cases)
};
struct CentreOfFrictionOptions {
  /// The prior's standard deviation about the starting centre (the outline's centroid) per axis, and the bound on the
  /// offset: physical settings (a flat object's pressure centre lies a few millimetres from its centroid), not fitted.
  double prior_sd_m = 3e-3;
  double max_offset_m = 12e-3;
  int max_iterations = 30;
  /// What is fitted: the centre (else held at the object's), and with the outline's limit surface the pressure's rim
  /// weight w (else held at the object's). w's prior is Gaussian about 0 (uniform pressure) of standard deviation
  /// `rim_weight_prior_sd`, weak against its physical range (about -0.5 to 1: rim_weight_range, the pressure
  /// non-negative everywhere), and w is bounded to that range.
  bool fit_centre = true;
  bool fit_rim_weight = false;
  double rim_weight_prior_sd = 0.5;
  FitOptions fit;
};
/// Fits the centre of friction of `object` (its outline, mass and inertia; its centre is the start and the prior's)
/// shared by `cases`, from their per-push fits `fits` (same order), and with `options.fit_rim_weight` and the
/// outline's limit surface the pressure's rim weight with it (from the object's). InputError for no case;
/// std::logic_error for unequal sizes.
CentreOfFrictionFit fit_centre_of_friction(const ForecastObject& object, const std::vector<RecordedForecastCase>& cases,
                                           const std::vector<PushFit>& fits,
                                           const CentreOfFrictionOptions& options = {});

/// The jackknife's standard error of the rim weight that fit_centre_of_friction(object, cases, fits, options) found
/// (`full`): each push left out in turn and the joint fit redone on the others, se^2 = (n - 1) / n sum_i (w_(i) -
/// mean w_(.))^2 over the n left-out fits. The pushes are the independent draws; Ceres' covariance
/// (CentreOfFrictionFit::rim_weight_standard_error) takes a push's correlated residuals as independent and misjudges
/// the spread of w over pushes (docs/forecast.md). Each refit starts from `full`'s rim weight and per-push parameters
/// (the centre, when fitted, from the object's, where its prior is), so that it converges in a few iterations; the
/// refits run on `jobs` threads and the result does not depend on it. 0 with fewer than 3 pushes or when
/// `options.fit_rim_weight` is off or the limit surface is the ellipsoid (no rim weight is fitted then).
double rim_weight_jackknife_standard_error(const ForecastObject& object, const std::vector<RecordedForecastCase>& cases,
                                           const std::vector<PushFit>& fits, const CentreOfFrictionOptions& options,
                                           const CentreOfFrictionFit& full, int jobs = 1);

/// What a forecast's central trajectory is, at each output time, from the learned pushes' own forecasts (the
/// ensemble, weighted by similarity):
/// - EnsembleMean ("ensemble_mean"): their weighted mean, the best point under squared error;
/// - EnsembleMedian ("ensemble_median"): their positions' weighted geometric median (weighted_geometric_median) and
///   their yaws' weighted median (weighted_median), the best point under the absolute error the study scores; where
///   the ensemble splits across the contact's stick/slide switch it lies on the heavier mode, not between them;
/// - MedianParameters ("median"): the forecast of their parameters' (weighted) median.
/// The regions are centred on the central forecast, with the ensemble's spread about it. The mean of the ensemble
/// errs less than the median parameters on the real pushes (docs/forecast.md): the trajectory bends nonlinearly with
/// the parameters.
enum class CentralForecast { EnsembleMean, MedianParameters, EnsembleMedian };
/// "ensemble_mean", "median", "ensemble_median"; InputError otherwise.
CentralForecast central_forecast_named(const std::string& name);
const char* central_forecast_name(CentralForecast central);
/// The names central_forecast_named takes, in that order.
inline const std::vector<std::string> kCentralForecastNames = {"ensemble_mean", "median", "ensemble_median"};
/// The central forecast LearnOptions' defaults make (docs/forecast.md: chosen on simulated pushes).
inline constexpr const char* kCentralForecastDefaultChoice = "ensemble_mean";

/// The residual correction of the central forecast (ObjectModel::residual_correction, `--residual-correction`):
/// - "none": the central forecast as it is;
/// - "loo": shifted by the similarity-weighted mean of the learned pushes' leave-one-out final errors
///   (PushFit::loo_final_error, in the frame of each push's plan, carried into the plan's frame), shrunk towards
///   zero by n_eff / (n_eff + kResidualShrinkage) with n_eff = (sum w)^2 / sum w^2 of the same similarity weights w
///   as the ensemble, and growing with the tip's progress along the plan (0 at its start, the whole shift from its
///   end on, the slide included);
/// - "chosen": "loo" when its leave-one-out forecasts of the learned pushes err less than without it (final and
///   trajectory mean, mm and degrees alike; each left-out push corrected by the others' errors), else "none".
enum class ResidualCorrectionChoice { None, LeaveOneOut, Chosen };
ResidualCorrectionChoice residual_correction_named(const std::string& name);
const char* residual_correction_name(ResidualCorrectionChoice choice);
inline const std::vector<std::string> kResidualCorrectionNames = {"none", "loo", "chosen"};
/// The choice LearnOptions' defaults make (docs/forecast.md: decided on simulated pushes).
inline constexpr const char* kResidualCorrectionDefaultChoice = "loo";
/// k of the residual correction's shrinkage n_eff / (n_eff + k): set before any run (a push's own leave-one-out error
/// taken to scatter about the systematic part by about as much as that part varies, twice over), not fitted.
inline constexpr double kResidualShrinkage = 2.0;

/// The weighted median of (value, weight) pairs (weights positive; sorted in place, nothing allocated): the value
/// where the cumulative weight first reaches half the total, or the midpoint of it and the next value when it reaches
/// half exactly. NaN when empty.
double weighted_median(std::vector<std::pair<double, double>>& value_weight);

/// The weighted geometric median of `points` (columns), the point minimising sum_i w_i |x_i - y|: Weiszfeld's
/// iteration from `*start` (a nearby median, as the previous output time's; nullptr: the weighted mean), with Vardi
/// and Zhang's step where the iterate meets a point (so that a point that is the median is found and one that is not
/// is left), until a step is below `tolerance_m` or after `max_iterations`. Weights non-negative (at least one
/// positive); nothing allocated.
Eigen::Vector2d weighted_geometric_median(const Eigen::Ref<const Eigen::Matrix2Xd>& points,
                                          const Eigen::Ref<const Eigen::VectorXd>& weights, double tolerance_m = 1e-9,
                                          int max_iterations = 200, const Eigen::Vector2d* start = nullptr);

/// How the 90 % regions are sized (see the header's comment).
struct RegionCalibration {
  /// k_pos and k_yaw in each third of the planned push (by plan time; the last third holds the slide and the rest
  /// after it, so the final pose): errors grow over a push faster than the ensemble's spread does.
  std::array<double, 3> position_scale{{1.645, 1.645, 1.645}};
  std::array<double, 3> yaw_scale{{1.645, 1.645, 1.645}};
  static int stage(double t_s, double plan_end_s) {
    return t_s < plan_end_s / 3 ? 0 : (t_s < 2 * plan_end_s / 3 ? 1 : 2);
  }
  double position_floor_m = 5e-4;  ///< the pose measurement's and model's floor
  double yaw_floor_rad = 0.5 * M_PI / 180;
  int pushes = 0;  ///< held-out pushes it was calibrated on (0: not calibrated, k a normal quantile)
  std::string method =
      "held-out error over ensemble spread, split-conformal 90 % quantile, leave-one-push-out over the learned pushes";
};

/// The learned object: what the object file holds.
struct ObjectModel {
  int version = kObjectModelVersion;
  std::string surface;
  ForecastObject object;
  std::string outline_source;     ///< "shape table: rect1", "data folder: butter_outline.csv", "polygon file: ..."
  ForecastParameters parameters;  ///< central
  Eigen::Vector3d standard_error = Eigen::Vector3d::Zero();  ///< of the central values
  Eigen::Vector3d push_to_push_sd = Eigen::Vector3d::Zero();
  std::vector<PushFit> pushes;  ///< the ensemble
  /// h: a forecast weighs learned push i by exp(-d_i^2 / (2 h^2)), d_i its descriptor's distance to the plan's; its
  /// central parameters are the weighted median (in logarithms) and its regions the weighted spread. 0: all alike
  /// (the central parameters are `parameters`). Chosen by learn among 0, 2, 1 and 0.5 by the learned pushes' own
  /// leave-one-out error when the weighting is not averaged (similarity_averaged, learn's default).
  double similarity_bandwidth = 0;
  /// How the learned pushes are weighted for a plan: false, by the one bandwidth `similarity_bandwidth`; true
  /// (averaged), by the mean over the bandwidths kAveragedBandwidths of each push's normalised weight under that
  /// bandwidth (w_i(h) / sum_j w_j(h)): a weighting with a narrow core and wide tails, for which no bandwidth is
  /// chosen (similarity_bandwidth is then 0 and unused). The choice among bandwidths on a dozen learned pushes is
  /// noisy; their average is not.
  bool similarity_averaged = false;
  /// The parameters' trend over the plan (inactive: none). Chosen by learn with the bandwidth, among
  /// LearnOptions::trend_ridges, by the learned pushes' own leave-one-out error; kept only when it beats the best
  /// bandwidth without a trend by more than one standard error of their paired per-push differences.
  ParameterTrend trend;
  CentralForecast central = CentralForecast::EnsembleMean;
  /// Whether the central forecast is shifted by the learned pushes' leave-one-out final errors
  /// (ResidualCorrectionChoice "loo"), with shrinkage k `residual_shrinkage`; the regions are then calibrated on the
  /// corrected leave-one-out forecasts.
  bool residual_correction = false;
  double residual_shrinkage = kResidualShrinkage;
  std::string residual_correction_method = "none";
  /// Where the ensemble's rod friction comes from (PusherFrictionSource): "fitted per push", or the measured value
  /// every learned push holds.
  std::string pusher_friction_method = "fitted per push";
  RegionCalibration regions;
  ForecastSettings settings;
  /// object.centre_of_friction_m's standard error, and how many pushes it was learned from (0: not learned, the
  /// outline's centroid).
  Eigen::Vector2d centre_of_friction_standard_error_m = Eigen::Vector2d::Zero();
  int centre_of_friction_pushes = 0;
  std::string centre_of_friction_method = "the object's own (not learned)";
  /// object.pressure_rim_weight's standard error (the jackknife's over the learned pushes,
  /// rim_weight_jackknife_standard_error; 0 when the rim weight is not learned), and how many pushes it was learned
  /// from (0: not learned, 0 uniform).
  double pressure_rim_weight_standard_error = 0;
  int pressure_rim_weight_pushes = 0;
  std::string pressure_shape_method = "uniform (not learned)";
};

/// Where the learned pushes' rod friction mu_p comes from (LearnOptions::pusher_friction, `--pusher-friction`):
/// - "fitted": each push's own fit (fit_push_parameters), with c and mu_s;
/// - "measured": held at the median over the learned pushes of the friction their force sensors measured where the
///   contact slid (RecordedForecastCase::measured_pusher_friction), each push's c and mu_s refitted under it (and the
///   centre of friction's joint fit holds it too); "fitted" where no learned push measured it.
enum class PusherFrictionSource { Fitted, Measured };
PusherFrictionSource pusher_friction_named(const std::string& name);
const char* pusher_friction_name(PusherFrictionSource source);
inline const std::vector<std::string> kPusherFrictionNames = {"fitted", "measured"};
/// The choice LearnOptions' defaults make (docs/forecast.md: decided on simulated pushes).
inline constexpr const char* kPusherFrictionDefaultChoice = "fitted";

struct LearnOptions {
  PusherFrictionSource pusher_friction = pusher_friction_named(kPusherFrictionDefaultChoice);
  CentralForecast central = central_forecast_named(kCentralForecastDefaultChoice);
  ResidualCorrectionChoice residual_correction = residual_correction_named(kResidualCorrectionDefaultChoice);
  std::vector<double> bandwidths = {0.0, 2.0, 1.0, 0.5};  ///< similarity_bandwidth's candidates
  /// ObjectModel::similarity_averaged (then `bandwidths` is unused). The default: on simulated pushes it forecast
  /// better than one chosen bandwidth, and on the real ones it was not worse (docs/forecast.md).
  bool similarity_averaged = true;
  /// The trend's candidate ridge weights (0: no trend), each tried with every bandwidth; the trend is fitted anew on
  /// the others for every left-out push. The default offers none (set_trend_choice "chosen" offers
  /// kTrendCandidateRidges): on simulated pushes the in-fold choice did not forecast better (docs/forecast.md).
  std::vector<double> trend_ridges = {0.0};
  ForecastSettings settings;
  /// Learn the centre of friction (fit_centre_of_friction) from this many pushes on (0: never; the object's own
  /// centre is kept, and so are the per-push fits).
  int centre_of_friction_min_pushes = 4;
  /// Keep the learned centre only when it forecasts the learned pushes better than the object's own centre in this
  /// many-fold cross-validation over them (fewer than 2: always keep it).
  int centre_of_friction_folds = 3;
  /// With the outline's limit surface: learn the pressure's rim weight jointly with the centre of friction (as the
  /// centre is kept or not) from this many pushes on (0: never, uniform pressure), kept only when it forecasts the
  /// learned pushes better than without it in this many-fold cross-validation over them (fewer than 2: always).
  int pressure_shape_min_pushes = 4;
  int pressure_shape_folds = 3;
  /// The learned rim weight's standard error by the jackknife over the learned pushes (one more joint fit per push;
  /// false: not computed, 0, as the study's folds do, which never report it), its refits on `jobs` threads.
  bool rim_weight_jackknife = true;
  int jobs = 1;
  CentreOfFrictionOptions centre_of_friction;
};

/// Sets how `options` learns the centre of friction: "chosen" (the defaults: learned when cross-validation over the
/// learned pushes prefers it), "learned" (always, from centre_of_friction_min_pushes on) or "centroid" (never).
/// InputError otherwise.
void set_centre_of_friction_choice(LearnOptions& options, const std::string& choice);
/// The choice LearnOptions' defaults make.
inline constexpr const char* kCentreOfFrictionDefaultChoice = "chosen";

/// Sets how `options` learns the pressure's shape under the outline's limit surface (the ellipsoid has none):
/// "chosen" (the defaults: the rim weight learned when cross-validation over the learned pushes prefers it),
/// "learned" (always, from pressure_shape_min_pushes on) or "uniform" (never, rim weight 0). InputError otherwise.
void set_pressure_shape_choice(LearnOptions& options, const std::string& choice);
inline constexpr const char* kPressureShapeDefaultChoice = "chosen";

/// The ridge weights a chosen trend is picked among (0: none): a slope shrunk to a half or to 10/11 of its
/// least-squares value for a feature spread over one unit.
inline const std::vector<double> kTrendCandidateRidges = {0.0, 1.0, 0.1};
/// Sets whether `options` learns a parameter trend: "none" (the defaults: never) or "chosen" (the ridge weight among
/// kTrendCandidateRidges, with the bandwidth, by the learned pushes' own leave-one-out error). InputError otherwise.
void set_trend_choice(LearnOptions& options, const std::string& choice);
/// The choice LearnOptions' defaults make.
inline constexpr const char* kTrendDefaultChoice = "none";

/// The bandwidths an averaged similarity weighting averages over (ObjectModel::similarity_averaged): 0 (all alike),
/// 2, 1 and 0.5, the candidates a chosen bandwidth is chosen among.
inline const std::vector<double> kAveragedBandwidths = {0.0, 2.0, 1.0, 0.5};
/// Sets how `options` weighs the learned pushes for a plan: "chosen" (one bandwidth, chosen among
/// LearnOptions::bandwidths by the learned pushes' own leave-one-out error) or "averaged" (ObjectModel::
/// similarity_averaged). InputError otherwise.
void set_similarity_choice(LearnOptions& options, const std::string& choice);
/// The choice LearnOptions' defaults make.
inline constexpr const char* kSimilarityDefaultChoice = "averaged";

/// Learns the object from the fits of its pushes (at least one; with `centre_of_friction_min_pushes` or more the
/// centre of friction is fitted jointly and the pushes' own parameters refitted under it, when it forecasts the
/// learned pushes better in cross-validation (`centre_of_friction_folds`); with three or more the
/// regions are calibrated, leaving each push out, which forecasts `cases`, the same pushes in the same order; with
/// four or more the similarity bandwidth is chosen the same way). `bandwidths`: the candidates (empty: 0, 2, 1, 0.5).
ObjectModel learn_object_model(const ForecastObject& object, const std::string& surface,
                               const std::string& outline_source, const std::vector<RecordedForecastCase>& cases,
                               const std::vector<PushFit>& fits, const LearnOptions& options = {});

/// The trend of `fits`' parameters over their descriptors with ridge weight `ridge` (0: none). At least 3 fits for a
/// trend; fewer give none.
ParameterTrend fit_parameter_trend(const std::vector<PushFit>& fits, double ridge);

/// The parameters of a plan described by `descriptor`: the learned pushes' median (each moved along the trend),
/// weighted by similarity (see similarity_bandwidth); the central trajectory under CentralForecast::MedianParameters.
ForecastParameters central_parameters(const ObjectModel& model, const PushDescriptor& descriptor);

/// The object file's JSON, and back. from_json throws InputError prefixed by `source` for a missing or bad field,
/// another format or a newer version; an outline {"kind": "shape_table", "shape": NAME} is resolved from the shape
/// table and, for butter, `data_folder`.
nlohmann::json object_model_to_json(const ObjectModel& model);
ObjectModel object_model_from_json(const nlohmann::json& json, const std::string& source,
                                   const std::filesystem::path& data_folder);
ObjectModel read_object_model(const std::filesystem::path& path, const std::filesystem::path& data_folder);

/// The forecast of one plan with its 90 % regions.
struct ForecastDistribution {
  Eigen::VectorXd times_s;
  Eigen::MatrixX3d mean;                              ///< the central forecast
  Eigen::VectorXd position_radius_m;                  ///< 90 % disc about mean(x, y)
  Eigen::VectorXd yaw_halfwidth_rad;                  ///< 90 % interval about mean(yaw)
  Eigen::VectorXd position_spread_m, yaw_spread_rad;  ///< the ensemble's RMS spread about the mean
  std::vector<Eigen::MatrixX3d> members;              ///< the ensemble's trajectories (when asked for)
  ForecastRun run;
};

/// Reusable storage for many forecasts of one model (a planner's loop): after the first call of a size nothing is
/// allocated.
struct ForecastWorkspace {
  Eigen::MatrixX3d member;
  /// The median central forecast's storage: the ensemble's positions (rows 2m, 2m + 1 of member m) and yaws (row m)
  /// at each output time (columns), the members' weights, and the yaw median's sort buffer.
  Eigen::MatrixXd ensemble_xy, ensemble_yaw;
  Eigen::VectorXd weights;
  std::vector<std::pair<double, double>> value_weight;
};

/// Forecasts `plan` from `pose0` (object at rest) at `times_s` (plan time) with the model's regions.
ForecastDistribution forecast_distribution(const ObjectModel& model, const TipPlan& plan, const Eigen::Vector3d& pose0,
                                           const Eigen::VectorXd& times_s, bool keep_members = false);
/// forecast_distribution into `out` (sized by the caller: times_s.size() rows), using `work`; members not kept.
void forecast_distribution_into(const ObjectModel& model, const TipPlan& plan, const Eigen::Vector3d& pose0,
                                const Eigen::VectorXd& times_s, ForecastDistribution& out, ForecastWorkspace& work);

/// Many candidate plans from one start: the final pose (rows), its 90 % radius and yaw half-width, and the rest time
/// of each, for a planner choosing among them.
struct BatchForecast {
  Eigen::MatrixX3d final_pose;
  Eigen::VectorXd final_position_radius_m, final_yaw_halfwidth_rad, rest_time_s;
};
BatchForecast forecast_batch(const ObjectModel& model, const std::vector<TipPlan>& plans, const Eigen::Vector3d& pose0);

/// Output times every `step_s` from 0 to the central forecast's rest time plus `after_s`.
Eigen::VectorXd forecast_output_times(const ObjectModel& model, const TipPlan& plan, const Eigen::Vector3d& pose0,
                                      double step_s = 0.01, double after_s = 0.1);

}  // namespace pushpred
