#include "pushpred/observers/pid_force_reconstruction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/observers/estimation_span.hpp"
#include "pushpred/systems/linear_system.hpp"

namespace pushpred {
namespace {

void require_gain(double v, const char* name) {
  if (!(v >= 0) || !std::isfinite(v)) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "PID force reconstruction: gain %s must be finite and not negative (got %g)", name, v);
    throw InputError(buf);
  }
}

}  // namespace

void PidGains::validate() const {
  require_gain(kp, "kp");
  require_gain(ki, "ki");
  require_gain(kd, "kd");
  require_gain(lp, "lp");
  require_gain(li, "li");
  require_gain(ld, "ld");
}

void PidReconstructionOptions::validate() const {
  if (!(mass_kg >= 0) || !std::isfinite(mass_kg))
    throw InputError("PID force reconstruction: nominal mass must be positive (or 0 for the shape's), got " +
                     std::to_string(mass_kg) + " kg");
  if (!(inertia_kgm2 >= 0) || !std::isfinite(inertia_kgm2))
    throw InputError("PID force reconstruction: nominal moment of inertia must be positive (or 0 for the shape's), got " +
                     std::to_string(inertia_kgm2) + " kg m^2");
  if (!(velocity_window_s > 0) || !std::isfinite(velocity_window_s))
    throw InputError("PID force reconstruction: initial-velocity window must be positive");
  integrator.validate();
}

PidForceReconstruction::PidForceReconstruction(PidGains gains, PidReconstructionOptions options)
    : gains_(gains), options_(std::move(options)) {
  gains_.validate();
  options_.validate();
}

DisturbanceEstimate PidForceReconstruction::estimate(const SynchronisedPush& push, double t0, double t1) const {
  return track(push, t0, t1).estimate;
}

PidForceReconstruction::Tracking PidForceReconstruction::track(const SynchronisedPush& push, double t0,
                                                               double t1) const {
  const EstimationSpan span = estimation_span(push, t0, t1, "PID force reconstruction");
  const double m = options_.mass_kg > 0 ? options_.mass_kg : push.shape.mass_kg;
  const double I = options_.inertia_kgm2 > 0 ? options_.inertia_kgm2 : push.shape.inertia_kgm2;
  if (!(m > 0) || !(I > 0) || !std::isfinite(m) || !std::isfinite(I))
    throw InputError(about(push.source, "PID force reconstruction: shape '" + push.shape.name +
                                            "' has no positive mass and moment of inertia"));
  const Eigen::Vector3d M(m, m, I);
  const Eigen::Vector3d kp(gains_.kp, gains_.kp, gains_.lp), ki(gains_.ki, gains_.ki, gains_.li),
      kd(gains_.kd, gains_.kd, gains_.ld);

  // States per channel c: 3c = r_sim, 3c + 1 = r_sim', 3c + 2 = iota. Inputs: r_meas relative to the first
  // sample (first-order hold) and its slope on each grid interval (held, so it jumps at every sample).
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(9, 9), B = Eigen::MatrixXd::Zero(9, 6);
  for (int c = 0; c < 3; ++c) {
    const int r = 3 * c, v = r + 1, i = r + 2;
    A(r, v) = 1;
    A(v, r) = -kp(c) / M(c);  // M v' = kp e + ki iota + kd (r_meas' - v)
    A(v, v) = -kd(c) / M(c);
    A(v, i) = ki(c) / M(c);
    B(v, c) = kp(c) / M(c);
    B(v, 3 + c) = kd(c) / M(c);
    A(i, r) = -1;  // iota' = e
    B(i, c) = 1;
  }
  const Eigen::Index n = span.size();
  const Eigen::RowVector3d origin = push.pose.row(span.first);
  const Eigen::MatrixX3d y = push.pose.middleRows(span.first, n).rowwise() - origin;
  const Eigen::VectorXd t = push.t_s.segment(span.first, n);
  Eigen::MatrixX3d slope(n, 3);
  for (Eigen::Index k = 0; k + 1 < n; ++k) slope.row(k) = (y.row(k + 1) - y.row(k)) / (t(k + 1) - t(k));
  slope.row(n - 1) = slope.row(n - 2);
  const LinearSystem system(A, B, {SampledSignal(t, y, Hold::First), SampledSignal(t, slope, Hold::Zero)});

  const InitialMotion motion = initial_motion(push, span, options_.velocity_window_s);
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(9);
  for (int c = 0; c < 3; ++c) {
    x0(3 * c + 1) = motion.velocity(c);
    // The integral term carries the measured acceleration, so that f_hat starts at M a0.
    if (ki(c) > 0) x0(3 * c + 2) = M(c) * motion.acceleration(c) / ki(c);
  }
  CvodeIntegrator integrator(system, options_.integrator);
  const Eigen::MatrixXd X = integrator.solve(t(0), x0, t);

  Tracking out;
  DisturbanceEstimate& e = out.estimate;
  e.estimator = "pid";
  e.t_s = t;
  e.u = push.applied_input().middleRows(span.first, n);
  e.nominal_inertia = M;
  e.velocity.resize(n, 3);
  out.simulated_pose.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) {
      e.velocity(k, c) = X(k, 3 * c + 1);
      out.simulated_pose(k, c) = X(k, 3 * c) + origin(c);
    }
  e.total.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index b = std::max<Eigen::Index>(k, 1), a = b - 1;
    e.total.row(k) = (e.velocity.row(b) - e.velocity.row(a)).cwiseProduct(M.transpose()) / (t(b) - t(a));
  }
  e.d_hat = e.total - e.u;
  return out;
}

}  // namespace pushpred
