#include "pushpred/diagnosis/effect_floor.hpp"

#include <algorithm>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"

namespace pushpred {

FloorContext measure_floor_context(const std::vector<DiagnosisPush>& data, double friction_coefficient,
                                   double friction_spread, double relevance_fraction) {
  if (data.empty()) throw InputError("effect floors: no fit data");
  FloorContext c;
  const ShapeInfo& shape = data.front().push.shape;
  c.mass_kg = shape.mass_kg;
  c.inertia_kgm2 = shape.inertia_kgm2;
  c.radius_of_gyration_m = shape.mass_kg > 0 ? std::sqrt(shape.inertia_kgm2 / shape.mass_kg) : 0.0;
  c.friction_coefficient = friction_coefficient;
  c.friction_spread = friction_spread;
  c.relevance_fraction = relevance_fraction;
  std::vector<double> periods, accelerations;
  double speed2 = 0, travel = 0;
  long sliding = 0;
  for (const auto& d : data) {
    const Eigen::VectorXd& t = d.push.t_s;
    for (Eigen::Index k = 1; k < t.size(); ++k) periods.push_back(t(k) - t(k - 1));
    for (Eigen::Index k = 0; k < d.rows(); ++k) {
      if (d.stuck[static_cast<std::size_t>(k)]) continue;
      speed2 += d.smooth_velocity.row(k).head<2>().squaredNorm();
      // Time at low speed only where the speed is resolved: near a fast start or stop the smoothed speed is blur
      // (DiagnosisPush::blurred). The slow slips of stick-slip stay in: there the low-speed term acts.
      if (!d.blurred[static_cast<std::size_t>(k)])
        c.sliding_speeds_m_s.push_back(d.smooth_velocity.row(k).head<2>().norm());
      accelerations.push_back(d.smooth_acceleration.row(k).head<2>().norm());
      ++sliding;
    }
    if (d.rows() > 0) travel += (d.smooth_pose.row(d.rows() - 1).head<2>() - d.smooth_pose.row(0).head<2>()).norm();
  }
  if (!periods.empty()) {
    std::nth_element(periods.begin(), periods.begin() + static_cast<std::ptrdiff_t>(periods.size() / 2), periods.end());
    c.sample_period_s = periods[periods.size() / 2];
  }
  if (sliding > 0) {
    c.sliding_speed_m_s = std::sqrt(speed2 / static_cast<double>(sliding));
    // RMS, like the speeds: a mass error acts on the data through its acceleration everywhere, and a peak (the 95th
    // percentile was used before) is set by short speed ramps that carry little of the data.
    double a2 = 0;
    for (double a : accelerations) a2 += a * a;
    c.acceleration_m_s2 = std::sqrt(a2 / static_cast<double>(accelerations.size()));
  }
  c.travel_m = travel / static_cast<double>(data.size());
  // Keep a sample of at most 4000 speeds: enough for the shares the floors need.
  if (c.sliding_speeds_m_s.size() > 4000) {
    const std::size_t stride = c.sliding_speeds_m_s.size() / 4000 + 1;
    std::vector<double> kept;
    for (std::size_t k = 0; k < c.sliding_speeds_m_s.size(); k += stride) kept.push_back(c.sliding_speeds_m_s[k]);
    c.sliding_speeds_m_s = std::move(kept);
  }
  return c;
}

}  // namespace pushpred
