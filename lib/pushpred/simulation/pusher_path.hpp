#pragma once
// The prescribed motion of the pusher rod's centre: a straight line of `length_m` in direction `direction`,
// starting at `start_m` at rest at `start_time_s` and ending at rest. The robot is position controlled and far
// stiffer than the contact, so the rod follows this path exactly whatever the force.
//
// Profiles (both end with the same raised-cosine stop):
// - constant speed: the speed rises to `speed_m_s` along a raised cosine of `ramp_s`, holds, and falls back
//   along a raised cosine of `ramp_s` (the real recordings: about 0.05 s from 5 % to 95 % of the speed, for
//   every speed from 10 to 150 mm/s). A path too short for both ramps gets shorter ramps.
// - constant acceleration: from rest at `acceleration_m_s2` until the raised-cosine stop of `ramp_s` brings
//   the rod to rest exactly at `length_m`.
// Units: metres, seconds, world (= robot) frame.
#include <Eigen/Core>
#include <vector>

namespace pushpred {

struct PusherMotion {
  enum class Profile { ConstantSpeed, ConstantAcceleration };
  Profile profile = Profile::ConstantSpeed;
  double speed_m_s = 0.01;         ///< cruise speed (ConstantSpeed)
  double acceleration_m_s2 = 0.0;  ///< (ConstantAcceleration)
  double length_m = 0.05;
  double ramp_s = 0.07;
};

class PusherPath {
 public:
  PusherPath() = default;
  /// Throws InputError for a non-positive speed, acceleration, length or ramp, or a zero direction.
  PusherPath(const Eigen::Vector2d& start_m, const Eigen::Vector2d& direction, double start_time_s,
             const PusherMotion& motion);

  /// Distance travelled along the path and its rate at time t (0 before the start, length after the end).
  double distance_m(double t_s) const;
  double speed_m_s(double t_s) const;
  Eigen::Vector2d position_m(double t_s) const { return start_ + distance_m(t_s) * direction_; }
  Eigen::Vector2d velocity_m_s(double t_s) const { return speed_m_s(t_s) * direction_; }

  double start_time_s() const { return t_start_; }
  double end_time_s() const { return t_end_; }
  const Eigen::Vector2d& start_m() const { return start_; }
  const Eigen::Vector2d& direction() const { return direction_; }
  double peak_speed_m_s() const { return v_peak_; }
  /// Times where the rod's acceleration jumps or its profile changes piece: the integrator stops there.
  std::vector<double> phase_boundaries() const;

 private:
  Eigen::Vector2d start_ = Eigen::Vector2d::Zero(), direction_ = Eigen::Vector2d::UnitX();
  PusherMotion motion_;
  double t_start_ = 0;
  // Phase ends, relative to t_start_: speeding up, holding (or accelerating), stopping.
  double rise_s_ = 0, hold_end_s_ = 0, t_end_ = 0;
  double v_peak_ = 0, rise_length_m_ = 0, hold_length_m_ = 0, stop_s_ = 0;
};

}  // namespace pushpred
