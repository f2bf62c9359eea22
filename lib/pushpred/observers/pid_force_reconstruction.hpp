#pragma once
// The PID force reconstruction of the paper's section II-B: a simulated object tracks the measured pose under
// a PID "controller" whose output is taken as the total force or torque,
//
//   M r_sim'' = kp e + ki \int e + kd e' = f_hat,   e = r_meas - r_sim     (per channel; l_* for rotation),
//
// and the unknown force is d_hat = f_hat - u (u as in disturbance_estimator.hpp).
//
// Realisation without differentiating the measurement: with s = M r_sim' - kd r_meas and iota = \int e,
//   r_sim' = (s + kd r_meas) / M,   s' = kp e + ki iota - kd r_sim',   iota' = e,
// which is the paper's equation exactly when r_meas is the linear interpolation of the samples (first-order
// hold; e' then jumps at samples but the right-hand side stays continuous, so CVODE never re-initialises).
// f_hat at a grid sample t_k is the mean of M r_sim'' over the interval that ends there,
// M (r_sim'(t_k) - r_sim'(t_{k-1})) / (t_k - t_{k-1}) (for the first sample, over the first interval). A point
// value would be ill-defined: the slope of r_meas jumps at every sample, and in the rotation channel the fast
// pole near -ld / I (about -8000 rad/s) turns each jump into an impulse-like transient of r_sim'' that a left
// limit would miss and a central difference would alias. The interval mean keeps every impulse, so that
// M r'' = f_hat integrated again follows r_sim. Positions are relative to the span's first sample.
//
// Initialisation at the span's first sample: r_sim = r_meas, r_sim' = v0 (initial_velocity, as the observer),
// iota = 0, so f_hat starts at 0 (the object is taken to move steadily).
#include <Eigen/Core>

#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/systems/cvode_integrator.hpp"

namespace pushpred {

/// PID gains, a plain value type. Defaults: the paper's, found there by trial and error.
struct PidGains {
  double kp = 46.6, ki = 34.6, kd = 15.4;    ///< translation: [N/m], [N/(m s)], [N s/m]
  double lp = 117.2, li = 137.8, ld = 24.5;  ///< rotation: [N m/rad], [N m/(rad s)], [N m s/rad]
  /// Throws InputError unless every gain is finite and not negative.
  void validate() const;
};

struct PidReconstructionOptions {
  double mass_kg = 0;           ///< nominal mass; 0: from the push's shape
  double inertia_kgm2 = 0;      ///< nominal moment of inertia; 0: from the push's shape
  double velocity_window_s = 0.04;
  IntegratorOptions integrator;
  void validate() const;
};

class PidForceReconstruction final : public DisturbanceEstimator {
 public:
  explicit PidForceReconstruction(PidGains gains = {}, PidReconstructionOptions options = {});

  std::string name() const override { return "pid"; }
  using DisturbanceEstimator::estimate;
  /// d_hat = f_hat - u; `velocity` is r_sim'.
  DisturbanceEstimate estimate(const SynchronisedPush& push, double t_start_s, double t_end_s) const override;

  /// The estimate together with the simulated pose r_sim that tracked the measurement.
  struct Tracking {
    DisturbanceEstimate estimate;
    Eigen::MatrixX3d simulated_pose;  ///< r_sim, absolute, same frame as the push's pose
  };
  Tracking track(const SynchronisedPush& push, double t_start_s, double t_end_s) const;

  const PidGains& gains() const { return gains_; }
  const PidReconstructionOptions& options() const { return options_; }

 private:
  PidGains gains_;
  PidReconstructionOptions options_;
};

}  // namespace pushpred
