#include "pushpred/observers/estimation_span.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pushpred/core/error.hpp"

namespace pushpred {

EstimationSpan estimation_span(const SynchronisedPush& push, double t0, double t1, const std::string& who) {
  if (!std::isfinite(t0) || !std::isfinite(t1)) throw InputError(about(push.source, who + ": span times must be finite"));
  EstimationSpan span;
  Eigen::Index count = 0;
  if (push.size() > 0 && push.t_s(push.index_at(t0)) >= t0 - 1e-9) {
    span.first = push.index_at(t0);
    span.last = span.first - 1;
    while (span.last + 1 < push.size() && push.t_s(span.last + 1) <= t1 + 1e-9) ++span.last;
    count = std::max<Eigen::Index>(span.size(), 0);
  }
  if (count < 2) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s: the span [%.4g, %.4g] s holds %ld grid samples of a %.4g s push; need at least 2",
                  who.c_str(), t0, t1, static_cast<long>(count), push.duration_s());
    throw InputError(about(push.source, buf));
  }
  return span;
}

Eigen::RowVector3d initial_velocity(const SynchronisedPush& push, const EstimationSpan& span, double window_s) {
  const double t0 = push.t_s(span.first);
  Eigen::Index n = 2;
  while (n < span.size() && push.t_s(span.first + n) - t0 <= window_s + 1e-9) ++n;
  const Eigen::VectorXd t = push.t_s.segment(span.first, n).array() - t0;
  const Eigen::MatrixX3d y = push.pose.middleRows(span.first, n);
  const double t_mean = t.mean();
  const Eigen::VectorXd dt = t.array() - t_mean;
  const Eigen::RowVector3d y_mean = y.colwise().mean();
  return (dt.transpose() * (y.rowwise() - y_mean)) / dt.squaredNorm();
}

}  // namespace pushpred
