#include "pushpred/preprocessing/plausibility.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {
namespace {

std::string number(double value) {
  std::ostringstream s;
  s.precision(3);
  s << value;
  return s.str();
}

void check_times(const std::string& source, const std::string& name, const TimedStream& s,
                 const PlausibilityLimits& limits) {
  const std::string where = "stream '" + name + "'";
  const Eigen::Index n = s.size();
  if (n < 2) throw InputError(about(source, where + " has fewer than two samples"));
  const double largest = std::max(std::abs(s.start_s()), std::abs(s.end_s()));
  if (largest > limits.max_time_s)
    throw InputError(about(source, where + " has time stamps near " + number(largest) +
                                       ", which are not Unix seconds (milliseconds?); the format stores seconds"));
  std::vector<double> steps(static_cast<size_t>(n - 1));
  Eigen::Index widest = 0;
  for (Eigen::Index i = 1; i < n; ++i) {
    steps[static_cast<size_t>(i - 1)] = s.t_s(i) - s.t_s(i - 1);
    if (steps[static_cast<size_t>(i - 1)] > steps[static_cast<size_t>(widest)]) widest = i - 1;
  }
  const double gap = steps[static_cast<size_t>(widest)];
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double rate = 1.0 / steps[steps.size() / 2];
  if (rate < limits.min_rate_hz || rate > limits.max_rate_hz)
    throw InputError(about(source, where + " runs at " + number(rate) + " Hz (median step " +
                                       number(1.0 / rate) + " s), outside " + number(limits.min_rate_hz) + " to " +
                                       number(limits.max_rate_hz) +
                                       " Hz; the dataset's streams run near 250 Hz with time stamps in seconds"));
  if (gap > limits.max_gap_s)
    throw InputError(about(source, where + " has a gap of " + number(gap) + " s between rows " +
                                       std::to_string(widest) + " and " + std::to_string(widest + 1) +
                                       " (the rest of the stream spans " + number(s.end_s() - s.start_s() - gap) +
                                       " s); at most " + number(limits.max_gap_s) + " s is accepted"));
  if (s.end_s() - s.start_s() > limits.max_span_s)
    throw InputError(about(source, where + " spans " + number(s.end_s() - s.start_s()) + " s, longer than the " +
                                       number(limits.max_span_s) + " s a push may last"));
}

void check_column(const std::string& source, const std::string& name, const TimedStream& s, int column,
                  const char* what, double bound, const char* unit) {
  Eigen::Index row = 0;
  const double largest = s.values.col(column).cwiseAbs().maxCoeff(&row);
  if (!(largest <= bound))
    throw InputError(about(source, "stream '" + name + "' has " + what + " " + number(s.values(row, column)) + " " +
                                       unit + " at row " + std::to_string(row) + ", beyond the plausible " +
                                       number(bound) + " " + unit));
}

}  // namespace

void check_plausible(const Recording& r, const PlausibilityLimits& limits) {
  const std::string& src = r.source;
  for (const auto& [name, stream] : {std::pair<std::string, const TimedStream*>{"tip_pose", &r.tip_pose},
                                     {"object_pose", &r.object_pose},
                                     {"ft_wrench", &r.ft_wrench}}) {
    check_times(src, name, *stream, limits);
    if (name == "ft_wrench") {
      check_column(src, name, *stream, 0, "fx", limits.max_force_N, "N");
      check_column(src, name, *stream, 1, "fy", limits.max_force_N, "N");
      check_column(src, name, *stream, 2, "tz", limits.max_torque_Nm, "N m");
    } else {
      check_column(src, name, *stream, 0, "x", limits.max_position_m, "m");
      check_column(src, name, *stream, 1, "y", limits.max_position_m, "m");
      check_column(src, name, *stream, 2, "yaw", limits.max_yaw_rad, "rad");
    }
  }
}

void check_plausible_motion(const SynchronisedPush& p, const PlausibilityLimits& limits) {
  const Eigen::Index n = p.size();
  if (n < 2 || !(p.rate_hz > 0)) return;
  const Eigen::Index w =
      std::max<Eigen::Index>(1, static_cast<Eigen::Index>(std::lround(limits.motion_window_s * p.rate_hz)));
  const auto at = [&](Eigen::Index k) {
    return "at t = " + number(p.t_s(k)) + " s (grid sample " + std::to_string(k) + ")";
  };
  const auto refuse = [&](const std::string& what) {
    throw InputError(about(p.source, what + "; docs/robustness.md says why such motion is refused"));
  };
  const double rho =
      p.shape.mass_kg > 0 && p.shape.inertia_kgm2 > 0 ? std::sqrt(p.shape.inertia_kgm2 / p.shape.mass_kg) : 0.0;
  const double max_yaw_rate = rho > 0 ? limits.max_speed_m_s / rho : 0.0;
  // Speed, then yaw rate, then acceleration, so that a jump is named by the first of them it breaks.
  for (Eigen::Index k = 0; k + w < n; ++k) {
    const double speed = (p.pose.row(k + w).head<2>() - p.pose.row(k).head<2>()).norm() / (p.t_s(k + w) - p.t_s(k));
    if (speed > limits.max_speed_m_s)
      refuse("object_pose moves at " + number(speed) + " m/s " + at(k) + ", beyond the " +
             number(limits.max_speed_m_s) + " m/s a pushed object can");
  }
  for (Eigen::Index k = 0; max_yaw_rate > 0 && k + w < n; ++k) {
    const double yaw_rate = std::abs(p.pose(k + w, 2) - p.pose(k, 2)) / (p.t_s(k + w) - p.t_s(k));
    if (yaw_rate > max_yaw_rate)
      refuse("object_pose turns at " + number(yaw_rate) + " rad/s " + at(k) + ", beyond the " + number(max_yaw_rate) +
             " rad/s at which a point of " + p.shape.name + " one radius of gyration (" + number(1e3 * rho) +
             " mm) from its centre would move at " + number(limits.max_speed_m_s) + " m/s");
  }
  for (Eigen::Index k = 0; k + 2 * w < n; ++k) {
    const double h = 0.5 * (p.t_s(k + 2 * w) - p.t_s(k));
    const double acceleration =
        (p.pose.row(k + 2 * w).head<2>() - 2 * p.pose.row(k + w).head<2>() + p.pose.row(k).head<2>()).norm() / (h * h);
    if (acceleration > limits.max_acceleration_m_s2)
      refuse("object_pose accelerates at " + number(acceleration) + " m/s^2 " + at(k + w) + ", beyond the " +
             number(limits.max_acceleration_m_s2) + " m/s^2 a push force and friction can give it");
  }
  if (!p.shape.has_outline()) return;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double c = std::cos(p.pose(k, 2)), s = std::sin(p.pose(k, 2));
    const Eigen::Vector2d d = p.lever_m.row(k).transpose();
    const Eigen::Vector2d body(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
    const double penetration = kPusherRadius_m - signed_distance_to_outline(p.shape, body);
    if (penetration > limits.max_tip_penetration_m)
      refuse("the rod's surface lies " + number(1e3 * penetration) + " mm inside " + p.shape.name + "'s outline " +
             at(k) + ", more than the " + number(1e3 * limits.max_tip_penetration_m) +
             " mm a pressed contact allows: the object pose is not the object's");
  }
}

}  // namespace pushpred
