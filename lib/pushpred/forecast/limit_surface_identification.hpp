#pragma once
// How a recorded push's object turns under its contact force, identified from the force sensor and the object's
// motion alone, and whether that follows the plan (`pushpred limit-surface-study`).
//
// On the ellipsoidal limit surface (prediction/quasi_static_pushing.hpp) the support's friction wrench (f, m) about the
// centre of friction and the object's twist (v of the centre of friction, omega) satisfy v = k f and
// omega = k m / c^2 for one k > 0: the ratio c says how much the object turns for a given moment of the contact force.
// With the recorded contact force on the object (the force sensor) as the pusher's wrench (quasi-static: the support's
// friction balances it), k = v . f / |f|^2 at each sample and the recorded turn fixes c:
//   c^2 = sum_j k_j m_j / sum_j omega_j
// over the samples where the rod pushes (the turn-matching estimate: the c under which the recorded force turns the
// object by the recorded angle over those samples). The rod's friction does not enter: the force's direction is the
// sensor's, which holds the rod's friction at what the sensor measured
// (RecordedForecastCase::measured_pusher_friction). Units: SI.
#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "pushpred/forecast/forecast_study.hpp"
#include "pushpred/forecast/object_model.hpp"

namespace pushpred {

/// The plan's lever: the signed distance [m] of the planned push line from the centre of friction, counter-clockwise
/// positive (the direction's cross product with the contact point's offset from the centre, in the body frame).
double plan_lever_m(const ForecastObject& object, const PushDescriptor& d);

/// The ways the study predicts a push's ln c from the other pushes of its object (kPlanModelNames order):
/// - "others_median": their median, not using the plan;
/// - "linear_trend": ridge regression (lambda 1, as trend_features' ridge) on trend_features (push angle, contact
///   point's body x and y, ln speed);
/// - "similarity": the others weighted by how alike they pushed (the averaged similarity weighting of learn);
/// - "lever": ridge regression (lambda 1) on |lever| / 15 mm and |angle| / 20 degrees (a non-ellipsoidal limit
///   surface's effective c depends on the wrench's direction, which these set).
inline const std::vector<std::string> kPlanModelNames = {"others_median", "linear_trend", "similarity", "lever"};

struct LimitSurfaceStudyPush {
  std::string name, object, surface;
  PushDescriptor descriptor;
  double lever_m = 0;
  double measured_pusher_friction = std::numeric_limits<double>::quiet_NaN();
  TorqueRatioIdentification identified;
  double own_fit_torque_ratio_m = 0;  ///< the push's own trajectory fit (mu_p fitted)
  /// Per kPlanModelNames: the ln c predicted from the other pushes (NaN: too few identified others).
  std::vector<double> predicted_log_c;
  /// Forecast errors with mu_p the others' measured median (their fitted median where none measured), mu_s the
  /// others' fitted median and c: per kPlanModelNames, then the push's own identified c ("own_identified"; the
  /// others' median where it is not identified). No model of the forecast stage uses these: they measure.
  std::vector<ForecastErrors> errors;
  double held_pusher_friction = 0, support_friction = 0;
};

/// Leave one push out per object and surface over `cases` (`fits[i]` the own fit of `cases[i]`,
/// `identified[i]` the identification of `cases[i]`).
std::vector<LimitSurfaceStudyPush> run_limit_surface_study(const std::vector<RecordedForecastCase>& cases,
                                                           const std::vector<PushFit>& fits,
                                                           const std::vector<TorqueRatioIdentification>& identified);

/// Over `pushes` whose c is identified and predicted: per kPlanModelNames, 1 less the model's mean squared
/// leave-one-out error in ln c over others_median's (its share of the variance the plan explains; 0 for
/// others_median, NaN with fewer than two such pushes). `used` (optional) gets their number.
std::vector<double> plan_model_r2(const std::vector<LimitSurfaceStudyPush>& pushes, int* used = nullptr);

/// The per-push CSV and the per-object summary (markdown) of a study.
std::string limit_surface_study_csv(const std::vector<LimitSurfaceStudyPush>& pushes);
std::string limit_surface_study_tables(const std::vector<LimitSurfaceStudyPush>& pushes);

}  // namespace pushpred
