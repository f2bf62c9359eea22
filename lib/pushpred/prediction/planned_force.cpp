#include "pushpred/prediction/planned_force.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pushpred/core/error.hpp"

namespace pushpred {

PlannedForce plan_from_measurement(const SynchronisedPush& push, double t0, double t1, double rate_hz) {
  if (!(rate_hz > 0) || !std::isfinite(rate_hz)) throw InputError("planned-force rate must be positive");
  // A plan sampled faster than the push's grid repeats grid samples; 1e9 Hz would ask for billions of them.
  if (rate_hz > push.rate_hz) {
    char text[128];
    std::snprintf(text, sizeof text, "planned-force rate of %g Hz is above the push's grid rate of %g Hz", rate_hz,
                  push.rate_hz);
    throw InputError(about(push.source, text));
  }
  if (!(t1 > t0)) throw InputError(about(push.source, "planned force needs t1 > t0"));
  if (t0 < -1e-9 || t1 > push.duration_s() + 1e-9)
    throw InputError(about(push.source, "planned-force span lies outside the push"));
  const Eigen::MatrixX3d u = push.applied_input();
  std::vector<double> times;
  for (long k = 0;; ++k) {
    const double t = t0 + k / rate_hz;
    if (t >= t1 - 1e-12) break;
    times.push_back(t);
  }
  Eigen::VectorXd t_s(static_cast<Eigen::Index>(times.size()));
  Eigen::MatrixXd values(t_s.size(), 3);
  for (Eigen::Index k = 0; k < t_s.size(); ++k) {
    t_s(k) = times[static_cast<size_t>(k)];
    values.row(k) = u.row(push.index_at(t_s(k)));
  }
  return {SampledSignal(t_s, values, Hold::Zero), t0, t1, rate_hz};
}

PlannedTipVelocity plan_tip_velocity_from_measurement(const SynchronisedPush& push, double t0, double t1,
                                                      double rate_hz) {
  // The same sampling times and checks as the planned force.
  const PlannedForce force = plan_from_measurement(push, t0, t1, rate_hz);
  const Eigen::VectorXd& t_s = force.signal.times();
  Eigen::MatrixXd values(t_s.size(), 2);
  for (Eigen::Index k = 0; k < t_s.size(); ++k) {
    const Eigen::Index a = push.index_at(t_s(k));
    Eigen::Index b = push.index_at(std::min(t_s(k) + 1.0 / rate_hz, t1));
    if (push.t_s(b) > t1 + 1e-9 && b > a) --b;  // stay within the phase's path
    const double dt = push.t_s(b) - push.t_s(a);
    values.row(k) = dt > 0 ? ((push.tip_m.row(b) - push.tip_m.row(a)) / dt).eval() : Eigen::RowVector2d::Zero().eval();
  }
  return {SampledSignal(t_s, values, Hold::Zero), t0, t1, rate_hz};
}

}  // namespace pushpred
