#include "pushpred/systems/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>
#include <type_traits>

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
struct CvodeDeleter {
  void operator()(void* mem) const { CVodeFree(&mem); }
};

}  // namespace

void IntegratorOptions::validate() const {
  if (!(relative_tolerance > 0) || !std::isfinite(relative_tolerance))
    throw InputError("integrator: relative tolerance must be positive and finite (got " +
                     format_time(relative_tolerance) + ")");
  if (!(absolute_tolerance > 0) || !std::isfinite(absolute_tolerance))
    throw InputError("integrator: absolute tolerance must be positive and finite (got " +
                     format_time(absolute_tolerance) + ")");
  if (max_steps_between_outputs <= 0)
    throw InputError("integrator: maximum number of steps between outputs must be positive");
  if (!(max_step_s >= 0) || !std::isfinite(max_step_s))
    throw InputError("integrator: maximum step must be zero (no limit) or positive");
}

struct CvodeIntegrator::Impl {
  const ContinuousSystem& system;
  IntegratorOptions options;
  int n = 0;
  std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter> context;
  std::unique_ptr<_generic_N_Vector, VectorDeleter> y;
  std::unique_ptr<_generic_SUNMatrix, MatrixDeleter> matrix;
  std::unique_ptr<_generic_SUNLinearSolver, LinearSolverDeleter> solver;
  std::unique_ptr<void, CvodeDeleter> memory;
  std::exception_ptr callback_error;  // an exception thrown inside a callback, rethrown after CVODE returns
  std::string last_message;           // CVODE's own text for its last error, added to SolverError
  Stats stats;

  Impl(const ContinuousSystem& s, IntegratorOptions o) : system(s), options(o) {}

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
      self->system.derivative(t, x, xdot);
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
      self->system.jacobian(t, x, jac);
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
    : impl_(std::make_unique<Impl>(system, options)) {
  options.validate();
  Impl& m = *impl_;
  m.n = system.state_size();
  if (m.n <= 0) throw InputError("integrator: the system has no states");

  SUNContext ctx = nullptr;
  if (SUNContext_Create(nullptr, &ctx) != 0 || !ctx) throw SolverError("SUNDIALS: cannot create a context");
  m.context.reset(ctx);
  m.y.reset(N_VNew_Serial(m.n, ctx));
  m.matrix.reset(SUNDenseMatrix(m.n, m.n, ctx));
  if (!m.y || !m.matrix) throw SolverError("SUNDIALS: cannot allocate the state vector or matrix");
  N_VConst(0.0, m.y.get());
  m.solver.reset(SUNLinSol_Dense(m.y.get(), m.matrix.get(), ctx));
  if (!m.solver) throw SolverError("SUNDIALS: cannot create the dense linear solver");
  m.memory.reset(CVodeCreate(options.method == IntegratorOptions::Method::Bdf ? CV_BDF : CV_ADAMS, ctx));
  if (!m.memory) throw SolverError("CVODE: cannot create the integrator memory");

  void* mem = m.memory.get();
  m.check(CVodeSetErrHandlerFn(mem, &Impl::error_handler, impl_.get()), "CVodeSetErrHandlerFn", 0.0);
  m.check(CVodeInit(mem, &Impl::rhs, 0.0, m.y.get()), "CVodeInit", 0.0);
  m.check(CVodeSetUserData(mem, impl_.get()), "CVodeSetUserData", 0.0);
  m.check(CVodeSStolerances(mem, options.relative_tolerance, options.absolute_tolerance), "CVodeSStolerances", 0.0);
  m.check(CVodeSetLinearSolver(mem, m.solver.get(), m.matrix.get()), "CVodeSetLinearSolver", 0.0);
  if (system.has_jacobian()) m.check(CVodeSetJacFn(mem, &Impl::jacobian), "CVodeSetJacFn", 0.0);
  m.check(CVodeSetMaxNumSteps(mem, options.max_steps_between_outputs), "CVodeSetMaxNumSteps", 0.0);
  if (options.max_step_s > 0) m.check(CVodeSetMaxStep(mem, options.max_step_s), "CVodeSetMaxStep", 0.0);
}

CvodeIntegrator::~CvodeIntegrator() = default;

CvodeIntegrator::Stats CvodeIntegrator::stats() const { return impl_->stats; }

Eigen::MatrixXd CvodeIntegrator::solve(double t0, const Eigen::VectorXd& x0, const Eigen::VectorXd& out_t) {
  Impl& m = *impl_;
  if (x0.size() != m.n)
    throw InputError("integrator: initial state has " + std::to_string(x0.size()) + " entries, the system " +
                     std::to_string(m.n));
  if (!x0.allFinite()) throw InputError("integrator: initial state holds NaN or infinity");
  if (!std::isfinite(t0)) throw InputError("integrator: start time is not finite");
  for (Eigen::Index k = 0; k < out_t.size(); ++k) {
    if (!std::isfinite(out_t(k))) throw InputError("integrator: output time " + std::to_string(k) + " is not finite");
    if (out_t(k) < t0)
      throw InputError("integrator: output time " + format_time(out_t(k)) + " s precedes the start time " +
                       format_time(t0) + " s");
    if (k > 0 && out_t(k) < out_t(k - 1)) throw InputError("integrator: output times must be non-decreasing");
  }
  m.stats = {};
  m.last_message.clear();
  Eigen::MatrixXd out(out_t.size(), m.n);
  if (out_t.size() == 0) return out;
  const double t_end = out_t(out_t.size() - 1);

  // Interval ends: the start, every declared jump strictly inside, the end. Jumps closer together than
  // CVODE can resolve are merged.
  std::vector<double> ends{t0};
  std::vector<double> jumps = m.system.discontinuities(t0, t_end);
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
  void* mem = m.memory.get();
  Eigen::Index k = 0;
  while (k < out_t.size() && (out_t(k) <= t0 || too_close(t0, out_t(k)))) out.row(k++) = y.transpose();
  for (std::size_t i = 0; i + 1 < ends.size(); ++i) {
    const double a = ends[i], b = ends[i + 1];
    if (i > 0) {
      m.add_counters();
      ++m.stats.reinitialisations;
    }
    m.system.enter_interval(a, b);
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

}  // namespace pushpred
