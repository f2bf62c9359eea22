#include "pushpred/calibration/pid_gain_fit.hpp"

#include <ceres/dynamic_numeric_diff_cost_function.h>
#include <ceres/problem.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/nominal_inertia.hpp"
#include "pushpred/observers/estimation_span.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/observers/resimulation.hpp"

namespace pushpred {
namespace {

/// What every error of the fit starts with.
constexpr const char* kFit = "PID gain fit";

/// "PID gain fit: what".
std::string fit_error(const std::string& what) { return std::string(kFit) + ": " + what; }

// Gains enter Ceres as p = ln(g / kPidGainFloor): g = kPidGainFloor maps to p = 0, where Ceres' relative
// numeric-diff step would vanish; useful gains (1e-3 for the rotation of a 0.002 kg m^2 object to 1e3) map to p of
// 7 to 21. The gains are clamped to [kPidGainFloor, kPidGainCeiling] inside the residuals rather than bounded in
// Ceres: beyond the clamp the objective is flat, so the parameter stops there, whereas Ceres' bounds-constrained
// trust region runs a projected line search that re-evaluates the numeric Jacobian at every trial point (ten
// times the cost when a gain that does not matter, such as an unused integral gain, runs into its bound).
double gain_at(double p) { return std::clamp(kPidGainFloor * std::exp(p), kPidGainFloor, kPidGainCeiling); }

std::array<double, 3> gains_of(const PidGains& g, PidFitProblem p) {
  if (p == PidFitProblem::Translation) return {g.kp, g.ki, g.kd};
  return {g.lp, g.li, g.ld};
}

void set_gains(PidGains& g, PidFitProblem p, const std::array<double, 3>& v) {
  if (p == PidFitProblem::Translation) g.kp = v[0], g.ki = v[1], g.kd = v[2];
  else g.lp = v[0], g.li = v[1], g.ld = v[2];
}

/// The gains a residual evaluation of `problem` runs with: the problem's from the log-parameters, the other
/// problem's zero. The channels are decoupled, so the others do not change the fitted channels' residuals; on the
/// CVODE path, at zero gain they are slow and cost nothing (the paper's rotation gains put a pole near -ld / I,
/// about -1.4e4 rad/s, that would set CVODE's steps for the translation problem too).
PidGains evaluation_gains(PidFitProblem problem, const double* p) {
  PidGains g;
  g.kp = g.ki = g.kd = g.lp = g.li = g.ld = 0.0;
  set_gains(g, problem, {gain_at(p[0]), gain_at(p[1]), gain_at(p[2])});
  return g;
}

double span_end(const PidFitPush& p) { return std::min(p.t_end_s, p.push.duration_s()); }

/// Writes the normalised residuals of channels [first, first + count) of one tracking run: per channel the n
/// tracking residuals, then the n - 1 roughness residuals times sqrt(lambda).
void write_residuals(const PidFitPush& p, const PidForceReconstruction::Tracking& tr, PidFitChannels ch,
                     double sqrt_lambda, double* out) {
  const Eigen::Index n = tr.estimate.t_s.size();
  const Eigen::Index first = p.push.index_at(tr.estimate.t_s(0));
  for (int c = ch.first; c < ch.first + ch.count; ++c) {
    const double inv_pose = 1.0 / p.noise.pose(c), w_df = sqrt_lambda / p.noise.force_step(c);
    for (Eigen::Index k = 0; k < n; ++k) *out++ = (p.push.pose(first + k, c) - tr.simulated_pose(k, c)) * inv_pose;
    for (Eigen::Index k = 0; k + 1 < n; ++k) *out++ = (tr.estimate.total(k + 1, c) - tr.estimate.total(k, c)) * w_df;
  }
}

/// One run of the PID reconstruction, exact discretisation or CVODE as the options say.
PidForceReconstruction::Tracking run_pid(const PidForceReconstruction& pid, const PidFitPush& p, bool exact) {
  return exact ? pid.track_exactly(p.push, p.t_start_s, span_end(p)) : pid.track(p.push, p.t_start_s, span_end(p));
}

/// The residuals of one push for one problem, as a function of the three log-gains: one run of the PID
/// reconstruction per evaluation. A failed run (CVODE gives up, or a matrix exponential overflows, at extreme
/// gains) reports failure to Ceres, which then shrinks its step.
class PidTrackingResiduals {
 public:
  PidTrackingResiduals(const PidFitPush& push, PidFitProblem problem, const PidGainFitOptions& options)
      : push_(push),
        problem_(problem),
        channels_(pid_fit_channels(problem)),
        sqrt_lambda_(std::sqrt(options.roughness_weight)),
        reconstruction_(options.reconstruction),
        exact_(options.exact_discretisation),
        samples_(estimation_span(push.push, push.t_start_s, span_end(push), kFit).size()) {}

  int num_residuals() const { return static_cast<int>(channels_.count * (2 * samples_ - 1)); }

  bool operator()(double const* const* parameters, double* residuals) const {
    try {
      const PidForceReconstruction pid(evaluation_gains(problem_, parameters[0]), reconstruction_);
      const PidForceReconstruction::Tracking tr = run_pid(pid, push_, exact_);
      if (tr.estimate.t_s.size() != samples_) return false;
      write_residuals(push_, tr, channels_, sqrt_lambda_, residuals);
      for (int i = 0; i < num_residuals(); ++i)
        if (!std::isfinite(residuals[i])) return false;
      return true;
    } catch (const std::exception&) {
      return false;
    }
  }

 private:
  const PidFitPush& push_;
  PidFitProblem problem_;
  PidFitChannels channels_;
  double sqrt_lambda_;
  PidReconstructionOptions reconstruction_;
  bool exact_;
  Eigen::Index samples_;
};

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

PidFitChannels pid_fit_channels(PidFitProblem problem) {
  return problem == PidFitProblem::Translation ? PidFitChannels{0, 2} : PidFitChannels{2, 1};
}

std::string pid_fit_unsuitable_reason(const SynchronisedPush& push, const RestNoiseOptions& options) {
  options.validate();
  if (push.flags.frozen_force_sensor)
    return "frozen force sensor: its force is not needed for tracking, but d_hat = f_hat - u is meaningless";
  return short_rest_reason(push, options);
}

RestNoise measure_rest_noise(const SynchronisedPush& push, const RestNoiseOptions& options) {
  const std::string unsuitable = pid_fit_unsuitable_reason(push, options);
  if (!unsuitable.empty()) throw InputError(about(push.source, fit_error(unsuitable)));
  const RestNoise noise = noise_over_rest(push, find_rest_at_start(push, options).end);
  for (int c = 0; c < 3; ++c) {
    static const char* const names[3] = {"x", "y", "rotation"};
    if (!(noise.pose(c) > 0) || !(noise.force_step(c) > 0))
      throw InputError(about(push.source, fit_error(std::string("the ") + names[c] +
                                                    " pose or input does not vary at all during the rest at the start "
                                                    "(a frozen stream?), so it has no noise scale")));
  }
  return noise;
}

PidFitPush make_pid_fit_push(SynchronisedPush push, const RestNoiseOptions& options) {
  PidFitPush p;
  p.noise = measure_rest_noise(push, options);
  p.push = std::move(push);
  return p;
}

ceres::Solver::Options default_pid_fit_solver_options() {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.max_num_iterations = 50;
  o.function_tolerance = 1e-7;
  o.parameter_tolerance = 1e-6;
  o.gradient_tolerance = 1e-10;
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  return o;
}

void PidGainFitOptions::validate() const {
  require_positive_finite(roughness_weight, fit_error("the roughness weight lambda"));
  require_positive_finite(numeric_diff_relative_step, fit_error("the numeric-diff relative step"));
  if (numeric_diff_relative_step >= 0.1)
    throw InputError(fit_error("the numeric-diff relative step must be below 0.1"));
  for (const double w : start_bandwidths_rad_s) require_positive_finite(w, fit_error("every start bandwidth [rad/s]"));
  reconstruction.validate();
  std::string error;
  if (!solver.IsValid(&error)) throw InputError(fit_error("invalid Ceres solver options: " + error));
}

std::string pid_fit_problem_name(PidFitProblem problem) {
  return problem == PidFitProblem::Translation ? "translation" : "rotation";
}

PidGainFit fit_pid_gains(const std::vector<PidFitPush>& pushes, const PidGainFitOptions& options,
                         const PidGains& start) {
  options.validate();
  if (pushes.empty()) throw InputError(fit_error("no push to fit on (the set is empty)"));
  start.validate();
  for (const double g : {start.kp, start.ki, start.kd, start.lp, start.li, start.ld})
    if (!(g >= kPidGainFloor && g <= kPidGainCeiling))
      throw InputError(fit_error("start gains must lie in [1e-6, 1e6] (log-parameterised), got " + fmt("%g", g)));
  Eigen::Vector3d mean_inertia = Eigen::Vector3d::Zero();
  for (const PidFitPush& p : pushes) {
    if (p.push.flags.frozen_force_sensor)
      throw InputError(about(p.push.source, fit_error("frozen force sensor: d_hat = f_hat - u is meaningless")));
    for (int c = 0; c < 3; ++c) {
      if (!(p.noise.pose(c) > 0) || !std::isfinite(p.noise.pose(c)) || !(p.noise.force_step(c) > 0) ||
          !std::isfinite(p.noise.force_step(c)))
        throw InputError(about(p.push.source, fit_error("noise scales must be positive and finite")));
    }
    estimation_span(p.push, p.t_start_s, span_end(p), kFit);  // throws for a span without samples
    try {
      mean_inertia += nominal_inertia(p.push.shape, options.reconstruction.mass_kg, options.reconstruction.inertia_kgm2) /
                      static_cast<double>(pushes.size());
    } catch (const InputError& e) {
      throw InputError(about(p.push.source, fit_error(e.what())));
    }
  }

  ceres::NumericDiffOptions diff;
  diff.relative_step_size = options.numeric_diff_relative_step;
  PidGainFit fit;
  fit.pushes = static_cast<long>(pushes.size());
  fit.gains = start;
  for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
    if (!(problem == PidFitProblem::Translation ? options.fit_translation : options.fit_rotation)) continue;
    PidFitSolve& s = problem == PidFitProblem::Translation ? fit.translation : fit.rotation;
    std::vector<PidTrackingResiduals> functors;
    int residuals = 0;
    for (const PidFitPush& push : pushes) {
      functors.emplace_back(push, problem, options);
      residuals += functors.back().num_residuals();
    }

    // Start: the best of the given gains and the triple-pole designs (Ceres is a local method; see the header).
    const double M = mean_inertia(pid_fit_channels(problem).first);
    std::vector<std::pair<std::string, std::array<double, 3>>> starts{{"given gains", gains_of(start, problem)}};
    for (const double w : options.start_bandwidths_rad_s)
      starts.push_back({"triple pole at " + fmt("%g", w) + " rad/s", {3 * M * w * w, M * w * w * w, 3 * M * w}});
    std::vector<double> r(static_cast<std::size_t>(residuals));
    double p[3] = {0, 0, 0};
    s.start_cost = std::numeric_limits<double>::infinity();
    for (const auto& [label, g] : starts) {
      double q[3];
      for (int i = 0; i < 3; ++i) q[i] = std::log(std::clamp(g[i], kPidGainFloor, kPidGainCeiling) / kPidGainFloor);
      const double* qp = q;
      double cost = 0;
      double* out = r.data();
      for (const auto& f : functors) {
        if (!f(&qp, out)) {
          cost = std::numeric_limits<double>::infinity();
          break;
        }
        out += f.num_residuals();
      }
      if (std::isfinite(cost))
        for (const double v : r) cost += 0.5 * v * v;
      if (label == "given gains") s.given_cost = cost;
      if (cost < s.start_cost) {
        s.start_cost = cost;
        s.start = label;
        std::copy(q, q + 3, p);
      }
    }
    if (!std::isfinite(s.start_cost))
      throw SolverError(fit_error("the reconstruction fails (CVODE) at every start of the " +
                                  pid_fit_problem_name(problem) + " gains"));

    ceres::Problem cp;
    for (const auto& f : functors) {
      auto* cost = new ceres::DynamicNumericDiffCostFunction<PidTrackingResiduals, ceres::CENTRAL>(
          new PidTrackingResiduals(f), ceres::TAKE_OWNERSHIP, diff);
      cost->AddParameterBlock(3);
      cost->SetNumResiduals(f.num_residuals());
      cp.AddResidualBlock(cost, nullptr, p);
    }
    ceres::Solver::Summary summary;
    ceres::Solve(options.solver, &cp, &summary);
    if (!summary.IsSolutionUsable())
      throw SolverError(fit_error("Ceres found no usable " + pid_fit_problem_name(problem) + " gains over " +
                                  std::to_string(pushes.size()) + " push(es): " + summary.message));
    set_gains(fit.gains, problem, {gain_at(p[0]), gain_at(p[1]), gain_at(p[2])});
    s.fitted = true;
    s.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
    s.final_cost = summary.final_cost;
    s.termination = std::string(ceres::TerminationTypeToString(summary.termination_type)) + ": " + summary.message;
  }
  return fit;
}

namespace {

/// The disturbance observer's estimate over the push's span, with the reconstruction's nominal inertia, by the
/// same path (exact or CVODE) as the reconstruction.
DisturbanceEstimate observer_estimate(const PidFitPush& p, const PidGainFitOptions& options) {
  QFilterObserverOptions o;
  o.mass_kg = options.reconstruction.mass_kg;
  o.inertia_kgm2 = options.reconstruction.inertia_kgm2;
  o.integrator = options.reconstruction.integrator;
  const QFilterObserver observer(o);
  return options.exact_discretisation ? observer.estimate_exactly(p.push, p.t_start_s, span_end(p))
                                      : observer.estimate(p.push, p.t_start_s, span_end(p));
}

}  // namespace

PidGainQuality assess_pid_gains(const PidFitPush& p, const PidGains& gains, const PidGainFitOptions& options) {
  options.validate();
  const PidForceReconstruction pid(gains, options.reconstruction);
  const PidForceReconstruction::Tracking tr = run_pid(pid, p, options.exact_discretisation);
  const DisturbanceEstimate dob = observer_estimate(p, options);

  const Eigen::Index n = tr.estimate.t_s.size();
  PidGainQuality q;
  q.samples = static_cast<long>(n);
  Eigen::VectorXd r(3 * (2 * n - 1));
  write_residuals(p, tr, {0, 3}, 1.0, r.data());
  for (int c = 0; c < 3; ++c) {
    const Eigen::Index at = c * (2 * n - 1);
    q.tracking_sum(c) = r.segment(at, n).squaredNorm();
    q.roughness_sum(c) = r.segment(at + n, n - 1).squaredNorm();
    q.tracking_rms(c) = std::sqrt(q.tracking_sum(c) / static_cast<double>(n)) * p.noise.pose(c);
    q.roughness_rms(c) = std::sqrt(q.roughness_sum(c) / static_cast<double>(n - 1)) * p.noise.force_step(c);
    const Eigen::VectorXd du = tr.estimate.u.col(c).tail(n - 1) - tr.estimate.u.col(c).head(n - 1);
    q.input_roughness_rms(c) = std::sqrt(du.squaredNorm() / static_cast<double>(n - 1));
  }
  q.dob_rms = rms_difference(tr.estimate.d_hat, dob.d_hat).transpose();
  return q;
}

PidFitForces pid_fit_forces(const PidFitPush& p, const PidGains& fitted, const PidGainFitOptions& options) {
  options.validate();
  const bool exact = options.exact_discretisation;
  PidFitForces forces;
  forces.paper = run_pid(PidForceReconstruction(PidGains{}, options.reconstruction), p, exact).estimate;
  forces.fitted = run_pid(PidForceReconstruction(fitted, options.reconstruction), p, exact).estimate;
  forces.dob = observer_estimate(p, options);
  return forces;
}

PidObjectiveTerms pid_objective_terms(const std::vector<const PidGainQuality*>& qualities, PidFitProblem problem) {
  const PidFitChannels ch = pid_fit_channels(problem);
  PidObjectiveTerms t;
  for (const PidGainQuality* q : qualities) {
    t.tracking += q->tracking_sum.segment(ch.first, ch.count).sum();
    t.roughness += q->roughness_sum.segment(ch.first, ch.count).sum();
  }
  return t;
}

double pid_objective(const std::vector<PidGainQuality>& qualities, PidFitProblem problem, double lambda) {
  std::vector<const PidGainQuality*> qs;
  for (const auto& q : qualities) qs.push_back(&q);
  const PidObjectiveTerms t = pid_objective_terms(qs, problem);
  return 0.5 * (t.tracking + lambda * t.roughness);
}

PidFitStudy run_pid_fit_study(const std::vector<PidFitPush>& pushes, const PidFitStudyOptions& options) {
  PidFitStudy study;
  study.roughness_weight = options.fit.roughness_weight;
  study.joint = fit_pid_gains(pushes, options.fit);  // checks the options and that there are pushes
  for (const PidFitPush& p : pushes) {
    const auto& r = options.fit.reconstruction;
    study.mean_inertia += nominal_inertia(p.push.shape, r.mass_kg, r.inertia_kgm2) / static_cast<double>(pushes.size());
  }
  for (const PidFitPush& p : pushes) {
    PidFitPushResult r;
    r.source = p.push.source;
    r.noise = p.noise;
    r.paper = assess_pid_gains(p, PidGains{}, options.fit);
    r.joint = assess_pid_gains(p, study.joint.gains, options.fit);
    if (options.per_push) {
      try {
        r.own = fit_pid_gains({p}, options.fit);
        r.own_quality = assess_pid_gains(p, r.own->gains, options.fit);
      } catch (const std::exception& e) {
        study.failed.push_back({p.push.source, std::string("per-push fit: ") + e.what()});
        r.own.reset();
        r.own_quality.reset();
      }
    }
    study.pushes.push_back(std::move(r));
  }
  return study;
}

}  // namespace pushpred
