#pragma once
// The files of `pushpred fit-pid` (calibration/pid_gain_fit.hpp's study): pid_gains.json, pid_fit.md and the
// reconstructed forces of one push as CSV. JSON and Markdown report lengths in mm, angles in degrees, forces in N
// and torques in N mm (each key or column says which); the CSV is SI.
#include <nlohmann/json.hpp>
#include <string>

#include "pushpred/calibration/pid_gain_fit.hpp"

namespace pushpred {

/// pid_gains.json: gains (paper, joint, per push), objective terms before and after, noise scales, and per push
/// the tracking RMS [mm, deg], roughness and RMS difference from the observer's d_hat, before and after.
nlohmann::json pid_fit_json(const PidFitStudy& study);
/// pid_fit.md: the same as tables.
std::string pid_fit_markdown(const PidFitStudy& study);

/// The reconstructed forces as CSV, one row per grid sample: t_s, then per channel (x [N], y [N], rotation [N m])
/// the applied input u, the observer's d_hat, and the PID's d_hat with the paper's and with the fitted gains
/// (calibration's pid_fit_forces computes them).
std::string pid_fit_forces_csv(const PidFitForces& forces);

}  // namespace pushpred
