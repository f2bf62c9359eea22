#pragma once
// PID gains of the paper's force reconstruction (section II-B, observers/pid_force_reconstruction.hpp) fitted by
// Ceres instead of by trial and error: the calibration of an observer (not an estimator of the relation
// d = beta u + eps, hence a stage of its own above observers). The study's files are written by
// reports/pid_fit_report.hpp; the rest at the start and its noise are found by preprocessing/rest_noise.hpp. The gains should make the simulated object track the measured pose to
// within the pose sensor's noise while keeping the reconstructed total force f_hat no rougher than the force
// sensor's noise allows. Least squares over grid samples k and channels c:
//
//   tracking   (r_meas,ck - r_sim,ck) / sigma_pose_c                        k = 0 .. n-1
//   roughness  sqrt(lambda) (f_hat,c(k+1) - f_hat,ck) / sigma_df_c            k = 0 .. n-2
//
// sigma_pose_c [m, m, rad] and sigma_df_c [N, N, N m] are measured on each push while the object rests before the
// push begins (measure_rest_noise, preprocessing/rest_noise.hpp); lambda (default 1) weighs the two. Translation gains (kp, ki, kd) are shared
// by x and y and fitted on the x and y residuals, rotation gains (lp, li, ld) on the rotation residuals: two
// independent three-parameter problems. Each gain g enters Ceres as p = ln(g / 1e-6) (positive gains, relative
// steps; the residuals clamp g to [1e-6, 1e6]). A residual evaluation is one run of the reconstruction over the
// push (PidForceReconstruction::track_exactly, the exact discretisation; CVODE's track on request), differentiated
// by central differences (ceres::DynamicNumericDiffCostFunction). Fitting over a set of pushes sums their residual
// blocks: one gain set for all. docs/pid_gains.md states the objective and its results.
//
// Start. Levenberg-Marquardt is local, and the objective is flat where the derivative gain dominates the inertia
// (kd / M far above the 250 Hz sample rate): r_sim' then follows the measured slope within a sample whatever the
// gains, f_hat is M times the measured pose's second difference, and no gain changes anything. The paper's
// rotation gains lie there (ld / I is about 1.4e4 1/s for I = 0.0018 kg m^2). So Ceres starts from the best of the
// given gains and a few triple-pole designs of increasing bandwidth (PidGainFitOptions::start_bandwidths_rad_s).
#include <ceres/solver.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/observers/pid_force_reconstruction.hpp"
#include "pushpred/preprocessing/rest_noise.hpp"

namespace pushpred {

/// Why the PID fit cannot use `push`, or empty when it can: a frozen force sensor (d_hat = f_hat - u is then
/// meaningless), or a rest at the start too short to measure the noise.
std::string pid_fit_unsuitable_reason(const SynchronisedPush& push, const RestNoiseOptions& options = {});

/// Noise scales from the rest at the start of the push. Throws InputError when the push is unsuitable (above) or a
/// measured scale is zero (a frozen stream).
RestNoise measure_rest_noise(const SynchronisedPush& push, const RestNoiseOptions& options = {});

/// One push to fit on: the push, its noise scales, and the span the reconstruction runs over (the whole push by
/// default, rest included: the rest is where the gains show how much sensor noise they pass into f_hat).
struct PidFitPush {
  SynchronisedPush push;
  RestNoise noise;
  double t_start_s = 0;
  double t_end_s = std::numeric_limits<double>::infinity();  ///< clamped to the push's duration
};

/// The push with noise measured by measure_rest_noise (throws InputError when it is unsuitable).
PidFitPush make_pid_fit_push(SynchronisedPush push, const RestNoiseOptions& options = {});

/// Ceres options used by default: DENSE_QR, Levenberg-Marquardt, at most 50 iterations, function tolerance
/// 1e-7 (on the CVODE path smaller relative cost changes are integration noise), parameter tolerance 1e-6
/// (relative change of the log-gains), single thread, silent.
ceres::Solver::Options default_pid_fit_solver_options();

struct PidGainFitOptions {
  double roughness_weight = 1.0;  ///< lambda > 0
  /// The reconstruction the gains are fitted for (nominal inertia, CVODE tolerances).
  PidReconstructionOptions reconstruction;
  /// Run the reconstruction (and the observer the report compares with) by the exact discretisation of its
  /// linear system (track_exactly; about a thousand times faster, bench/bench_observers.cpp) rather than by
  /// CVODE (track; integration noise of about 1e-6 relative in f_hat). The two agree to that noise.
  bool exact_discretisation = true;
  /// Central-difference step relative to |p|, p = ln(g / 1e-6) (p is 7 to 21 for useful gains, so steps of 7e-4
  /// to 2e-3 in ln g: far above the CVODE path's noise, far below the curvature scale).
  double numeric_diff_relative_step = 1e-4;
  ceres::Solver::Options solver = default_pid_fit_solver_options();
  /// Starts besides the given gains, as closed-loop bandwidths w [rad/s]: the gains that put the three poles of
  /// M s^3 + kd s^2 + kp s + ki at -w (kd = 3 M w, kp = 3 M w^2, ki = M w^3; M the mean nominal mass or inertia of
  /// the set). Ceres starts from whichever start has the lowest objective (see the header for why).
  std::vector<double> start_bandwidths_rad_s = {1, 3, 10, 30, 100};
  bool fit_translation = true, fit_rotation = true;  ///< a problem left out keeps the given gains
  /// Throws InputError naming the first bad value (lambda <= 0, bad step, invalid Ceres options, ...).
  void validate() const;
};

/// One of the two independent problems.
enum class PidFitProblem { Translation, Rotation };
std::string pid_fit_problem_name(PidFitProblem problem);

/// How one problem was solved. Costs are Ceres' 1/2 sum of squared residuals.
struct PidFitSolve {
  bool fitted = false;      ///< false when the options left this problem out (its gains stay the given ones)
  double given_cost = 0;    ///< at the given (start) gains
  std::string start;        ///< the start Ceres ran from: "given gains" or "triple pole at W rad/s"
  double start_cost = 0, final_cost = 0;
  int iterations = 0;
  std::string termination;  ///< Ceres' termination type and message
};

struct PidGainFit {
  PidGains gains;  ///< the fitted gains
  PidFitSolve translation, rotation;
  long pushes = 0;
};

/// Fits the gains over `pushes` (one push: a per-push fit; several: one gain set for the set), starting from
/// `start`. Throws InputError for an empty set, a push flagged frozen_force_sensor, bad noise scales or bad
/// options; SolverError when the reconstruction fails at every start or Ceres returns no usable solution.
PidGainFit fit_pid_gains(const std::vector<PidFitPush>& pushes, const PidGainFitOptions& options,
                         const PidGains& start = {});

/// What one gain set does on one push: the objective's two terms and what they mean in units, and how far the
/// PID's d_hat lies from the disturbance observer's ("dob", QFilterObserver with default options and the
/// reconstruction's nominal inertia).
struct PidGainQuality {
  long samples = 0;
  Eigen::Vector3d tracking_sum = Eigen::Vector3d::Zero();   ///< sum_k ((r_meas - r_sim) / sigma_pose)^2
  Eigen::Vector3d roughness_sum = Eigen::Vector3d::Zero();  ///< sum_k ((f_hat(k+1) - f_hat(k)) / sigma_df)^2
  Eigen::Vector3d tracking_rms = Eigen::Vector3d::Zero();   ///< RMS of r_meas - r_sim [m, m, rad]
  Eigen::Vector3d roughness_rms = Eigen::Vector3d::Zero();  ///< RMS of f_hat(k+1) - f_hat(k) [N, N, N m]
  Eigen::Vector3d dob_rms = Eigen::Vector3d::Zero();        ///< RMS of d_hat_pid - d_hat_dob [N, N, N m]
  /// RMS of the measured input's step u(k+1) - u(k) over the span [N, N, N m]: not a property of the gains, the
  /// roughness of a force the sensor saw, for comparison.
  Eigen::Vector3d input_roughness_rms = Eigen::Vector3d::Zero();
};
PidGainQuality assess_pid_gains(const PidFitPush& push, const PidGains& gains, const PidGainFitOptions& options);

/// The forces a gain set reconstructs on one push, beside the observer's, over the push's span: the applied input
/// u and the estimates of the unknown force (d_hat [N, N, N m] per grid sample) of the disturbance observer, of the
/// PID with the paper's gains and of the PID with `fitted` gains. reports/pid_fit_report.hpp writes them as CSV.
struct PidFitForces {
  DisturbanceEstimate dob, paper, fitted;
};
PidFitForces pid_fit_forces(const PidFitPush& push, const PidGains& fitted, const PidGainFitOptions& options);

/// Gains are fitted in [kPidGainFloor, kPidGainCeiling] (log-parameterised, clamped in the residuals); a gain at the
/// floor is one the objective has no use for.
constexpr double kPidGainFloor = 1e-6, kPidGainCeiling = 1e6;

/// The channels a problem fits: translation x and y (0, 2), rotation (2, 1).
struct PidFitChannels {
  int first, count;
};
PidFitChannels pid_fit_channels(PidFitProblem problem);

/// The objective's two sums for `problem` over assessments: tracking and roughness, each summed over the
/// problem's channels and the pushes.
struct PidObjectiveTerms {
  double tracking = 0, roughness = 0;
};
PidObjectiveTerms pid_objective_terms(const std::vector<const PidGainQuality*>& qualities, PidFitProblem problem);

/// The objective of `problem` (1/2 (tracking + lambda roughness), summed over its channels and the pushes),
/// from assessments: what Ceres minimises, up to the integrator's accuracy.
double pid_objective(const std::vector<PidGainQuality>& qualities, PidFitProblem problem, double lambda);

// The study `pushpred fit-pid` runs (its files: reports/pid_fit_report.hpp).

struct PidFitStudyOptions {
  PidGainFitOptions fit;
  bool per_push = false;  ///< also fit one gain set per push (the joint fit over the set is always made)
};

struct PidFitPushResult {
  std::string source;
  RestNoise noise;
  PidGainQuality paper, joint;                 ///< with the paper's gains and with the joint fit's
  std::optional<PidGainFit> own;               ///< the per-push fit
  std::optional<PidGainQuality> own_quality;   ///< with the per-push fit's gains
};

struct PidFitStudy {
  PidGainFit joint;
  std::vector<PidFitPushResult> pushes;
  std::vector<BatchFailure> skipped;  ///< unsuitable pushes and why (pid_fit_unsuitable_reason)
  std::vector<BatchFailure> failed;   ///< files that could not be read, and per-push fits that failed
  double roughness_weight = 1.0;
  Eigen::Vector3d mean_inertia = Eigen::Vector3d::Zero();  ///< mean nominal m, m [kg], I [kg m^2] of the set
};

/// Fits jointly (and per push when asked) and assesses every push with the paper's and the fitted gains.
/// Throws InputError for an empty set or bad options.
PidFitStudy run_pid_fit_study(const std::vector<PidFitPush>& pushes, const PidFitStudyOptions& options);

}  // namespace pushpred
