#pragma once
// What `pushpred observe` reports for one push: the Q-filter observer and the PID force reconstruction side by
// side (the paper's figure 4), and the paper's check of both (figure 2): the pose re-simulated from each
// estimate's total force against the measured pose. This file computes the numbers and the text of the output
// files; the app writes them through StagedOutput and draws the plots with reports/plotting.hpp.
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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

/// An output file: its name inside the output folder and its text.
struct OutputFile {
  std::string name, text;
};

/// observer.csv, resimulation.csv, observation.json and the gnuplot scripts (forces.gp: DOB against PID, as the
/// paper's figure 4; trajectory.gp: re-simulated against measured pose, as its figure 2). Each script reads its
/// CSV and writes its PNG by relative name.
std::vector<OutputFile> observation_files(const Observation& observation);
/// Names of the gnuplot scripts among observation_files(), for the app to run.
std::vector<std::string> observation_plot_scripts();

nlohmann::json observation_json(const Observation& observation);
/// A few lines for the terminal: RMS differences in N, N m, mm and degrees.
std::string observation_summary(const Observation& observation);

}  // namespace pushpred
