#pragma once
// Integrates a ContinuousSystem with SUNDIALS CVODE (6.4). The integrator owns the SUNContext, the state
// vector, the dense matrix and linear solver and the CVODE memory, each in an RAII holder. It stops at every
// discontinuity the system declares and re-initialises CVODE there (CVodeReInit), so no step straddles a
// jump of a held input. CVODE failures become SolverError naming the CVODE flag and the time.
#include <Eigen/Core>
#include <memory>

#include "pushpred/systems/continuous_system.hpp"

namespace pushpred {

struct IntegratorOptions {
  enum class Method { Bdf, Adams };
  Method method = Method::Bdf;
  double relative_tolerance = 1e-8;
  double absolute_tolerance = 1e-10;  ///< same for every state
  long max_steps_between_outputs = 50000;
  double max_step_s = 0;              ///< 0: no limit
  /// Throws InputError when a tolerance is not positive and finite, or a step limit is negative.
  void validate() const;
};

class CvodeIntegrator {
 public:
  /// Keeps a reference to `system`, which must outlive the integrator. Throws InputError for bad options or a
  /// system without states, SolverError when CVODE cannot be set up.
  explicit CvodeIntegrator(const ContinuousSystem& system, IntegratorOptions options = {});
  ~CvodeIntegrator();
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  /// States at `output_times_s` (non-decreasing, all >= t0), one row per output time, starting from x0 at t0.
  /// Throws InputError for a wrong-sized or non-finite x0 or bad output times, SolverError when CVODE fails.
  Eigen::MatrixXd solve(double t0_s, const Eigen::VectorXd& x0, const Eigen::VectorXd& output_times_s);

  /// Statistics of the last solve (steps taken, right-hand-side calls, re-initialisations at jumps).
  struct Stats {
    long steps = 0, rhs_evaluations = 0, reinitialisations = 0;
  };
  Stats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pushpred
