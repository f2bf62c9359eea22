#pragma once
// Continuous-time systems x' = f(t, x), in the manner of Drake's systems framework: a system declares its
// state size and derivative (and Jacobian where it has one); integration is done elsewhere (CvodeIntegrator).
// A system owns whatever input signals drive it and says where they jump, so that the integrator can stop
// and re-initialise there instead of stepping across a discontinuity.
#include <Eigen/Core>
#include <vector>

namespace pushpred {

class ContinuousSystem {
 public:
  virtual ~ContinuousSystem() = default;

  /// Number of continuous states.
  virtual int state_size() const = 0;

  /// xdot = f(t, x). Called in the integrator's hot loop: must not allocate.
  virtual void derivative(double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                          Eigen::Ref<Eigen::VectorXd> xdot) const = 0;

  /// Whether jacobian() is provided. Linear systems provide it; otherwise CVODE uses difference quotients.
  virtual bool has_jacobian() const { return false; }

  /// J = df/dx at (t, x), state_size() x state_size(). Must not allocate.
  virtual void jacobian(double /*t*/, const Eigen::Ref<const Eigen::VectorXd>& /*x*/,
                        Eigen::Ref<Eigen::MatrixXd> /*J*/) const {}

  /// Times strictly inside (t0, t1) where an input jumps (zero-order-hold samples, a new planned force).
  virtual std::vector<double> discontinuities(double /*t0*/, double /*t1*/) const { return {}; }
};

}  // namespace pushpred
