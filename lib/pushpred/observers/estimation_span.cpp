#include "pushpred/observers/estimation_span.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/QR>

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

namespace {

/// Coefficients (one column per signal column) of the least-squares polynomial of `order` in tau.
Eigen::MatrixXd polynomial_fit(const Eigen::VectorXd& tau, const Eigen::MatrixXd& values, int order) {
  Eigen::MatrixXd H(tau.size(), order + 1);
  for (int j = 0; j <= order; ++j) H.col(j) = tau.array().pow(j);
  return H.colPivHouseholderQr().solve(values);
}

}  // namespace

InitialMotion initial_motion(const SynchronisedPush& push, const EstimationSpan& span, double window_s) {
  const double t0 = push.t_s(span.first);
  Eigen::Index n = 2;
  while (n < span.size() && push.t_s(span.first + n) - t0 <= window_s + 1e-9) ++n;
  // Time scaled to [0, 1] keeps the normal equations well conditioned.
  const double scale = push.t_s(span.first + n - 1) - t0;
  const Eigen::VectorXd tau = (push.t_s.segment(span.first, n).array() - t0) / scale;
  const Eigen::MatrixXd y = push.pose.middleRows(span.first, n).rowwise() - push.pose.row(span.first);
  const int order = n >= 4 ? 2 : 1;
  const Eigen::MatrixXd c = polynomial_fit(tau, y, order);
  InitialMotion m;
  m.velocity = c.row(1) / scale;
  if (order == 2) m.acceleration = 2 * c.row(2) / (scale * scale);
  const Eigen::MatrixXd u = push.applied_input().middleRows(span.first, n);
  const Eigen::MatrixXd line = polynomial_fit(tau, u, 1);
  m.input = line.row(0);
  m.input_rate = line.row(1) / scale;
  return m;
}

}  // namespace pushpred
