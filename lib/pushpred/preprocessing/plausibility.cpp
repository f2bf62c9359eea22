#include "pushpred/preprocessing/plausibility.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pushpred/core/error.hpp"

namespace pushpred {

namespace {

void check_times(const std::string& source, const std::string& name, const TimedStream& s,
                 const PlausibilityLimits& limits) {
  const std::string where = "stream '" + name + "'";
  const Eigen::Index n = s.size();
  if (n < 2) throw InputError(about(source, where + " has fewer than two samples"));
  const double largest = std::max(std::abs(s.start_s()), std::abs(s.end_s()));
  if (largest > limits.max_time_s)
    throw InputError(about(source, where + " has time stamps near " + three_significant_digits(largest) +
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
    throw InputError(about(source, where + " runs at " + three_significant_digits(rate) + " Hz (median step " +
                                       three_significant_digits(1.0 / rate) + " s), outside " + three_significant_digits(limits.min_rate_hz) + " to " +
                                       three_significant_digits(limits.max_rate_hz) +
                                       " Hz; the dataset's streams run near 250 Hz with time stamps in seconds"));
  if (gap > limits.max_gap_s)
    throw InputError(about(source, where + " has a gap of " + three_significant_digits(gap) + " s between rows " +
                                       std::to_string(widest) + " and " + std::to_string(widest + 1) +
                                       " (the rest of the stream spans " + three_significant_digits(s.end_s() - s.start_s() - gap) +
                                       " s); at most " + three_significant_digits(limits.max_gap_s) + " s is accepted"));
  if (s.end_s() - s.start_s() > limits.max_span_s)
    throw InputError(about(source, where + " spans " + three_significant_digits(s.end_s() - s.start_s()) + " s, longer than the " +
                                       three_significant_digits(limits.max_span_s) + " s a push may last"));
}

void check_column(const std::string& source, const std::string& name, const TimedStream& s, int column,
                  const char* what, double bound, const char* unit) {
  Eigen::Index row = 0;
  const double largest = s.values.col(column).cwiseAbs().maxCoeff(&row);
  if (!(largest <= bound))
    throw InputError(about(source, "stream '" + name + "' has " + what + " " + three_significant_digits(s.values(row, column)) + " " +
                                       unit + " at row " + std::to_string(row) + ", beyond the plausible " +
                                       three_significant_digits(bound) + " " + unit));
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

}  // namespace pushpred
