#pragma once
// The planned force of the paper's prediction phase: what a planner would command, here the measured input
// sampled sparsely (10 Hz by default) and held (zero-order) between samples, so the prediction never sees the
// measured force itself. Channels and frames as in SynchronisedPush::applied_input():
// [f_x, f_y] [N] in {R} and T_C + r_m x f_C [N m] about the object centre.
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/systems/sampled_signal.hpp"

namespace pushpred {

struct PlannedForce {
  SampledSignal signal;  ///< 3 channels, zero-order hold, samples at t0, t0 + 1/rate, ... < t1
  double t0_s = 0, t1_s = 0;
  double rate_hz = 0;
};

/// Samples `push`'s measured input at t0, t0 + 1/rate_hz, ... (strictly before t1) and holds it. The value at
/// each sampling time is the measured input at the first grid sample at or after it. Throws InputError for
/// t1 <= t0, a span outside the push, or a rate that is not positive.
PlannedForce plan_from_measurement(const SynchronisedPush& push, double t0_s, double t1_s, double rate_hz = 10.0);

/// The planned motion of the pusher tip, the motion counterpart of PlannedForce: what a planner commands is a
/// path of the tip, here the recorded tip path r_C of the phase (SynchronisedPush::tip_m, {R}) sampled at the
/// same times as the planned force and held (zero-order). The value held from t_k on is the mean tip velocity
/// over the plan step [t_k, min(t_k + 1/rate, t1)] [m/s]: the planned waypoints' difference, so it reads the tip
/// path of [t0, t1] only, never the object's motion, and not the recording's sample-to-sample noise.
struct PlannedTipVelocity {
  SampledSignal signal;  ///< 2 channels (v_x, v_y [m/s], {R}), zero-order hold, samples at t0, t0 + 1/rate, ... < t1
  double t0_s = 0, t1_s = 0;
  double rate_hz = 0;
};

/// Samples the tip path of `push` at the planned force's times (plan_from_measurement) and holds the mean tip
/// velocity of each plan step. Throws InputError as plan_from_measurement does.
PlannedTipVelocity plan_tip_velocity_from_measurement(const SynchronisedPush& push, double t0_s, double t1_s,
                                                      double rate_hz = 10.0);

}  // namespace pushpred
