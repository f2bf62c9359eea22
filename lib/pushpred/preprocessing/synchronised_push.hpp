#pragma once
// One recorded push on a uniform time grid: the record every later stage (observers, estimators, prediction,
// diagnosis) reads.
//
// Frames and signs, stated once for the whole library:
// - {R}, the reference frame: the paper's x-y frame. Tip position and tip force are rotated into it by
//   C(theta_tip) (paper eqs. 1 and 3); the object pose is used as recorded. In every real file |theta_tip| is
//   below 1e-3 rad, so {R} and the robot frame agree to that angle.
// - Positions in metres, angles in radians (object yaw unwrapped, counter-clockwise positive), forces in
//   newtons, torques in newton metres about the vertical axis, counter-clockwise positive.
// - `force_N` is f_C, the force the pusher applies to the object: the negative of the sensor reading.
// - `lever_m` is r_m = r_C - r_O (tip position minus object centre), and `torque_about_centre_Nm` is
//   T_C + r_m x f_C, the pusher's whole torque about the object centre (the rotational input u of the paper).
// - `t_s` counts from `t0_unix_s`, the start of the span common to the three streams.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "pushpred/preprocessing/plausibility.hpp"
#include "pushpred/reading/recording.hpp"
#include "pushpred/reading/shape_table.hpp"

namespace pushpred {

/// Radius of the MCube pusher rod [m].
inline constexpr double kPusherRadius_m = 4.745e-3;

struct PreprocessOptions {
  double rate_hz = 250.0;               ///< uniform grid rate
  double glitch_position_m = 2e-3;      ///< a pose sample this far off its neighbours' midpoint is a glitch...
  double glitch_yaw_rad = 0.035;        ///< ...or this far in yaw (2 degrees)
  double contact_force_N = 0.25;        ///< |f_C| above this means contact (noise at rest: 0.04 N fx, 0.10 N fy std)
  double contact_gap_m = 2e-3;          ///< geometric contact: tip surface within this of the outline
  double barely_moves_m = 2e-3;         ///< object travel below this flags the push
  PlausibilityLimits limits;            ///< checked before any work (see plausibility.hpp)
};

/// Flags a push can carry; they never stop preprocessing, later stages decide what to do with them.
struct PushFlags {
  bool frozen_force_sensor = false;  ///< force stream holds a few repeated values: force cannot be trusted
  bool barely_moves = false;         ///< object travel below PreprocessOptions::barely_moves_m
  bool no_contact = false;           ///< contact never detected
  bool contact_from_geometry = false;  ///< contact found from tip-outline distance, not from force
  std::vector<std::string> names() const;
};

struct SynchronisedPush {
  std::string source;
  PushParameters push;  ///< from the file name, or surface "unknown" and the shape given by the caller
  ShapeInfo shape;
  double rate_hz = 0;
  double t0_unix_s = 0;

  Eigen::VectorXd t_s;                     ///< grid times since t0 [s]
  Eigen::MatrixX3d pose;                   ///< object x, y [m], yaw [rad] (unwrapped), {R}
  Eigen::MatrixX2d tip_m;                  ///< tip position r_C, {R}
  Eigen::VectorXd tip_yaw_rad;             ///< theta_tip
  Eigen::MatrixX2d force_N;                ///< f_C, force on the object, {R}
  Eigen::VectorXd tip_torque_Nm;           ///< T_C, negative of the measured tz
  Eigen::MatrixX2d lever_m;                ///< r_m = r_C - r_O
  Eigen::VectorXd torque_about_centre_Nm;  ///< T_C + r_m x f_C
  std::vector<char> in_contact;            ///< per grid sample

  bool has_contact = false;
  double contact_start_s = 0, contact_end_s = 0;  ///< first and last grid time in contact

  // What preprocessing found and did, for reports.
  int object_glitches = 0, tip_glitches = 0;
  std::vector<StreamRepair> repairs;  ///< the reader's and preprocessing's
  PushFlags flags;
  double stream_rate_hz[3] = {0, 0, 0};  ///< as recorded: object, force, tip

  Eigen::Index size() const { return t_s.size(); }
  double duration_s() const { return t_s.size() ? t_s(t_s.size() - 1) : 0.0; }
  /// The paper's inputs per channel (x, y, rotation): u = [f_Cx, f_Cy, T_C + r_m x f_C], n x 3.
  Eigen::MatrixX3d applied_input() const;
  /// Index of the first grid sample at or after time t (clamped to the grid).
  Eigen::Index index_at(double t_s) const;
};

/// Synchronises the three streams of `recording` onto a uniform grid over their common span, with yaw
/// unwrapping, single-sample glitch rejection and contact detection. `shape` supplies mass, inertia, outline.
/// Throws InputError when the recording is not plausible (check_plausible), the streams do not overlap or the span
/// is shorter than two grid samples.
SynchronisedPush synchronise(const Recording& recording, const ShapeInfo& shape, const PreprocessOptions& options = {});

/// Throws InputError naming the push, the sample (time and index) and the value when the object's motion on the grid
/// is beyond what a pushed object can do (PlausibilityLimits: speed, yaw rate, acceleration over a window, and the
/// rod's surface deep inside the outline). synchronise() calls it last.
void check_plausible_motion(const SynchronisedPush& push, const PlausibilityLimits& limits = {});

/// The shape named by the file name, or `shape_override` when given; throws InputError when neither
/// exists or the name is not in `table` (by default the known shapes: the published ones and the user's own).
const ShapeInfo& shape_for(const Recording& recording, const std::string& shape_override,
                           const ShapeTable& table = ShapeTable::known());

/// Reads and synchronises in one call.
SynchronisedPush load_push(const std::filesystem::path& path, const std::string& shape_override = "",
                           const PreprocessOptions& options = {});

// Building blocks, exposed for tests and for readers of other data.

/// Adds multiples of 2 pi so that consecutive samples differ by less than pi.
Eigen::VectorXd unwrap_angle(const Eigen::VectorXd& wrapped_rad);
/// Replaces single-sample spikes of a pose stream (x, y, yaw unwrapped) by the neighbours' midpoint; returns
/// how many were replaced.
int remove_single_sample_glitches(Eigen::MatrixX3d& pose, double position_threshold_m, double yaw_threshold_rad);
/// Linear interpolation of `values` (rows at strictly increasing `t`) at the times `grid`, which must lie
/// inside [t.front(), t.back()].
Eigen::MatrixXd interpolate_linear(const Eigen::VectorXd& t, const Eigen::MatrixXd& values, const Eigen::VectorXd& grid);
/// True when the force stream looks frozen: a handful of repeated values.
bool force_stream_frozen(const TimedStream& ft_wrench);

}  // namespace pushpred
