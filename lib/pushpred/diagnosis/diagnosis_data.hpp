#pragma once
// The data a diagnosis fits: one push (as corrected so far), the paper's disturbance observer run over the
// samples used for fitting, and the observer's view of the applied input (Q u and its rate), so that every
// regressor lives on the observer's time base. Channels, frames and signs: preprocessing/synchronised_push.hpp.
#include <Eigen/Core>
#include <optional>

#include "pushpred/diagnosis/candidate_effect.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/observers/q_filter_observer.hpp"

namespace pushpred {

struct DiagnosisPush {
  SynchronisedPush push;                 ///< as corrected by the data corrections applied so far
  DisturbanceEstimate estimate;          ///< the observer over the fit span
  Eigen::Index first = 0;                ///< grid index of the estimate's first row
  Eigen::MatrixX3d filtered_input;       ///< Q u at the estimate's rows (channel units), interval means like d_hat
  Eigen::MatrixX3d filtered_input_rate;  ///< (Q u)' [N/s, N/s, N m/s], interval means
  /// Velocity from the pose smoothed without lag (zero_phase_smooth at kSmoothingBandwidth_rad_s) [m/s, rad/s]:
  /// the diagnosis fits offline, so it can use a velocity whose noise is far below the observer's.
  Eigen::MatrixX3d smooth_velocity;
  Eigen::MatrixX3d smooth_pose;
  Eigen::MatrixX3d smooth_acceleration;  ///< [m/s^2, rad/s^2]
  /// Per row: the object is stuck (sliding speed of smooth_velocity below kStuckSpeed_m_s). Static friction then
  /// balances whatever acts, d = -u, so no effect is visible there.
  std::vector<char> stuck;
  /// Per row: the object slides, but its smoothed speed is not resolved: the speed would change by all of itself
  /// within the smoother's time scale kSpeedResolution_s (sliding speed < kSpeedResolution_s x sliding
  /// acceleration). Around a fast start or stop the zero-phase smoother spreads the speed jump over tens of
  /// milliseconds, so an object truly at rest (or already fast) shows a low smoothed speed; a law of the speed
  /// (Stribeck friction, above all) would read that blur as a low-speed effect. These rows explain nothing in the
  /// friction regression, and the floors do not count them as time spent at low speed.
  std::vector<char> unresolved;
  /// Per row: unresolved within the smoother's time scale (the largest sliding acceleration within
  /// +-kSpeedResolution_s, not the row's own; a superset of `unresolved`). In the blurred tail of a start or stop the
  /// smoothed acceleration passes through zero and the speed, a few mm/s, is still blur. Rows like these still carry
  /// the friction acting then, so the regression keeps them; but they are not time spent sliding slowly, and the
  /// floors (effect_floor.hpp) do not count them so.
  std::vector<char> blurred;
  double q_zeta = 0, q_wn_rad_s = 0;  ///< the observer's Q filter
  /// The force every push of the set reads at rest (a sensor bias) [N, world frame], shared_rest_force_N over the
  /// set's pushes; zero for a push prepared alone. Taken off a rest force before judging whether it points into the
  /// contact (samples_without_contact).
  Eigen::Vector2d shared_rest_force_N = Eigen::Vector2d::Zero();
  /// The rig's known push-to-push spread of the sensor zero [N per axis] (DiagnosisOptions::sensor_zero_spread_N), for
  /// the force-offset test; 0 for a push prepared alone.
  double sensor_zero_spread_N = 0;
  /// What the selected refinements of the friction law explain (n x 3, as the observer sees it; zero until the
  /// diagnosis sets it), for direct fits that work against the friction law (time_offset).
  Eigen::MatrixX3d friction_explained;

  Eigen::Index rows() const { return estimate.t_s.size(); }
  /// The force-law state at estimate row `row`: smoothed pose and velocity, the measured input u (not filtered:
  /// regressors are Q-filtered after evaluation, like d_hat), the push's first pose.
  EffectState state(Eigen::Index row) const;
  /// What a disturbance `raw` (n x 3, one row per estimate row) looks like in d_hat: zero where the object is
  /// stuck, then through the observer's Q filter, reported as interval means like d_hat. Every regressor goes
  /// through this.
  Eigen::MatrixX3d as_observed(const Eigen::MatrixX3d& raw) const;
};

/// Bandwidth of the zero-phase smoothing of the pose for the force laws' state [rad/s].
inline constexpr double kSmoothingBandwidth_rad_s = 100.0;
/// Sliding speed (builtin_effects.hpp) below which a sample counts as stuck [m/s].
inline constexpr double kStuckSpeed_m_s = 1.5e-3;
/// Sliding speed above which the pusher's force on a sliding object is its friction's stop force (the quasi-static
/// law's level: the object slides clearly, the friction is fully developed) [m/s].
inline constexpr double kClearlySlidingSpeed_m_s = 5e-3;
/// The smoother's time scale [s]: 2 / kSmoothingBandwidth_rad_s, about the width over which the forward-backward
/// filter spreads a jump in speed.
inline constexpr double kSpeedResolution_s = 2.0 / kSmoothingBandwidth_rad_s;

/// Runs the observer over [t0_s, t1_s] of `push` and prepares the regression inputs. Throws InputError for a
/// span with fewer than two samples.
DiagnosisPush prepare_diagnosis_push(const SynchronisedPush& push, double t0_s, double t1_s,
                                     const QFilterObserverOptions& observer = {});
/// The same from an estimate already made by the observer of `observer` (its Q filter is read from there).
DiagnosisPush diagnosis_push_from_estimate(const SynchronisedPush& push, DisturbanceEstimate estimate,
                                           const QFilterObserverOptions& observer = {});

/// How q_filter reports its output at the sample times.
enum class FilterOutput {
  Point,         ///< the value at each sample
  IntervalMean,  ///< the mean over the interval that ends at each sample (the first sample: the first interval),
                 ///< as the observer reports d_hat and its total (q_filter_observer.hpp)
};

/// `values` (rows at times `t_s`, held first-order between them) through Q = wn^2 / (s^2 + 2 zeta wn s + wn^2),
/// starting in the steady state of the first row; exact discretisation. `rate`, when given, receives the
/// derivative of the output (reported the same way).
Eigen::MatrixXd q_filter(const Eigen::VectorXd& t_s, const Eigen::MatrixXd& values, double zeta, double wn_rad_s,
                         Eigen::MatrixXd* rate = nullptr, FilterOutput output = FilterOutput::Point);

/// `values` through the second-order low-pass of bandwidth wn (zeta 1/sqrt(2)) forward and then backward in time
/// (no lag); `rate`, when given, receives the derivative of the result.
Eigen::MatrixXd zero_phase_smooth(const Eigen::VectorXd& t_s, const Eigen::MatrixXd& values, double wn_rad_s,
                                  Eigen::MatrixXd* rate = nullptr);

/// The push as `correction` says it was: force (and tip torque) stream read `force_delay_s` later, the sensor
/// bias removed, mass and inertia scaled. Time grid and pose are unchanged.
SynchronisedPush apply_data_correction(const SynchronisedPush& push, const ModelCorrection& correction);

/// Grid samples where the tip is certainly not touching: before the tip has moved `travel_m` from where it
/// rests at the start of the recording (a push starts with the tip at rest, a gap away from the object).
std::vector<Eigen::Index> samples_before_tip_moves(const SynchronisedPush& push, double travel_m = 3e-4);

/// The mean recorded force f_C over the grid `samples` [N, world frame]; `samples` must not be empty.
Eigen::Vector2d mean_force_N(const SynchronisedPush& push, const std::vector<Eigen::Index>& samples);

/// The outline's point closest to the rod's centre at grid sample k (the measured tip's centre in the object's body
/// frame, Outline::closest): its signed distance less the rod's radius is the gap between rod and object.
Outline::Closest rod_closest(const SynchronisedPush& push, const Outline& outline, Eigen::Index k);

/// Below this measured gap between the resting rod's surface and the object's outline [m], the rod may touch: the
/// contact compresses by f / k (a 3.7 N preload on the rig's 1e4 N/m: 0.37 mm, read as a negative gap), the trackers
/// are good to a few micrometres, so a rod that presses reads a gap at or below zero and one 0.2 mm clear cannot press.
inline constexpr double kContactMargin_m = 2e-4;

/// The gap between the rod's surface and the object's outline [m] at grid sample k, from the measured tip and
/// object poses (negative: the rod is pressed in); NaN for a shape without an outline.
double measured_rod_gap_m(const SynchronisedPush& push, Eigen::Index k);

/// A rest force along the outline's inward normal at the rod, within this angle, is a contact's push [rad]: a rod's
/// friction cone (its fitted mu_p of 0.15-0.45 spans 9-24 degrees) with room for the normal's error. On the real ABS
/// pushes every rest force above 0.5 N whose measured gap reads 0.27-1.5 mm lies within 11 degrees of that normal
/// (19 pushes), where sensor zeros would point anywhere: the trackers and outlines place the rod to a millimetre or
/// two, not to the 0.2 mm of kContactMargin_m.
inline constexpr double kRestContactCone_rad = 0.5236;  // 30 degrees
/// A rest force counts as a direction only above this many of the sensor's noise (per axis, from the rest samples'
/// first differences).
inline constexpr double kRestForceResolution = 5.0;

/// Whether the mean recorded force f_C before the tip moves is what a contact pushes with: resolved
/// (kRestForceResolution) and within kRestContactCone_rad of the outline's inward normal at the rod, in the world
/// frame. False for a shape without an outline or a push without rest samples.
/// With `shared_rest_force_N`, a force every push reads at rest: only if the mean points into the contact both as
/// recorded and with that force taken off.
bool rest_force_points_into_contact(const SynchronisedPush& push,
                                    const Eigen::Vector2d& shared_rest_force_N = Eigen::Vector2d::Zero());

/// The force a set of pushes (one object, one sensor) all read at rest [N, world frame]: the median rest force of
/// the pushes whose rest is clear by their own rule (samples_without_contact). A per-push rule alone reads a clear
/// push whose sensor bias happens to point into its contact as pressed (a 30 degree cone holds a random direction
/// one time in six); the other clear pushes tell the bias. Zero without a clear push.
Eigen::Vector2d shared_rest_force_N(const std::vector<SynchronisedPush>& pushes);

/// Grid samples where the sensor's true force is zero: those before the tip moves (samples_before_tip_moves) on a
/// push whose rod rests clear of the object: its median measured gap over them above kContactMargin_m, and their
/// mean force not a contact's (resolved and within kRestContactCone_rad of the inward normal at the rod). A rod that
/// presses before the tip moves (a preload) makes its rest anything but force-free: such a push gives none. With
/// `shared_rest_force_N` (shared_rest_force_N()) a rest force counts as a contact's only if it points into the
/// contact both as recorded and with the shared force taken off. A shape without an outline cannot be measured so: its
/// samples before the tip moves are taken, as a gap is then assumed.
std::vector<Eigen::Index> samples_without_contact(const SynchronisedPush& push,
                                                  const Eigen::Vector2d& shared_rest_force_N = Eigen::Vector2d::Zero());
/// Such samples a push needs for its sensor zero to count as measured (the force-offset test, the adequacy test).
inline constexpr std::size_t kRestSamplesForZero = 5;

/// A push's sensor zero as its rest measures it.
struct MeasuredZero {
  Eigen::Vector2d zero_N;  ///< z [N, world frame]: the recorded force at rest is -z
  double variance_N2 = 0;  ///< the rest samples' variance about their mean, per axis (x and y pooled) [N^2]
};
/// The push's sensor zero measured where the sensor's true force is zero (samples_without_contact); none on a push
/// whose rod starts pressed (or with fewer than kRestSamplesForZero such samples).
std::optional<MeasuredZero> measured_sensor_zero(const DiagnosisPush& push);
/// measured_sensor_zero()'s z [N].
std::optional<Eigen::Vector2d> measured_sensor_zero_N(const DiagnosisPush& push);

}  // namespace pushpred
