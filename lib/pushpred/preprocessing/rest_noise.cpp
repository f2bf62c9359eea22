#include "pushpred/preprocessing/rest_noise.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

/// Standard deviation of `v` about its least-squares line in `t`.
double std_about_line(const Eigen::VectorXd& t, const Eigen::VectorXd& v) {
  const Eigen::Index n = v.size();
  const Eigen::VectorXd tau = t.array() - t.mean();
  const double slope = tau.dot(v) / tau.squaredNorm();
  const Eigen::VectorXd r = (v.array() - v.mean()).matrix() - slope * tau;
  return std::sqrt(r.squaredNorm() / static_cast<double>(n - 2));
}

}  // namespace

void RestNoiseOptions::validate() const {
  require_positive_finite(reference_s, "rest at the start: the rest level's window [s]");
  require_positive_finite(moved_m, "rest at the start: the motion threshold [m]");
  require_positive_finite(moved_rad, "rest at the start: the rotation threshold [rad]");
  require_positive_finite(force_change_N, "rest at the start: the force threshold [N]");
  require_not_negative_finite(margin_s, "rest at the start: the margin [s]");
  require_positive_finite(min_rest_s, "rest at the start: the shortest rest [s]");
}

RestAtStart find_rest_at_start(const SynchronisedPush& push, const RestNoiseOptions& o) {
  const Eigen::Index n = push.size();
  RestAtStart rest;
  if (n < 2) return rest;
  Eigen::Index ref = 1;
  while (ref < n && push.t_s(ref) - push.t_s(0) <= o.reference_s + 1e-9) ++ref;
  const auto median = [ref](const auto& column) {
    std::vector<double> v(static_cast<std::size_t>(ref));
    for (Eigen::Index k = 0; k < ref; ++k) v[static_cast<std::size_t>(k)] = column(k);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(ref / 2), v.end());
    return v[static_cast<std::size_t>(ref / 2)];
  };
  const Eigen::Vector3d pose0(median(push.pose.col(0)), median(push.pose.col(1)), median(push.pose.col(2)));
  const Eigen::Vector2d force0(median(push.force_N.col(0)), median(push.force_N.col(1)));
  while (rest.onset < n &&
         (push.pose.row(rest.onset).head<2>().transpose() - pose0.head<2>()).norm() <= o.moved_m &&
         std::abs(push.pose(rest.onset, 2) - pose0(2)) <= o.moved_rad &&
         (push.force_N.row(rest.onset).transpose() - force0).norm() <= o.force_change_N)
    ++rest.onset;
  if (rest.onset == n) {
    rest.end = n;  // never pushed: all rest
    return rest;
  }
  while (rest.end < rest.onset && push.t_s(rest.end) <= push.t_s(rest.onset) - o.margin_s + 1e-9) ++rest.end;
  return rest;
}

std::string short_rest_reason(const SynchronisedPush& push, const RestNoiseOptions& options) {
  options.validate();
  const RestAtStart rest = find_rest_at_start(push, options);
  const double rest_s = rest.end >= 2 ? push.t_s(rest.end - 1) - push.t_s(0) : 0.0;
  if (rest.end < 3 || rest_s < options.min_rest_s - 1e-9) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "the object rests for only %.3g s at the start (the push begins at %.3g s, the rest ends %.3g s "
                  "before); the noise scales need %.3g s",
                  rest_s, rest.onset < push.size() ? push.t_s(rest.onset) : 0.0, options.margin_s,
                  options.min_rest_s);
    return buf;
  }
  return {};
}

RestNoise noise_over_rest(const SynchronisedPush& push, Eigen::Index n) {
  if (n < 3 || n > push.size()) throw InputError(about(push.source, "rest noise: the rest needs 3 samples or more"));
  RestNoise noise;
  noise.rest_start_s = push.t_s(0);
  noise.rest_end_s = push.t_s(n - 1);
  noise.rest_samples = static_cast<long>(n);
  const Eigen::VectorXd t = push.t_s.head(n);
  const Eigen::MatrixX3d u = push.applied_input().topRows(n);
  for (int c = 0; c < 3; ++c) {
    noise.pose(c) = std_about_line(t, push.pose.col(c).head(n));
    const Eigen::VectorXd du = u.col(c).tail(n - 1) - u.col(c).head(n - 1);
    noise.force_step(c) = std::sqrt(du.squaredNorm() / static_cast<double>(n - 1));
  }
  return noise;
}

}  // namespace pushpred
