#pragma once
// The rest at the start of a push, and the sensors' noise measured over it: how far the pose wanders about a
// straight line (a line absorbs slow drift) and how far the applied input steps from one grid sample to the next
// while only the sensors' noise moves it. The PID gain fit (calibration/pid_gain_fit.hpp) scales its residuals by
// these. Units SI; the pose and the applied input u as in synchronised_push.hpp (SynchronisedPush::applied_input).
#include <Eigen/Core>
#include <cmath>
#include <string>

#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// How the rest at the start of a push is found. The real recordings start with the object still and the pusher
/// either in free air or already touching it (about half of them: the force reads a steady 1 to 3 N from the
/// first sample, so "before contact" would leave no rest); the rest therefore ends where the push begins: the
/// first sample at which the object has left its rest level (median of the first `reference_s`) by `moved_m`
/// or `moved_rad`, or the pusher's force f_C has changed from its rest level by `force_change_N`, less `margin_s`.
struct RestNoiseOptions {
  double reference_s = 0.04;            ///< the rest level is the median over the first this-long [s]
  double moved_m = 0.5e-3;              ///< the object has moved once it is this far from its rest level [m]...
  double moved_rad = 0.5 * M_PI / 180;  ///< ...or has turned this far [rad]...
  double force_change_N = 0.25;         ///< ...or |f_C - rest level| exceeds this [N] (the push has begun)
  double margin_s = 0.02;               ///< the rest ends this long before that onset [s]
  double min_rest_s = 0.1;              ///< shorter rests cannot measure the noise [s]
  /// Throws InputError naming the first value that is not positive and finite (margin_s may be 0).
  void validate() const;
};

/// The rest at the start of a push: grid samples [0, end), and the sample where the push begins (onset; the
/// push's size when it never does).
struct RestAtStart {
  Eigen::Index end = 0, onset = 0;
};
RestAtStart find_rest_at_start(const SynchronisedPush& push, const RestNoiseOptions& options = {});

/// Why the rest at the start of `push` is too short to measure the noise, as a sentence ("the object rests for
/// only ..."), or empty when it is long enough.
std::string short_rest_reason(const SynchronisedPush& push, const RestNoiseOptions& options = {});

/// The noise scales of one push, measured over its rest [rest_start_s, rest_end_s] (grid times).
struct RestNoise {
  /// sigma_pose: standard deviation of the pose about its least-squares line [m, m, rad].
  Eigen::Vector3d pose = Eigen::Vector3d::Ones();
  /// sigma_df: RMS of the step u(k+1) - u(k) of the applied input u [N, N, N m].
  Eigen::Vector3d force_step = Eigen::Vector3d::Ones();
  double rest_start_s = 0, rest_end_s = 0;
  long rest_samples = 0;
};

/// The noise over the grid samples [0, rest_end) of `push` (at least 3). A frozen stream gives a zero scale; the
/// caller decides what that means.
RestNoise noise_over_rest(const SynchronisedPush& push, Eigen::Index rest_end);

}  // namespace pushpred
