#include "pushpred/systems/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

std::string format_time(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", t);
  return buf;
}

std::string flag_name(int flag) {
  char* name = CVodeGetReturnFlagName(flag);  // allocated by CVODE, ours to free
  std::string out = name ? name : ("flag " + std::to_string(flag));
  std::free(name);
  return out;
}

// RAII holders for the SUNDIALS handles.
struct ContextDeleter {
  void operator()(SUNContext ctx) const { SUNContext_Free(&ctx); }
};
struct VectorDeleter {
  void operator()(_generic_N_Vector* v) const { N_VDestroy(v); }
};
struct MatrixDeleter {
  void operator()(_generic_SUNMatrix* m) const { SUNMatDestroy(m); }
};
struct LinearSolverDeleter {
  void operator()(_generic_SUNLinearSolver* s) const { SUNLinSolFree(s); }
};
struct NonlinearSolverDeleter {
  void operator()(_generic_SUNNonlinearSolver* s) const { SUNNonlinSolFree(s); }
};
struct CvodeDeleter {
  void operator()(void* mem) const { CVodeFree(&mem); }
};

}  // namespace

void IntegratorOptions::validate() const {
  require_positive_finite(relative_tolerance, "integrator: relative tolerance");
  require_positive_finite(absolute_tolerance, "integrator: absolute tolerance");
  if (max_steps_between_outputs <= 0)
    throw InputError("integrator: maximum number of steps between outputs must be positive");
  require_not_negative_finite(max_step_s, "integrator: maximum step [s] (0: no limit)");
}

IntegratorOptions::Method IntegratorOptions::resolved_for(const ContinuousSystem& system) const {
  if (method != Method::Automatic) return method;
  return system.stiff() ? Method::Bdf : Method::Adams;
}

struct CvodeIntegrator::Impl {
  const ContinuousSystem* system = nullptr;  // the system of the solve under way (or the bound one)
  IntegrationInterval interval;              // the jump-free interval being integrated, passed to the system
  IntegratorOptions options;                 // the bound system's
  IntegratorOptions::Method method;          // Bdf or Adams, fixed when CVODE's memory is created
  int n = 0;
  std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter> context;
  std::unique_ptr<_generic_N_Vector, VectorDeleter> y;
  std::unique_ptr<_generic_SUNMatrix, MatrixDeleter> matrix;                        // BDF only
  std::unique_ptr<_generic_SUNLinearSolver, LinearSolverDeleter> solver;            // BDF only
  std::unique_ptr<_generic_SUNNonlinearSolver, NonlinearSolverDeleter> fixed_point; // Adams only
  std::unique_ptr<void, CvodeDeleter> memory;  // last: freed first, before the solvers it uses
  std::exception_ptr callback_error;  // an exception thrown inside a callback, rethrown after CVODE returns
  std::string last_message;           // CVODE's own text for its last error, added to SolverError
  Stats stats;

  Impl(int size, IntegratorOptions::Method m) : method(m), n(size) {}

  void check(int flag, const char* function, double t) const {
    if (flag < 0)
      throw SolverError(std::string("CVODE ") + function + " failed with " + flag_name(flag) + " at t = " +
                        format_time(t) + " s" + (last_message.empty() ? "" : " (" + last_message + ")"));
  }

  // CVODE would print to stderr; errors become exceptions instead and warnings (e.g. "t + h = t") are dropped.
  static void error_handler(int code, const char* /*module*/, const char* /*function*/, char* message, void* data) {
    if (code < 0 && message) static_cast<Impl*>(data)->last_message = message;
  }

  static int rhs(realtype t, N_Vector y, N_Vector ydot, void* user_data) {
    auto* self = static_cast<Impl*>(user_data);
    try {
      const Eigen::Map<const Eigen::VectorXd> x(N_VGetArrayPointer(y), self->n);
      Eigen::Map<Eigen::VectorXd> xdot(N_VGetArrayPointer(ydot), self->n);
      self->system->derivative(self->interval, t, x, xdot);
      return xdot.allFinite() ? 0 : 1;  // recoverable: CVODE retries with a smaller step
    } catch (...) {
      self->callback_error = std::current_exception();
      return -1;
    }
  }

  static int jacobian(realtype t, N_Vector y, N_Vector /*fy*/, SUNMatrix J, void* user_data, N_Vector, N_Vector,
                      N_Vector) {
    auto* self = static_cast<Impl*>(user_data);
    try {
      const Eigen::Map<const Eigen::VectorXd> x(N_VGetArrayPointer(y), self->n);
      // SUNDIALS dense matrices are column-major with leading dimension n, as Eigen's default.
      Eigen::Map<Eigen::MatrixXd> jac(SUNDenseMatrix_Data(J), self->n, self->n);
      self->system->jacobian(self->interval, t, x, jac);
      return 0;
    } catch (...) {
      self->callback_error = std::current_exception();
      return -1;
    }
  }

  void add_counters() {
    long steps = 0, rhs_evals = 0;
    CVodeGetNumSteps(memory.get(), &steps);
    CVodeGetNumRhsEvals(memory.get(), &rhs_evals);
    stats.steps += steps;
    stats.rhs_evaluations += rhs_evals;
  }

  /// CVode towards tout; returns the time reached. Rethrows a callback's exception, converts failures.
  double advance(double tout) {
    realtype reached = 0;
    const int flag = CVode(memory.get(), tout, y.get(), &reached, CV_NORMAL);
    if (callback_error) {
      auto e = callback_error;
      callback_error = nullptr;
      std::rethrow_exception(e);
    }
    if (flag < 0) {
      realtype t_now = reached;
      CVodeGetCurrentTime(memory.get(), &t_now);
      check(flag, "CVode", t_now);
    }
    return reached;
  }
};

CvodeIntegrator::CvodeIntegrator(const ContinuousSystem& system, IntegratorOptions options)
    : CvodeIntegrator((options.validate(), system.state_size()), options.resolved_for(system)) {
  impl_->system = &system;
  impl_->options = options;
}

CvodeIntegrator::CvodeIntegrator(int state_size, IntegratorOptions::Method method)
    : impl_(std::make_unique<Impl>(state_size, method)) {
  Impl& m = *impl_;
  if (m.n <= 0) throw InputError("integrator: the system has no states");
  if (method == IntegratorOptions::Method::Automatic)
    throw InputError("integrator: an unbound integrator needs Bdf or Adams, not Automatic");
  const bool bdf = method == IntegratorOptions::Method::Bdf;

  SUNContext ctx = nullptr;
  if (SUNContext_Create(nullptr, &ctx) != 0 || !ctx) throw SolverError("SUNDIALS: cannot create a context");
  m.context.reset(ctx);
  m.y.reset(N_VNew_Serial(m.n, ctx));
  if (!m.y) throw SolverError("SUNDIALS: cannot allocate the state vector");
  N_VConst(0.0, m.y.get());
  m.memory.reset(CVodeCreate(bdf ? CV_BDF : CV_ADAMS, ctx));
  if (!m.memory) throw SolverError("CVODE: cannot create the integrator memory");

  void* mem = m.memory.get();
  m.check(CVodeSetErrHandlerFn(mem, &Impl::error_handler, impl_.get()), "CVodeSetErrHandlerFn", 0.0);
  m.check(CVodeInit(mem, &Impl::rhs, 0.0, m.y.get()), "CVodeInit", 0.0);
  m.check(CVodeSetUserData(mem, impl_.get()), "CVodeSetUserData", 0.0);
  if (bdf) {
    // Stiff: Newton iteration, whose linear systems (n <= 12 here) the dense direct solver handles best.
    m.matrix.reset(SUNDenseMatrix(m.n, m.n, ctx));
    if (!m.matrix) throw SolverError("SUNDIALS: cannot allocate the dense matrix");
    m.solver.reset(SUNLinSol_Dense(m.y.get(), m.matrix.get(), ctx));
    if (!m.solver) throw SolverError("SUNDIALS: cannot create the dense linear solver");
    m.check(CVodeSetLinearSolver(mem, m.solver.get(), m.matrix.get()), "CVodeSetLinearSolver", 0.0);
  } else {
    // Not stiff: fixed-point iteration converges in a step or two without a Jacobian or a linear solve, which
    // would cost more than the right-hand side of these small systems. No Anderson acceleration (m = 0).
    m.fixed_point.reset(SUNNonlinSol_FixedPoint(m.y.get(), 0, ctx));
    if (!m.fixed_point) throw SolverError("SUNDIALS: cannot create the fixed-point solver");
    m.check(CVodeSetNonlinearSolver(mem, m.fixed_point.get()), "CVodeSetNonlinearSolver", 0.0);
  }
}

CvodeIntegrator::~CvodeIntegrator() = default;

void check_output_times(const std::string& who, double t0, const Eigen::VectorXd& out_t) {
  if (!std::isfinite(t0)) throw InputError(who + ": start time is not finite");
  for (Eigen::Index k = 0; k < out_t.size(); ++k) {
    if (!std::isfinite(out_t(k))) throw InputError(who + ": output time " + std::to_string(k) + " is not finite");
    if (out_t(k) < t0)
      throw InputError(who + ": output time " + format_time(out_t(k)) + " s precedes the start time " +
                       format_time(t0) + " s");
    if (k > 0 && out_t(k) < out_t(k - 1)) throw InputError(who + ": output times must be non-decreasing");
  }
}

CvodeIntegrator::Stats CvodeIntegrator::stats() const { return impl_->stats; }

Eigen::MatrixXd CvodeIntegrator::solve(double t0, const Eigen::VectorXd& x0, const Eigen::VectorXd& out_t) {
  if (!impl_->system) throw InputError("integrator: no system bound; use solve(system, options, ...)");
  return solve(*impl_->system, impl_->options, t0, x0, out_t);
}

Eigen::MatrixXd CvodeIntegrator::solve(const ContinuousSystem& system, const IntegratorOptions& options, double t0,
                                       const Eigen::VectorXd& x0, const Eigen::VectorXd& out_t) {
  Impl& m = *impl_;
  options.validate();
  if (system.state_size() != m.n)
    throw InputError("integrator: made for " + std::to_string(m.n) + " states, the system has " +
                     std::to_string(system.state_size()));
  if (options.resolved_for(system) != m.method)
    throw InputError("integrator: the system or options ask for another method than this integrator's");
  m.system = &system;
  if (x0.size() != m.n)
    throw InputError("integrator: initial state has " + std::to_string(x0.size()) + " entries, the system " +
                     std::to_string(m.n));
  if (!x0.allFinite()) throw InputError("integrator: initial state holds NaN or infinity");
  check_output_times("integrator", t0, out_t);
  m.stats = {};
  m.last_message.clear();
  // Options may differ from the previous solve's: CVODE keeps them across CVodeReInit, so they are set each time.
  void* mem = m.memory.get();
  m.check(CVodeSStolerances(mem, options.relative_tolerance, options.absolute_tolerance), "CVodeSStolerances", t0);
  m.check(CVodeSetMaxNumSteps(mem, options.max_steps_between_outputs), "CVodeSetMaxNumSteps", t0);
  m.check(CVodeSetMaxStep(mem, options.max_step_s), "CVodeSetMaxStep", t0);  // 0: no limit
  if (m.solver)
    m.check(CVodeSetJacFn(mem, system.has_jacobian() ? &Impl::jacobian : nullptr), "CVodeSetJacFn", t0);
  Eigen::MatrixXd out(out_t.size(), m.n);
  if (out_t.size() == 0) return out;
  const double t_end = out_t(out_t.size() - 1);

  // Interval ends: the start, every declared jump strictly inside, the end. Jumps closer together than
  // CVODE can resolve are merged.
  std::vector<double> ends{t0};
  std::vector<double> jumps = system.discontinuities(t0, t_end);
  std::sort(jumps.begin(), jumps.end());
  const auto too_close = [](double a, double b) {
    return b - a <= 64 * std::numeric_limits<double>::epsilon() * std::max({1.0, std::abs(a), std::abs(b)});
  };
  for (double j : jumps)
    if (j > t0 && j < t_end && !too_close(ends.back(), j)) ends.push_back(j);
  if (t_end > t0 && !too_close(t0, t_end)) {
    if (ends.size() > 1 && too_close(ends.back(), t_end)) ends.back() = t_end;
    else ends.push_back(t_end);
  }

  Eigen::Map<Eigen::VectorXd> y(N_VGetArrayPointer(m.y.get()), m.n);
  y = x0;
  Eigen::Index k = 0;
  while (k < out_t.size() && (out_t(k) <= t0 || too_close(t0, out_t(k)))) out.row(k++) = y.transpose();
  for (std::size_t i = 0; i + 1 < ends.size(); ++i) {
    const double a = ends[i], b = ends[i + 1];
    if (i > 0) {
      m.add_counters();
      ++m.stats.reinitialisations;
    }
    m.interval = IntegrationInterval{a, b};
    m.check(CVodeReInit(mem, a, m.y.get()), "CVodeReInit", a);
    m.check(CVodeSetStopTime(mem, b), "CVodeSetStopTime", a);
    double t = a;
    const bool last = i + 2 == ends.size();
    while (k < out_t.size() && (out_t(k) < b || (last && out_t(k) <= b))) {
      // An output a rounding error away from where the integration stands (a jump it has just stopped at) is
      // taken there; one a rounding error short of the interval end is reached exactly at the end. CVODE
      // cannot take a step shorter than its rounding (CV_TOO_CLOSE).
      if (out_t(k) > t && !too_close(t, out_t(k))) t = m.advance(too_close(out_t(k), b) ? b : out_t(k));
      out.row(k++) = y.transpose();
    }
    if (t < b) t = m.advance(b);
  }
  if (ends.size() > 1) m.add_counters();
  // Outputs that coincide with the end of the last interval.
  while (k < out_t.size()) out.row(k++) = y.transpose();
  return out;
}

Eigen::MatrixXd integrate(const ContinuousSystem& system, const IntegratorOptions& options, double t0,
                          const Eigen::VectorXd& x0, const Eigen::VectorXd& output_times, CvodeIntegrator::Stats* stats) {
  options.validate();
  struct Entry {
    int size;
    IntegratorOptions::Method method;
    std::unique_ptr<CvodeIntegrator> integrator;
  };
  // One integrator per state size and method and thread: each solve re-initialises it, none is made per phase.
  thread_local std::vector<Entry> pool;
  const int n = system.state_size();
  const IntegratorOptions::Method method = options.resolved_for(system);
  CvodeIntegrator* integrator = nullptr;
  for (auto& e : pool)
    if (e.size == n && e.method == method) integrator = e.integrator.get();
  if (!integrator) {
    pool.push_back({n, method, std::make_unique<CvodeIntegrator>(n, method)});
    integrator = pool.back().integrator.get();
  }
  Eigen::MatrixXd out = integrator->solve(system, options, t0, x0, output_times);
  if (stats) *stats = integrator->stats();
  return out;
}

}  // namespace pushpred
