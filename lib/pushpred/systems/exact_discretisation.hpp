#pragma once
// Exact discretisation of x' = A x + B u(t) for an input held between samples, by the matrix exponential
// (Eigen's unsupported MatrixFunctions). Independent of CVODE: the tests use it as the reference for the
// integrator path of every linear system.
//
//   zero-order hold:  exp([[A, B], [0, 0]] dt)            gives  x+ = Phi x + Gamma_from u_k
//   first-order hold: exp([[A, B, 0], [0, 0, I], [0, 0, 0]] dt) gives  x+ = Phi x + Gamma_from u_k + Gamma_to u_{k+1}
#include <Eigen/Core>

#include "pushpred/systems/linear_system.hpp"
#include "pushpred/systems/sampled_signal.hpp"

namespace pushpred {

/// One exact step of length dt: x(t + dt) = phi x(t) + gamma_from u_k + gamma_to u_{k+1} (gamma_to is zero
/// under zero-order hold).
struct DiscreteStep {
  Eigen::MatrixXd phi, gamma_from, gamma_to;
};

/// Throws InputError for non-matching sizes or a step that is not positive and finite.
DiscreteStep discretise_exactly(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double dt_s, Hold hold);

/// States of x' = A x + B u at every sample time of `input` (held as `input` says), from x0 at the first
/// sample, one row per sample. Steps of equal length share one matrix exponential.
Eigen::MatrixXd propagate_exactly(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::VectorXd& x0,
                                  const SampledSignal& input);

/// The same for a LinearSystem whose inputs (each with its own hold) are all sampled at the same times: states at
/// those times from x0 at the first. Throws InputError when the inputs' sample times differ.
Eigen::MatrixXd propagate_exactly(const LinearSystem& system, const Eigen::VectorXd& x0);

}  // namespace pushpred
