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

}  // namespace pushpred
