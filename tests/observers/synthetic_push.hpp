#pragma once
// A push made up in closed form, for tests that need the truth: per channel the object follows
// y(t) = v0 t + (A / w) t - (A / w^2) sin(w t) (so y'' = A sin(w t), zero at t = 0), a known disturbance d(t)
// acts on it, and the pusher's input is what Newton's law then requires, u = M y'' - d. Sampled like the real
// data (uniform grid), noise-free.
#include <cmath>
#include <functional>
#include <string>

#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/reading/shape_table.hpp"
#include "test_support.hpp"

namespace pushpred::testing {

struct ChannelMotion {
  double v0 = 0, A = 0, w = 1;  // [m/s or rad/s], [m/s^2 or rad/s^2], [rad/s]
  double position(double t) const { return v0 * t + (A / w) * t - (A / (w * w)) * std::sin(w * t); }
  double acceleration(double t) const { return A * std::sin(w * t); }
};

struct SyntheticPushSpec {
  double rate_hz = 250, duration_s = 1.0;
  std::string shape = "rect2";
  ChannelMotion motion[3] = {{0.05, 0.2, 2 * M_PI * 1.5}, {-0.02, 0.1, 2 * M_PI * 0.8}, {0.1, 0.5, 2 * M_PI * 1.0}};
  std::function<double(int channel, double t)> disturbance;  ///< d per channel [N] / [N m]
};

inline SynchronisedPush synthetic_push(const SyntheticPushSpec& spec) {
  const auto n = static_cast<Eigen::Index>(std::floor(spec.duration_s * spec.rate_hz + 1e-9)) + 1;
  SynchronisedPush p = synthetic_push_shell(spec.shape, spec.rate_hz, n);
  const double M[3] = {p.shape.mass_kg, p.shape.mass_kg, p.shape.inertia_kgm2};
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = p.t_s(k);
    for (int c = 0; c < 3; ++c) {
      p.pose(k, c) = 0.4 * (c == 0) + spec.motion[c].position(t);  // an offset, as real poses have
      const double u = M[c] * spec.motion[c].acceleration(t) - spec.disturbance(c, t);
      if (c < 2) p.force_N(k, c) = u;
      else p.torque_about_centre_Nm(k) = u;
    }
  }
  return p;
}

}  // namespace pushpred::testing
