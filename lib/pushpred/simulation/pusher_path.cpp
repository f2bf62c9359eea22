#include "pushpred/simulation/pusher_path.hpp"

#include <cmath>
#include <string>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

// Raised-cosine ramps: speed V (1 - cos(pi s / T)) / 2 rising, V (1 + cos(pi s / T)) / 2 falling.
double rising_distance(double v, double ramp, double s) {
  return 0.5 * v * (s - ramp / M_PI * std::sin(M_PI * s / ramp));
}
double falling_distance(double v, double ramp, double s) {
  return 0.5 * v * (s + ramp / M_PI * std::sin(M_PI * s / ramp));
}

}  // namespace

PusherPath::PusherPath(const Eigen::Vector2d& start, const Eigen::Vector2d& direction, double start_time_s,
                       const PusherMotion& motion)
    : start_(start), motion_(motion), t_start_(start_time_s) {
  if (!(direction.norm() > 0) || !direction.allFinite()) throw InputError("push direction must be a non-zero vector");
  direction_ = direction.normalized();
  require_positive_finite(motion.length_m, "push length");
  require_positive_finite(motion.ramp_s, "speed ramp duration");
  const double length = motion.length_m;
  if (motion.profile == PusherMotion::Profile::ConstantSpeed) {
    require_positive_finite(motion.speed_m_s, "push speed");
    v_peak_ = motion.speed_m_s;
    const double ramp = std::min(motion.ramp_s, length / v_peak_);  // both ramps fit into the path
    rise_s_ = ramp;
    stop_s_ = ramp;
    rise_length_m_ = 0.5 * v_peak_ * ramp;
    hold_length_m_ = length - 2 * rise_length_m_;
    hold_end_s_ = rise_s_ + hold_length_m_ / v_peak_;
  } else {
    require_positive_finite(motion.acceleration_m_s2, "push acceleration");
    const double a = motion.acceleration_m_s2, ramp = motion.ramp_s;
    // Accelerate over L_a, then stop along the raised cosine over v_peak ramp / 2: L_a + v_peak ramp / 2 = L with
    // v_peak = sqrt(2 a L_a); a quadratic in u = sqrt(L_a).
    const double beta = std::sqrt(2 * a) * ramp / 2;
    const double u = 0.5 * (-beta + std::sqrt(beta * beta + 4 * length));
    hold_length_m_ = u * u;
    v_peak_ = std::sqrt(2 * a * hold_length_m_);
    rise_s_ = 0;
    rise_length_m_ = 0;
    hold_end_s_ = v_peak_ / a;
    stop_s_ = ramp;
  }
  t_end_ = t_start_ + hold_end_s_ + stop_s_;
}

double PusherPath::distance_m(double t) const {
  const double s = t - t_start_;
  if (s <= 0) return 0.0;
  if (s < rise_s_) return rising_distance(v_peak_, rise_s_, s);
  if (s < hold_end_s_) {
    const double h = s - rise_s_;
    if (motion_.profile == PusherMotion::Profile::ConstantSpeed) return rise_length_m_ + v_peak_ * h;
    return 0.5 * motion_.acceleration_m_s2 * h * h;
  }
  const double f = s - hold_end_s_;
  if (f < stop_s_) return rise_length_m_ + hold_length_m_ + falling_distance(v_peak_, stop_s_, f);
  return rise_length_m_ + hold_length_m_ + 0.5 * v_peak_ * stop_s_;
}

double PusherPath::speed_m_s(double t) const {
  const double s = t - t_start_;
  if (s <= 0) return 0.0;
  if (s < rise_s_) return 0.5 * v_peak_ * (1 - std::cos(M_PI * s / rise_s_));
  if (s < hold_end_s_) {
    if (motion_.profile == PusherMotion::Profile::ConstantSpeed) return v_peak_;
    return motion_.acceleration_m_s2 * (s - rise_s_);
  }
  const double f = s - hold_end_s_;
  if (f < stop_s_) return 0.5 * v_peak_ * (1 + std::cos(M_PI * f / stop_s_));
  return 0.0;
}

std::vector<double> PusherPath::phase_boundaries() const {
  std::vector<double> b{t_start_};
  if (rise_s_ > 0) b.push_back(t_start_ + rise_s_);
  b.push_back(t_start_ + hold_end_s_);
  b.push_back(t_end_);
  return b;
}

}  // namespace pushpred
