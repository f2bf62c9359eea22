#pragma once
// The force sensor's zero, push by push. The real F/T sensor is not zeroed between pushes: with nothing touching,
// its fx, fy read a different offset on each push (docs/simulator.md). Where a push's rod rests clear of the object
// (samples_without_contact), that push's offset is measured; its deviation from the mean over such pushes would
// otherwise read as a change of friction or a force law. The common part, the mean, is left in the data for the
// force_offset effect to test against the pushes' spread; so is every sample of the rest window, which that test
// reads. A push whose rod presses from the start has no measured zero and is left as it is.
// Units: N; frames as synchronised_push.hpp (the robot frame).
#include <Eigen/Core>
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// The rig's force noise at rest, total standard deviation of fx and fy [N] (white and slow together; measured on
/// the real pushes by `pushpred simulate --measure-real`, docs/simulator.md).
inline constexpr double kRestForceNoise_N[2] = {0.0413, 0.101};

struct SensorZeros {
  std::vector<SynchronisedPush> pushes;  ///< the input, each measured push's deviation removed after its rest
  int measured = 0;                      ///< pushes whose rod rests clear of the object
  Eigen::Vector2d mean_N = Eigen::Vector2d::Zero();    ///< the measured zeros' mean (left in the data)
  Eigen::Vector2d spread_N = Eigen::Vector2d::Zero();  ///< their standard deviation per axis (0 below two)
  /// Per axis, whether the deviations were removed: only where the zeros spread beyond twice the larger of their own
  /// standard error and kRestForceNoise_N, not where a zeroed sensor's slow noise moves them.
  Eigen::Matrix<bool, 2, 1> removed = Eigen::Matrix<bool, 2, 1>::Constant(false);
};

/// The pushes with each measured zero's deviation from the mean removed from the samples after its rest window.
SensorZeros equalise_sensor_zeros(const std::vector<SynchronisedPush>& pushes);

}  // namespace pushpred
