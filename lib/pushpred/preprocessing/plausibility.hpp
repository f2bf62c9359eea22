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
};

/// Throws InputError naming `recording.source`, the stream and the problem when a bound is broken.
void check_plausible(const Recording& recording, const PlausibilityLimits& limits = {});

}  // namespace pushpred
