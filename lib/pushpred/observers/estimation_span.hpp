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

/// The object's motion and the applied input at the span's first sample t0, from least-squares fits over the
/// span's first `window_s` seconds: a parabola through the pose samples (a line when the window holds fewer than
/// four samples) and a line through the input samples. The window looks forward only, so the estimate uses no
/// data from before the span.
struct InitialMotion {
  Eigen::RowVector3d velocity = Eigen::RowVector3d::Zero();      ///< x', y' [m/s], theta' [rad/s]
  Eigen::RowVector3d acceleration = Eigen::RowVector3d::Zero();  ///< x'', y'' [m/s^2], theta'' [rad/s^2]
  Eigen::RowVector3d input = Eigen::RowVector3d::Zero();         ///< u [N, N, N m] (the line's value at t0)
  Eigen::RowVector3d input_rate = Eigen::RowVector3d::Zero();    ///< u' [N/s, N/s, N m/s]
};
InitialMotion initial_motion(const SynchronisedPush& push, const EstimationSpan& span, double window_s);

}  // namespace pushpred
