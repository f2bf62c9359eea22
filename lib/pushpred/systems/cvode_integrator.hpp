#pragma once
// Integrates a ContinuousSystem with SUNDIALS CVODE (6.4). The integrator owns the SUNContext, the state
// vector, the dense matrix and linear solver, the fixed-point solver and the CVODE memory, each in an RAII holder,
// and keeps them from one solve to the next: a new solve, of the same system or of another of the same size,
// only re-initialises CVODE (CVodeReInit), so nothing is allocated per phase or per push (integrate() keeps one
// integrator per thread and configuration). It stops at every discontinuity the system declares and
// re-initialises there, so no step straddles a jump of a held input; a kink (a first-order-held input) is not a
// jump and the integration goes on across it. The interval being integrated is the integrator's state, passed to
// the system with each right-hand side (IntegrationInterval, continuous_system.hpp); the system keeps none. CVODE failures become SolverError naming the CVODE flag and the time.
//
// Method: Adams with fixed-point iteration for a system that says it is not stiff (no Jacobian, no linear
// algebra: a step costs a few right-hand sides), BDF with Newton iteration and the dense direct solver for a stiff
// one, with the system's analytic Jacobian where it has one (ContinuousSystem::stiff says which systems are which).
#include <Eigen/Core>
#include <memory>
#include <string>

#include "pushpred/systems/continuous_system.hpp"

namespace pushpred {

struct IntegratorOptions {
  /// Automatic: Adams or BDF as the system says (ContinuousSystem::stiff); the others force one.
  enum class Method { Automatic, Bdf, Adams };
  Method method = Method::Automatic;
  double relative_tolerance = 1e-8;
  double absolute_tolerance = 1e-10;  ///< same for every state
  long max_steps_between_outputs = 50000;
  double max_step_s = 0;              ///< 0: no limit
  /// Throws InputError when a tolerance is not positive and finite, or a step limit is negative.
  void validate() const;
  /// Bdf or Adams: the method forced, or the one `system` asks for.
  Method resolved_for(const ContinuousSystem& system) const;
};

class CvodeIntegrator {
 public:
  /// Keeps a reference to `system`, which must outlive the integrator. Throws InputError for bad options or a
  /// system without states, SolverError when CVODE cannot be set up.
  explicit CvodeIntegrator(const ContinuousSystem& system, IntegratorOptions options = {});
  /// An integrator for any system of `state_size` states by `method` (Bdf or Adams), for solve(system, ...).
  CvodeIntegrator(int state_size, IntegratorOptions::Method method);
  ~CvodeIntegrator();
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  /// States at `output_times_s` (non-decreasing, all >= t0), one row per output time, starting from x0 at t0.
  /// Throws InputError for a wrong-sized or non-finite x0 or bad output times, SolverError when CVODE fails.
  Eigen::MatrixXd solve(double t0_s, const Eigen::VectorXd& x0, const Eigen::VectorXd& output_times_s);
  /// The same for another system of the same size, under `options` (whose method must resolve to this
  /// integrator's); the system need only live for the call.
  Eigen::MatrixXd solve(const ContinuousSystem& system, const IntegratorOptions& options, double t0_s,
                        const Eigen::VectorXd& x0, const Eigen::VectorXd& output_times_s);

  /// Statistics of the last solve (steps taken, right-hand-side calls, re-initialisations at jumps).
  struct Stats {
    long steps = 0, rhs_evaluations = 0, reinitialisations = 0;
  };
  Stats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Throws InputError, its message starting with `who`, unless every output time is finite, at or after `t0_s`
/// (itself finite) and no earlier than the one before: what a solve from t0 to those times needs, by any path.
void check_output_times(const std::string& who, double t0_s, const Eigen::VectorXd& output_times_s);

/// Solves `system` from x0 at t0 to `output_times_s` as CvodeIntegrator::solve does, on the calling thread's
/// integrator for the system's size and method (made on first use, re-used after). `stats`, when given, receives
/// the solve's statistics.
Eigen::MatrixXd integrate(const ContinuousSystem& system, const IntegratorOptions& options, double t0_s,
                          const Eigen::VectorXd& x0, const Eigen::VectorXd& output_times_s,
                          CvodeIntegrator::Stats* stats = nullptr);

}  // namespace pushpred
