#pragma once
// What `pushpred observe` reports for one push: the Q-filter observer and the PID force reconstruction side by
// side (the paper's figure 4), and the paper's check of both (figure 2): the pose re-simulated from each
// estimate's total force against the measured pose. This file computes the numbers; the output files and the
// terminal text are written by reports/observation_report.hpp.
#include <Eigen/Core>
#include <string>

#include "pushpred/observers/pid_force_reconstruction.hpp"
#include "pushpred/observers/q_filter_observer.hpp"

namespace pushpred {

struct ObservationOptions {
  double t_start_s = 0;
  double t_end_s = -1;  ///< negative: the end of the push
  QFilterObserverOptions observer;
  PidGains pid_gains;
};

struct Observation {
  std::string source;
  DisturbanceEstimate dob, pid;
  Eigen::MatrixX3d measured_pose;                    ///< over the span [m, m, rad]
  Eigen::MatrixX3d resimulated_dob, resimulated_pid;  ///< from each estimate's total force
  Eigen::RowVector3d rms_dob;                        ///< RMS of d_hat(DOB), for scale [N, N, N m]
  Eigen::RowVector3d rms_dob_minus_pid;              ///< RMS of d_hat(DOB) - d_hat(PID) [N, N, N m]
  Eigen::RowVector3d rms_resimulation_dob, rms_resimulation_pid;  ///< RMS re-simulated - measured [m, m, rad]
};

/// Runs both estimators over the span and the re-simulation check. Throws InputError for a bad span or options.
Observation observe_push(const SynchronisedPush& push, const ObservationOptions& options = {});

}  // namespace pushpred
