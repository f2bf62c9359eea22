#pragma once
// The slice of a push an estimator works on, and the state it starts from. Estimators see only the data
// inside their span, so that a span that starts mid-push (the paper's identification phases) is estimated as
// if the data began there.
#include <Eigen/Core>
#include <string>

#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// Grid samples first..last (inclusive) of a push.
struct EstimationSpan {
  Eigen::Index first = 0, last = 0;
  Eigen::Index size() const { return last - first + 1; }
};

/// The grid samples with t in [t_start_s, t_end_s] (the first one at or after t_start_s). Throws InputError,
/// naming `who`, the push and the span, when it holds fewer than two samples or the times are not finite.
EstimationSpan estimation_span(const SynchronisedPush& push, double t_start_s, double t_end_s, const std::string& who);

/// Object velocity x', y' [m/s], theta' [rad/s] at the span's first sample: slope of a least-squares line through
/// the pose samples of the span's first `window_s` seconds (at least two samples). The window looks forward
/// only, so the estimate uses no data from before the span.
Eigen::RowVector3d initial_velocity(const SynchronisedPush& push, const EstimationSpan& span, double window_s);

}  // namespace pushpred
