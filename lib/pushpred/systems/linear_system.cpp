#include "pushpred/systems/linear_system.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "pushpred/core/error.hpp"

namespace pushpred {

LinearSystem::LinearSystem(Eigen::MatrixXd A, Eigen::MatrixXd B, SampledSignal input)
    : LinearSystem(std::move(A), std::move(B), std::vector<SampledSignal>{std::move(input)}) {}

LinearSystem::LinearSystem(Eigen::MatrixXd A, Eigen::MatrixXd B, std::vector<SampledSignal> inputs)
    : A_(std::move(A)), B_(std::move(B)), inputs_(std::move(inputs)) {
  if (A_.rows() == 0 || A_.rows() != A_.cols()) throw InputError("linear system: A must be square and not empty");
  if (B_.rows() != A_.rows())
    throw InputError("linear system: B has " + std::to_string(B_.rows()) + " rows, A " + std::to_string(A_.rows()));
  Eigen::Index channels = 0;
  for (const auto& in : inputs_) channels += in.channels();
  if (inputs_.empty() || B_.cols() != channels)
    throw InputError("linear system: B has " + std::to_string(B_.cols()) + " columns but the inputs " +
                     std::to_string(channels) + " channels");
  if (!A_.allFinite() || !B_.allFinite()) throw InputError("linear system: A or B holds NaN or infinity");
  u_.resize(channels);
  double shortest_s = std::numeric_limits<double>::infinity();
  for (const auto& in : inputs_)
    for (Eigen::Index k = 0; k + 1 < in.samples(); ++k) shortest_s = std::min(shortest_s, in.times()(k + 1) - in.times()(k));
  const double fastest = A_.eigenvalues().cwiseAbs().maxCoeff();
  stiff_ = std::isfinite(shortest_s) ? fastest * shortest_s > 2.0 : fastest > 0;
}

void LinearSystem::derivative(const IntegrationInterval& interval, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                              Eigen::Ref<Eigen::VectorXd> xdot) const {
  Eigen::Index at = 0;
  for (const auto& in : inputs_) {
    auto u = u_.segment(at, in.channels());
    if (!interval.empty()) in.evaluate_within(t, interval.t0_s, interval.t1_s, u);
    else in.evaluate(t, u);
    at += in.channels();
  }
  xdot.noalias() = A_ * x;
  xdot.noalias() += B_ * u_;
}

std::vector<double> LinearSystem::discontinuities(double t0, double t1) const {
  std::vector<double> all;
  for (const auto& in : inputs_) {
    const auto j = in.jumps(t0, t1);
    all.insert(all.end(), j.begin(), j.end());
  }
  return all;  // the integrator sorts and merges
}

void LinearSystem::jacobian(const IntegrationInterval&, double, const Eigen::Ref<const Eigen::VectorXd>&,
                            Eigen::Ref<Eigen::MatrixXd> J) const {
  J = A_;
}

LinearSystem double_integrator(const Eigen::VectorXd& inertia, SampledSignal force) {
  const Eigen::Index n = inertia.size();
  if (n == 0) throw InputError("double integrator: no channels");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(inertia(i) > 0) || !std::isfinite(inertia(i)))
      throw InputError("double integrator: mass or inertia of channel " + std::to_string(i) +
                       " must be positive and finite (got " + std::to_string(inertia(i)) + ")");
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(2 * n, n);
  B.bottomRows(n) = inertia.cwiseInverse().asDiagonal();
  return LinearSystem(std::move(A), std::move(B), std::move(force));
}

}  // namespace pushpred
