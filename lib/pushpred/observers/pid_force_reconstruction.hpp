#pragma once
// The PID force reconstruction of the paper's section II-B: a simulated object tracks the measured pose under
// a PID "controller" whose output is taken as the total force or torque,
//
//   M r_sim'' = kp e + ki \int e + kd e' = f_hat,   e = r_meas - r_sim     (per channel; l_* for rotation),
//
// and the unknown force is d_hat = f_hat - u (u as in disturbance_estimator.hpp).
//
// Realisation: per channel the states r_sim, r_sim' and iota = \int e, driven by r_meas held first-order
// between grid samples (the linear interpolation of the measured pose) and by its derivative, which is then the
// slope of each grid interval, held and jumping at every sample. CVODE therefore stops and re-initialises at
// every sample. (A realisation on r_meas alone, with s = M r_sim' - kd r_meas, avoids the jumps but recovers
// r_sim' from a difference of two large states: with I near 0.002 kg m^2 and ld = 24.5, the synthetic push of
// the tests then got rotational torque errors of half the torque's amplitude at rtol 1e-8, 2.5% with this one.)
//
// f_hat at a grid sample t_k is the mean of M r_sim'' over the interval that ends there,
// M (r_sim'(t_k) - r_sim'(t_{k-1})) / (t_k - t_{k-1}) (for the first sample, over the first interval): at each
// sample r_sim'' jumps by kd / M times the slope change, and in the rotation channel the fast pole near -ld / I
// (about -8000 rad/s) turns that into an impulse-like transient that a point value would miss or alias. The
// interval mean keeps every impulse, so that M r'' = f_hat integrated again follows r_sim. Positions are
// relative to the span's first sample.
//
// Initialisation at the span's first sample, from the same forward parabola fit as the observer (v0, a0):
// r_sim = r_meas, r_sim' = v0, iota = M a0 / ki, so that f_hat starts at M a0 and the tracking error at zero.
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
  double velocity_window_s = 0.03;  ///< forward window of the initial motion fit (as the observer's)
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

  /// The same from the exact discretisation of the same linear system (matrix exponentials for its two holds):
  /// the tests hold it equal to the CVODE path; about a thousand times faster (bench/bench_observers.cpp), for
  /// callers that run the reconstruction many times, such as a gain fit.
  DisturbanceEstimate estimate_exactly(const SynchronisedPush& push, double t_start_s, double t_end_s) const;
  Tracking track_exactly(const SynchronisedPush& push, double t_start_s, double t_end_s) const;

  const PidGains& gains() const { return gains_; }
  const PidReconstructionOptions& options() const { return options_; }

 private:
  PidGains gains_;
  PidReconstructionOptions options_;
};

}  // namespace pushpred
