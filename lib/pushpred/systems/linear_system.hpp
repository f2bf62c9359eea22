#pragma once
// x' = A x + B u(t): a linear time-invariant ContinuousSystem driven by a held SampledSignal, and the
// double integrator M r'' = F(t) built on it. Every continuous system of pushpred is of this kind, so CVODE
// gets the exact Jacobian (A) and the jumps of zero-order-held inputs.
//
// The system keeps no integration state (the interval being integrated comes with each call). Its only mutable
// member is a scratch buffer for the stacked inputs, so that derivative() does not allocate: its value means
// nothing between calls, but it makes one system usable by one thread at a time.
#include <Eigen/Core>
#include <vector>

#include "pushpred/systems/continuous_system.hpp"
#include "pushpred/systems/sampled_signal.hpp"

namespace pushpred {

class LinearSystem final : public ContinuousSystem {
 public:
  /// Throws InputError unless A is square, B has A's rows and as many columns as `input` has channels, and
  /// both are finite.
  LinearSystem(Eigen::MatrixXd A, Eigen::MatrixXd B, SampledSignal input);
  /// Several input signals, each with its own sample times and hold, stacked in order into u (B has as many
  /// columns as they have channels together); the system jumps wherever any of them does.
  LinearSystem(Eigen::MatrixXd A, Eigen::MatrixXd B, std::vector<SampledSignal> inputs);

  int state_size() const override { return static_cast<int>(A_.rows()); }
  /// A x + B u(t), the zero-order-held inputs as held inside `interval`.
  void derivative(const IntegrationInterval& interval, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                  Eigen::Ref<Eigen::VectorXd> xdot) const override;
  /// Stiff when a step as long as the shortest input sample interval h would take the fastest eigenvalue of A
  /// outside where Adams is stable and its fixed-point iteration converges (|h lambda| > 2). The PID
  /// reconstruction's rotation (ld / I near 8000 1/s, 4 ms samples: |h lambda| = 32) is stiff; the Q-filter
  /// observer (|lambda| = wn = 300 rad/s: 1.2) and the double integrator (lambda = 0) are not.
  bool stiff() const override { return stiff_; }
  bool has_jacobian() const override { return true; }
  void jacobian(const IntegrationInterval& interval, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                Eigen::Ref<Eigen::MatrixXd> J) const override;
  std::vector<double> discontinuities(double t0, double t1) const override;

  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::MatrixXd& B() const { return B_; }
  const std::vector<SampledSignal>& inputs() const { return inputs_; }

 private:
  Eigen::MatrixXd A_, B_;
  std::vector<SampledSignal> inputs_;
  bool stiff_ = true;
  // Scratch, not state: the stacked inputs inside one derivative() call, kept only so that it does not allocate.
  mutable Eigen::VectorXd u_;
};

/// M r'' = F(t) per channel: states [r (n), r' (n)], input F (n channels, held as `force` is). `inertia` holds
/// the n masses [kg] or moments of inertia [kg m^2]; throws InputError unless each is positive and finite.
LinearSystem double_integrator(const Eigen::VectorXd& inertia, SampledSignal force);

}  // namespace pushpred
