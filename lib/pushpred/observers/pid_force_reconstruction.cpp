#include "pushpred/observers/pid_force_reconstruction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/nominal_inertia.hpp"
#include "pushpred/observers/estimation_span.hpp"
#include "pushpred/systems/exact_discretisation.hpp"
#include "pushpred/systems/linear_system.hpp"

namespace pushpred {
namespace {

constexpr const char* kReconstruction = "PID force reconstruction";

}  // namespace

void PidGains::validate() const {
  const auto gain = [](const char* name) { return std::string(kReconstruction) + ": gain " + name; };
  require_not_negative_finite(kp, gain("kp"));
  require_not_negative_finite(ki, gain("ki"));
  require_not_negative_finite(kd, gain("kd"));
  require_not_negative_finite(lp, gain("lp"));
  require_not_negative_finite(li, gain("li"));
  require_not_negative_finite(ld, gain("ld"));
}

void PidReconstructionOptions::validate() const {
  require_nominal_inertia_choice(mass_kg, inertia_kgm2, kReconstruction);
  require_positive_finite(velocity_window_s, std::string(kReconstruction) + ": initial-velocity window [s]");
  integrator.validate();
}

PidForceReconstruction::PidForceReconstruction(PidGains gains, PidReconstructionOptions options)
    : gains_(gains), options_(std::move(options)) {
  gains_.validate();
  options_.validate();
}

namespace {

// What both paths need: the span, the nominal inertias, the linear system and its initial state.
struct PidSetup {
  EstimationSpan span;
  Eigen::Vector3d M;
  Eigen::RowVector3d origin;
  Eigen::VectorXd t;
  std::unique_ptr<LinearSystem> system;
  Eigen::VectorXd x0;
};

PidSetup set_up(const PidGains& gains, const PidReconstructionOptions& options, const SynchronisedPush& push,
                double t0, double t1) {
  PidSetup p;
  p.span = estimation_span(push, t0, t1, "PID force reconstruction");
  try {
    p.M = nominal_inertia(push.shape, options.mass_kg, options.inertia_kgm2);
  } catch (const InputError& e) {
    throw InputError(about(push.source, std::string("PID force reconstruction: ") + e.what()));
  }
  const Eigen::Vector3d& M = p.M;
  const Eigen::Vector3d kp(gains.kp, gains.kp, gains.lp), ki(gains.ki, gains.ki, gains.li),
      kd(gains.kd, gains.kd, gains.ld);

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
  const Eigen::Index n = p.span.size();
  p.origin = push.pose.row(p.span.first);
  const Eigen::MatrixX3d y = push.pose.middleRows(p.span.first, n).rowwise() - p.origin;
  p.t = push.t_s.segment(p.span.first, n);
  Eigen::MatrixX3d slope(n, 3);
  for (Eigen::Index k = 0; k + 1 < n; ++k) slope.row(k) = (y.row(k + 1) - y.row(k)) / (p.t(k + 1) - p.t(k));
  slope.row(n - 1) = slope.row(n - 2);
  p.system = std::make_unique<LinearSystem>(
      A, B, std::vector<SampledSignal>{SampledSignal(p.t, y, Hold::First), SampledSignal(p.t, slope, Hold::Zero)});

  const InitialMotion motion = initial_motion(push, p.span, options.velocity_window_s);
  p.x0 = Eigen::VectorXd::Zero(9);
  for (int c = 0; c < 3; ++c) {
    p.x0(3 * c + 1) = motion.velocity(c);
    // The integral term carries the measured acceleration, so that f_hat starts at M a0.
    if (ki(c) > 0) p.x0(3 * c + 2) = M(c) * motion.acceleration(c) / ki(c);
  }
  return p;
}

PidForceReconstruction::Tracking outputs(const PidSetup& p, const SynchronisedPush& push, const Eigen::MatrixXd& X) {
  const Eigen::Index n = p.span.size();
  PidForceReconstruction::Tracking out;
  DisturbanceEstimate& e = out.estimate;
  e.estimator = "pid";
  e.t_s = p.t;
  e.u = push.applied_input().middleRows(p.span.first, n);
  e.nominal_inertia = p.M;
  e.velocity.resize(n, 3);
  out.simulated_pose.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) {
      e.velocity(k, c) = X(k, 3 * c + 1);
      out.simulated_pose(k, c) = X(k, 3 * c) + p.origin(c);
    }
  e.total.resize(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index b = std::max<Eigen::Index>(k, 1), a = b - 1;
    e.total.row(k) = (e.velocity.row(b) - e.velocity.row(a)).cwiseProduct(p.M.transpose()) / (p.t(b) - p.t(a));
  }
  e.d_hat = e.total - e.u;
  return out;
}

}  // namespace

DisturbanceEstimate PidForceReconstruction::estimate(const SynchronisedPush& push, double t0, double t1) const {
  return track(push, t0, t1).estimate;
}

DisturbanceEstimate PidForceReconstruction::estimate_exactly(const SynchronisedPush& push, double t0, double t1) const {
  return track_exactly(push, t0, t1).estimate;
}

PidForceReconstruction::Tracking PidForceReconstruction::track(const SynchronisedPush& push, double t0,
                                                               double t1) const {
  const PidSetup p = set_up(gains_, options_, push, t0, t1);
  return outputs(p, push, integrate(*p.system, options_.integrator, p.t(0), p.x0, p.t));
}

PidForceReconstruction::Tracking PidForceReconstruction::track_exactly(const SynchronisedPush& push, double t0,
                                                                       double t1) const {
  const PidSetup p = set_up(gains_, options_, push, t0, t1);
  return outputs(p, push, propagate_exactly(*p.system, p.x0));
}

}  // namespace pushpred
