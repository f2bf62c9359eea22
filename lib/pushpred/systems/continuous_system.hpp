#pragma once
// Continuous-time systems x' = f(t, x), in the manner of Drake's systems framework: a system declares its
// state size and derivative (and Jacobian where it has one); integration is done elsewhere (CvodeIntegrator).
// A system owns whatever input signals drive it and says where they jump, so that the integrator can stop
// and re-initialise there instead of stepping across a discontinuity. As in Drake, the state of an integration
// belongs to the integrator, not to the system: the integrator holds the jump-free interval it is integrating
// across and passes it into every derivative() and jacobian() call (IntegrationInterval), so that a system is
// const and keeps no integration state of its own, and one system may be integrated by several integrators.
#include <Eigen/Core>
#include <vector>

namespace pushpred {

/// The interval [t0_s, t1_s] [s] free of declared jumps that the integrator is integrating across, held by the
/// integrator (CvodeIntegrator) and passed to every derivative() and jacobian() call. A system with
/// zero-order-held inputs evaluates them as seen from inside it (SampledSignal::evaluate_within), so that
/// derivative() at t1 uses the value held on the interval and not the one that starts at t1. (CVODE 6.4 happens to
/// end such an interval a rounding error short of t1; this keeps the result independent of that.) Systems without
/// held inputs ignore it. Empty (t1_s <= t0_s, the default): no interval; held inputs are read at t itself.
struct IntegrationInterval {
  double t0_s = 0;
  double t1_s = 0;
  bool empty() const { return !(t1_s > t0_s); }
};

class ContinuousSystem {
 public:
  virtual ~ContinuousSystem() = default;

  /// Number of continuous states.
  virtual int state_size() const = 0;

  /// xdot = f(t, x), t [s] inside `interval` (the integrator's; IntegrationInterval). Called in the integrator's
  /// hot loop: must not allocate.
  virtual void derivative(const IntegrationInterval& interval, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                          Eigen::Ref<Eigen::VectorXd> xdot) const = 0;

  /// Whether the system is stiff on the time scale of its solution: whether an explicit-like method (Adams with
  /// fixed-point iteration) would need steps much shorter than accuracy asks for, to stay stable. The integrator
  /// takes BDF with Newton iteration for a stiff system and Adams for one that is not (IntegratorOptions::Method).
  /// Default: stiff, the safe choice; each system says why it chooses otherwise.
  virtual bool stiff() const { return true; }

  /// Whether jacobian() is provided. Linear systems provide it; otherwise CVODE uses difference quotients.
  virtual bool has_jacobian() const { return false; }

  /// J = df/dx at (t, x), state_size() x state_size(), t inside `interval` as for derivative(). Must not allocate.
  virtual void jacobian(const IntegrationInterval& /*interval*/, double /*t*/,
                        const Eigen::Ref<const Eigen::VectorXd>& /*x*/, Eigen::Ref<Eigen::MatrixXd> /*J*/) const {}

  /// Times strictly inside (t0, t1) where an input jumps (zero-order-hold samples, a new planned force).
  virtual std::vector<double> discontinuities(double /*t0*/, double /*t1*/) const { return {}; }
};

}  // namespace pushpred
