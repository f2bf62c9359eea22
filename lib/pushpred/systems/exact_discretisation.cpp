#include "pushpred/systems/exact_discretisation.hpp"

#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <vector>
#include <string>

#include "pushpred/core/error.hpp"

namespace pushpred {

DiscreteStep discretise_exactly(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double dt, Hold hold) {
  const Eigen::Index n = A.rows(), m = B.cols();
  if (n == 0 || A.cols() != n || B.rows() != n) throw InputError("exact discretisation: A and B do not match");
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("exact discretisation: step must be positive and finite");
  DiscreteStep step;
  if (hold == Hold::Zero) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + m, n + m);
    M.topLeftCorner(n, n) = A * dt;
    M.topRightCorner(n, m) = B * dt;
    const Eigen::MatrixXd E = M.exp();
    step.phi = E.topLeftCorner(n, n);
    step.gamma_from = E.topRightCorner(n, m);
    step.gamma_to = Eigen::MatrixXd::Zero(n, m);
  } else {
    // Augmented state [x; u; w] with u' = w = (u_{k+1} - u_k) / dt and w' = 0 reproduces the linear ramp.
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n + 2 * m, n + 2 * m);
    M.topLeftCorner(n, n) = A * dt;
    M.block(0, n, n, m) = B * dt;
    M.block(n, n + m, m, m) = Eigen::MatrixXd::Identity(m, m);  // (u' = w) * dt with w scaled by dt
    const Eigen::MatrixXd E = M.exp();
    step.phi = E.topLeftCorner(n, n);
    const Eigen::MatrixXd G1 = E.block(0, n, n, m);      // response to u_k
    const Eigen::MatrixXd G2 = E.block(0, n + m, n, m);  // response to w dt = u_{k+1} - u_k
    step.gamma_from = G1 - G2;
    step.gamma_to = G2;
  }
  return step;
}

Eigen::MatrixXd propagate_exactly(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::VectorXd& x0,
                                  const SampledSignal& input) {
  const Eigen::Index n = A.rows(), samples = input.samples();
  if (x0.size() != n) throw InputError("exact propagation: initial state does not match A");
  if (B.cols() != input.channels()) throw InputError("exact propagation: B does not match the input's channels");
  Eigen::MatrixXd X(samples, n);
  if (samples == 0) return X;
  X.row(0) = x0.transpose();
  const Eigen::VectorXd& t = input.times();
  const Eigen::MatrixXd& u = input.values();
  DiscreteStep step;
  double step_dt = -1;
  Eigen::VectorXd x = x0;
  for (Eigen::Index k = 0; k + 1 < samples; ++k) {
    const double dt = t(k + 1) - t(k);
    if (std::abs(dt - step_dt) > 1e-12 * dt) {
      step = discretise_exactly(A, B, dt, input.hold());
      step_dt = dt;
    }
    x = step.phi * x + step.gamma_from * u.row(k).transpose() + step.gamma_to * u.row(k + 1).transpose();
    X.row(k + 1) = x.transpose();
  }
  return X;
}

Eigen::MatrixXd propagate_exactly(const LinearSystem& system, const Eigen::VectorXd& x0) {
  const auto& inputs = system.inputs();
  const Eigen::MatrixXd& A = system.A();
  const Eigen::Index n = A.rows();
  if (x0.size() != n) throw InputError("exact propagation: initial state does not match A");
  const Eigen::VectorXd& t = inputs.front().times();
  for (const auto& in : inputs)
    if (in.samples() != t.size() || (in.times() - t).cwiseAbs().maxCoeff() > 1e-12 * std::max(1.0, t.cwiseAbs().maxCoeff()))
      throw InputError("exact propagation: the inputs are not sampled at the same times");
  // By superposition, one discretisation per input signal with its own hold; the same phi for all.
  struct Block {
    Eigen::Index column;
    const SampledSignal* signal;
    DiscreteStep step;
  };
  std::vector<Block> blocks;
  Eigen::Index column = 0;
  for (const auto& in : inputs) {
    blocks.push_back({column, &in, {}});
    column += in.channels();
  }
  Eigen::MatrixXd X(t.size(), n);
  X.row(0) = x0.transpose();
  Eigen::VectorXd x = x0, next(n);
  double step_dt = -1;
  for (Eigen::Index k = 0; k + 1 < t.size(); ++k) {
    const double dt = t(k + 1) - t(k);
    if (std::abs(dt - step_dt) > 1e-12 * dt) {
      for (auto& b : blocks)
        b.step = discretise_exactly(A, system.B().middleCols(b.column, b.signal->channels()), dt, b.signal->hold());
      step_dt = dt;
    }
    next = blocks.front().step.phi * x;
    for (const auto& b : blocks)
      next += b.step.gamma_from * b.signal->values().row(k).transpose() +
              b.step.gamma_to * b.signal->values().row(k + 1).transpose();
    x = next;
    X.row(k + 1) = x.transpose();
  }
  return X;
}

}  // namespace pushpred
