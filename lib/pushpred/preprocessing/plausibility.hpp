#pragma once
// Plausibility checks on a recording as read, before any work is done on it: a file can be well-formed and still
// not be a push of the dataset (time stamps in milliseconds, a stream with a gap of a day, forces of 1e300 N).
// Each such file is refused with an InputError naming the file, the stream and the problem, instead of being
// accepted silently or making the observer or CVODE run for ever. docs/robustness.md lists every check.
#include <string>

#include "pushpred/reading/recording.hpp"

namespace pushpred {

/// The bounds a recording must keep. The dataset's streams run near 250 Hz for 0.8 to 5.5 s, with steps of at
/// most 0.05 s, positions within a metre of the robot, forces of a few newtons: every bound is far outside that.
struct PlausibilityLimits {
  double min_rate_hz = 25.0;       ///< median sample rate of each stream, a tenth of the dataset's...
  double max_rate_hz = 2500.0;     ///< ...to ten times it
  double max_gap_s = 1.0;          ///< longest step between two samples of a stream
  double max_span_s = 600.0;       ///< first to last sample of a stream (real pushes: at most 5.5 s)
  double max_time_s = 1e11;        ///< larger stamps are not Unix seconds (1e11 s is the year 5138)
  double max_position_m = 10.0;    ///< |x|, |y| of tip and object in the robot frame
  double max_yaw_rad = 6.2832;     ///< |yaw| of tip and object (the object's is stored wrapped to (-pi, pi])
  double max_force_N = 1000.0;     ///< |fx|, |fy| read by the force-torque sensor
  double max_torque_Nm = 100.0;    ///< |tz|
  // The object's motion on the grid (check_plausible_motion, synchronised_push.hpp), over windows of
  // motion_window_s so that pose noise (0.1 mm) stays far below every bound. docs/robustness.md derives them; the
  // real pushes stay below a tenth of each (0.21 m/s, 2.6 rad/s, 6 m/s^2, over 20 ms).
  double motion_window_s = 0.02;
  /// Speed of the object's tracked centre: a rod-pushed object moves no faster than the rod plus what an impact adds
  /// (at most the rod's speed again); the dataset's fastest rod, 2.5 m/s^2 over 50 mm, reaches 0.5 m/s. It bounds the
  /// yaw rate too: no point of the object moves faster, and a lamina has points at least its radius of gyration
  /// rho = sqrt(I / m) from its centre, so |yaw rate| <= max_speed_m_s / rho.
  double max_speed_m_s = 2.0;
  /// Acceleration of the tracked centre: the push force over the mass plus friction (at most g); the dataset's
  /// largest force, 34.5 N, on its lightest object, 0.80 kg, gives 53 m/s^2.
  double max_acceleration_m_s2 = 100.0;
  /// How far the rod's surface may lie inside the object's outline (a contact pressed hard, a compliant tip): more is
  /// a pose that is not the object's, e.g. the object's pose written over by the tip's.
  double max_tip_penetration_m = 0.02;
};

/// Throws InputError naming `recording.source`, the stream and the problem when a bound is broken.
void check_plausible(const Recording& recording, const PlausibilityLimits& limits = {});

}  // namespace pushpred
