#pragma once
// The common interface of disturbance estimators: a synchronised push in, the unknown force and torque
// d_hat(t) per channel out. Channels, here and everywhere in the library: 0 = x force [N], 1 = y force [N],
// 2 = rotation, torque about the object centre [N m]; frames and signs as in synchronised_push.hpp.
// Apps choose an estimator by name through make_disturbance_estimator().
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// Forces are reported per sample t_k as their mean over the grid interval [t_{k-1}, t_k] (the first sample: over
/// the first interval); a continuous-time estimator's output carries, between samples, ripple that a point value
/// would alias (q_filter_observer.hpp, pid_force_reconstruction.hpp). Velocities are values at t_k.
struct DisturbanceEstimate {
  std::string estimator;      ///< name of the estimator that made it
  Eigen::VectorXd t_s;        ///< times (a slice of the push's grid)
  Eigen::MatrixX3d u;         ///< applied input per channel at t_k: f_Cx, f_Cy [N], T_C + r_m x f_C [N m]
  Eigen::MatrixX3d d_hat;     ///< estimated unknown force [N] / torque [N m] per channel
  Eigen::MatrixX3d velocity;  ///< estimated object velocity x', y' [m/s], theta' [rad/s]
  /// The estimated total force [N] / torque [N m] M r'' per channel, as this estimator sees it. For the PID
  /// reconstruction it is f_hat = u + d_hat. For the observer, whose d_hat is Q-filtered, it is Q u + d_hat =
  /// M (Q y)'': u + d_hat would mix a filtered and an unfiltered force and, integrated twice, drift from the
  /// measured pose by about (2 zeta / wn) / M times the integral of d - d(t0).
  Eigen::MatrixX3d total;
  /// Nominal mass [kg] (x and y) and moment of inertia [kg m^2] (rotation) the estimator used.
  Eigen::Vector3d nominal_inertia = Eigen::Vector3d::Zero();
};

class DisturbanceEstimator {
 public:
  virtual ~DisturbanceEstimator() = default;
  virtual std::string name() const = 0;
  /// Estimates over the grid samples of `push` with t in [t_start_s, t_end_s], its states initialised from the
  /// data at t_start_s (no start-up transient). Throws InputError for an empty span.
  virtual DisturbanceEstimate estimate(const SynchronisedPush& push, double t_start_s, double t_end_s) const = 0;
  DisturbanceEstimate estimate(const SynchronisedPush& push) const {
    return estimate(push, 0.0, push.duration_s());
  }
};

/// The nominal mass [kg] and moment of inertia [kg m^2] an estimator's options give (0: the push's shape's), checked
/// alike for every estimator: throws InputError naming `who` unless both are finite and not negative.
void require_nominal_inertia_choice(double mass_kg, double inertia_kgm2, const std::string& who);

/// Names accepted by make_disturbance_estimator ("dob", "pid").
std::vector<std::string> disturbance_estimator_names();
/// The estimator called `name` with its default options; throws InputError naming the known ones otherwise.
std::unique_ptr<DisturbanceEstimator> make_disturbance_estimator(const std::string& name);

}  // namespace pushpred
