#pragma once
// The paper's check of a force estimate (section II-B, figure 2): drive the object's equations of motion
// M r'' = (the estimate's total force and torque, DisturbanceEstimate::total) from the measured pose and the
// estimate's velocity at the first sample, and compare the resulting pose with the measured one.
#include <Eigen/Core>

#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/systems/cvode_integrator.hpp"

namespace pushpred {

/// Pose x, y [m], theta [rad] at the estimate's samples, absolute (same frame as push.pose). The total force is
/// held at its reported interval mean over each grid interval, so that the re-simulated velocity at every sample
/// is the estimator's own. Throws InputError when the estimate does not belong to `push`.
Eigen::MatrixX3d resimulate_pose(const SynchronisedPush& push, const DisturbanceEstimate& estimate,
                                 const IntegratorOptions& integrator = {});

/// Root-mean-square over rows of each column of a - b.
Eigen::RowVector3d rms_difference(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b);

}  // namespace pushpred
