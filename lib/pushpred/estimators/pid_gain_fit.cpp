#include "pushpred/estimators/pid_gain_fit.hpp"

#include <ceres/dynamic_numeric_diff_cost_function.h>
#include <ceres/problem.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/core/version.hpp"
#include "pushpred/observers/estimation_span.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/observers/resimulation.hpp"

namespace pushpred {
namespace {

// Gains enter Ceres as p = ln(g / kGainFloor): g = kGainFloor maps to p = 0, where Ceres' relative
// numeric-diff step would vanish; useful gains (1e-3 for the rotation of a 0.002 kg m^2 object to 1e3) map to p of
// 7 to 21. The gains are clamped to [kGainFloor, kGainCeiling] inside the residuals rather than bounded in Ceres:
// beyond the clamp the objective is flat, so the parameter stops there, whereas Ceres' bounds-constrained
// trust region runs a projected line search that re-evaluates the numeric Jacobian at every trial point (ten
// times the cost when a gain that does not matter, such as an unused integral gain, runs into its bound).
constexpr double kGainFloor = 1e-6, kGainCeiling = 1e6;

double gain_at(double p) { return std::clamp(kGainFloor * std::exp(p), kGainFloor, kGainCeiling); }
constexpr double kRadToDeg = 180.0 / M_PI;

struct ProblemChannels {
  int first, count;
};
ProblemChannels channels_of(PidFitProblem p) {
  return p == PidFitProblem::Translation ? ProblemChannels{0, 2} : ProblemChannels{2, 1};
}

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
void write_residuals(const PidFitPush& p, const PidForceReconstruction::Tracking& tr, ProblemChannels ch,
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
        channels_(channels_of(problem)),
        sqrt_lambda_(std::sqrt(options.roughness_weight)),
        reconstruction_(options.reconstruction),
        exact_(options.exact_discretisation),
        samples_(estimation_span(push.push, push.t_start_s, span_end(push), "PID gain fit").size()) {}

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
  ProblemChannels channels_;
  double sqrt_lambda_;
  PidReconstructionOptions reconstruction_;
  bool exact_;
  Eigen::Index samples_;
};

/// Standard deviation of `v` about its least-squares line in `t`.
double std_about_line(const Eigen::VectorXd& t, const Eigen::VectorXd& v) {
  const Eigen::Index n = v.size();
  const Eigen::VectorXd tau = t.array() - t.mean();
  const double slope = tau.dot(v) / tau.squaredNorm();
  const Eigen::VectorXd r = (v.array() - v.mean()).matrix() - slope * tau;
  return std::sqrt(r.squaredNorm() / static_cast<double>(n - 2));
}

std::string short_name(const std::string& source) {
  const std::string name = std::filesystem::path(source).filename().string();
  return name.empty() ? source : name;
}

nlohmann::json gains_json(const PidGains& g) {
  return {{"kp_N_per_m", g.kp},          {"ki_N_per_m_s", g.ki},          {"kd_N_s_per_m", g.kd},
          {"lp_N_m_per_rad", g.lp},      {"li_N_m_per_rad_s", g.li},      {"ld_N_m_s_per_rad", g.ld}};
}

nlohmann::json solve_json(const PidFitSolve& s) {
  if (!s.fitted) return {{"fitted", false}};
  return {{"fitted", true},         {"cost_at_given_gains", s.given_cost}, {"start", s.start},
          {"start_cost", s.start_cost}, {"final_cost", s.final_cost},       {"iterations", s.iterations},
          {"termination", s.termination}};
}

nlohmann::json fit_json(const PidGainFit& f) {
  return {{"gains", gains_json(f.gains)},
          {"pushes", f.pushes},
          {"translation", solve_json(f.translation)},
          {"rotation", solve_json(f.rotation)}};
}

/// Per channel x, y, rotation: values in report units (mm, mm, deg or N, N, N mm).
nlohmann::json channels_json(const Eigen::Vector3d& v, double translation_scale, double rotation_scale) {
  return {{"x", v(0) * translation_scale}, {"y", v(1) * translation_scale}, {"rotation", v(2) * rotation_scale}};
}

nlohmann::json quality_json(const PidGainQuality& q) {
  const double n = static_cast<double>(q.samples), steps = static_cast<double>(std::max<long>(q.samples - 1, 1));
  return {{"samples", q.samples},
          {"tracking_mean_square", channels_json(q.tracking_sum / n, 1, 1)},
          {"roughness_mean_square", channels_json(q.roughness_sum / steps, 1, 1)},
          {"tracking_rms_mm_deg", channels_json(q.tracking_rms, 1e3, kRadToDeg)},
          {"roughness_rms_N_Nmm", channels_json(q.roughness_rms, 1, 1e3)},
          {"dob_difference_rms_N_Nmm", channels_json(q.dob_rms, 1, 1e3)},
          {"measured_input_roughness_rms_N_Nmm", channels_json(q.input_roughness_rms, 1, 1e3)}};
}

/// The objective's two sums for `problem` over `qualities`.
struct ObjectiveTerms {
  double tracking = 0, roughness = 0;
};
ObjectiveTerms objective_terms(const std::vector<const PidGainQuality*>& qualities, PidFitProblem problem) {
  const ProblemChannels ch = channels_of(problem);
  ObjectiveTerms t;
  for (const PidGainQuality* q : qualities) {
    t.tracking += q->tracking_sum.segment(ch.first, ch.count).sum();
    t.roughness += q->roughness_sum.segment(ch.first, ch.count).sum();
  }
  return t;
}

Eigen::Vector3d mean_of(const std::vector<const PidGainQuality*>& qs, Eigen::Vector3d PidGainQuality::*field) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (const PidGainQuality* q : qs) s += q->*field;
  return qs.empty() ? s : Eigen::Vector3d(s / static_cast<double>(qs.size()));
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

void RestNoiseOptions::validate() const {
  require_positive_finite(reference_s, "PID gain fit: the rest level's window [s]");
  require_positive_finite(moved_m, "PID gain fit: the rest's motion threshold [m]");
  require_positive_finite(moved_rad, "PID gain fit: the rest's rotation threshold [rad]");
  require_positive_finite(force_change_N, "PID gain fit: the rest's force threshold [N]");
  if (!(margin_s >= 0) || !std::isfinite(margin_s))
    throw InputError("PID gain fit: the rest's margin [s] must be finite and not negative");
  require_positive_finite(min_rest_s, "PID gain fit: the shortest rest [s]");
}

namespace {

/// The rest at the start of `push`: grid samples [0, end), and the sample where the push begins (onset; the
/// push's size when it never does). RestNoiseOptions states how they are found.
struct RestSpan {
  Eigen::Index end = 0, onset = 0;
};
RestSpan rest_span(const SynchronisedPush& push, const RestNoiseOptions& o) {
  const Eigen::Index n = push.size();
  RestSpan rest;
  if (n < 2) return rest;
  Eigen::Index ref = 1;
  while (ref < n && push.t_s(ref) - push.t_s(0) <= o.reference_s + 1e-9) ++ref;
  const auto median = [ref](const auto& column) {
    std::vector<double> v(static_cast<std::size_t>(ref));
    for (Eigen::Index k = 0; k < ref; ++k) v[static_cast<std::size_t>(k)] = column(k);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(ref / 2), v.end());
    return v[static_cast<std::size_t>(ref / 2)];
  };
  const Eigen::Vector3d pose0(median(push.pose.col(0)), median(push.pose.col(1)), median(push.pose.col(2)));
  const Eigen::Vector2d force0(median(push.force_N.col(0)), median(push.force_N.col(1)));
  while (rest.onset < n &&
         (push.pose.row(rest.onset).head<2>().transpose() - pose0.head<2>()).norm() <= o.moved_m &&
         std::abs(push.pose(rest.onset, 2) - pose0(2)) <= o.moved_rad &&
         (push.force_N.row(rest.onset).transpose() - force0).norm() <= o.force_change_N)
    ++rest.onset;
  if (rest.onset == n) {
    rest.end = n;  // never pushed: all rest
    return rest;
  }
  while (rest.end < rest.onset && push.t_s(rest.end) <= push.t_s(rest.onset) - o.margin_s + 1e-9) ++rest.end;
  return rest;
}

}  // namespace

std::string pid_fit_unsuitable_reason(const SynchronisedPush& push, const RestNoiseOptions& options) {
  options.validate();
  if (push.flags.frozen_force_sensor)
    return "frozen force sensor: its force is not needed for tracking, but d_hat = f_hat - u is meaningless";
  const RestSpan rest = rest_span(push, options);
  const double rest_s = rest.end >= 2 ? push.t_s(rest.end - 1) - push.t_s(0) : 0.0;
  if (rest.end < 3 || rest_s < options.min_rest_s - 1e-9) {
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "the object rests for only %.3g s at the start (the push begins at %.3g s, the rest ends %.3g s "
                  "before); the noise scales need %.3g s",
                  rest_s, rest.onset < push.size() ? push.t_s(rest.onset) : 0.0, options.margin_s,
                  options.min_rest_s);
    return buf;
  }
  return {};
}

PidFitNoise measure_rest_noise(const SynchronisedPush& push, const RestNoiseOptions& options) {
  const std::string unsuitable = pid_fit_unsuitable_reason(push, options);
  if (!unsuitable.empty()) throw InputError(about(push.source, "PID gain fit: " + unsuitable));
  const Eigen::Index n = rest_span(push, options).end;
  PidFitNoise noise;
  noise.rest_start_s = push.t_s(0);
  noise.rest_end_s = push.t_s(n - 1);
  noise.rest_samples = static_cast<long>(n);
  const Eigen::VectorXd t = push.t_s.head(n);
  const Eigen::MatrixX3d u = push.applied_input().topRows(n);
  for (int c = 0; c < 3; ++c) {
    noise.pose(c) = std_about_line(t, push.pose.col(c).head(n));
    const Eigen::VectorXd du = u.col(c).tail(n - 1) - u.col(c).head(n - 1);
    noise.force_step(c) = std::sqrt(du.squaredNorm() / static_cast<double>(n - 1));
    static const char* const names[3] = {"x", "y", "rotation"};
    if (!(noise.pose(c) > 0) || !(noise.force_step(c) > 0))
      throw InputError(about(push.source, std::string("PID gain fit: the ") + names[c] +
                                              " pose or input does not vary at all during the rest at the start "
                                              "(a frozen stream?), so it has no noise scale"));
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
  require_positive_finite(roughness_weight, "PID gain fit: the roughness weight lambda");
  require_positive_finite(numeric_diff_relative_step, "PID gain fit: the numeric-diff relative step");
  if (numeric_diff_relative_step >= 0.1)
    throw InputError("PID gain fit: the numeric-diff relative step must be below 0.1");
  for (const double w : start_bandwidths_rad_s) require_positive_finite(w, "PID gain fit: every start bandwidth [rad/s]");
  reconstruction.validate();
  std::string error;
  if (!solver.IsValid(&error)) throw InputError("PID gain fit: invalid Ceres solver options: " + error);
}

std::string pid_fit_problem_name(PidFitProblem problem) {
  return problem == PidFitProblem::Translation ? "translation" : "rotation";
}

PidGainFit fit_pid_gains(const std::vector<PidFitPush>& pushes, const PidGainFitOptions& options,
                         const PidGains& start) {
  options.validate();
  if (pushes.empty()) throw InputError("PID gain fit: no push to fit on (the set is empty)");
  start.validate();
  for (const double g : {start.kp, start.ki, start.kd, start.lp, start.li, start.ld})
    if (!(g >= kGainFloor && g <= kGainCeiling))
      throw InputError("PID gain fit: start gains must lie in [1e-6, 1e6] (log-parameterised), got " + fmt("%g", g));
  Eigen::Vector3d mean_inertia = Eigen::Vector3d::Zero();
  for (const PidFitPush& p : pushes) {
    if (p.push.flags.frozen_force_sensor)
      throw InputError(about(p.push.source, "PID gain fit: frozen force sensor: d_hat = f_hat - u is meaningless"));
    for (int c = 0; c < 3; ++c) {
      if (!(p.noise.pose(c) > 0) || !std::isfinite(p.noise.pose(c)) || !(p.noise.force_step(c) > 0) ||
          !std::isfinite(p.noise.force_step(c)))
        throw InputError(about(p.push.source, "PID gain fit: noise scales must be positive and finite"));
    }
    estimation_span(p.push, p.t_start_s, span_end(p), "PID gain fit");  // throws for a span without samples
    try {
      mean_inertia += nominal_inertia(p.push.shape, options.reconstruction.mass_kg, options.reconstruction.inertia_kgm2) /
                      static_cast<double>(pushes.size());
    } catch (const InputError& e) {
      throw InputError(about(p.push.source, std::string("PID gain fit: ") + e.what()));
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
    const double M = mean_inertia(channels_of(problem).first);
    std::vector<std::pair<std::string, std::array<double, 3>>> starts{{"given gains", gains_of(start, problem)}};
    for (const double w : options.start_bandwidths_rad_s)
      starts.push_back({"triple pole at " + fmt("%g", w) + " rad/s", {3 * M * w * w, M * w * w * w, 3 * M * w}});
    std::vector<double> r(static_cast<std::size_t>(residuals));
    double p[3] = {0, 0, 0};
    s.start_cost = std::numeric_limits<double>::infinity();
    for (const auto& [label, g] : starts) {
      double q[3];
      for (int i = 0; i < 3; ++i) q[i] = std::log(std::clamp(g[i], kGainFloor, kGainCeiling) / kGainFloor);
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
      throw SolverError("PID gain fit: the reconstruction fails (CVODE) at every start of the " +
                        pid_fit_problem_name(problem) + " gains");

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
      throw SolverError("PID gain fit: Ceres found no usable " + pid_fit_problem_name(problem) + " gains over " +
                        std::to_string(pushes.size()) + " push(es): " + summary.message);
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

std::string pid_fit_forces_csv(const PidFitPush& p, const PidGains& fitted, const PidGainFitOptions& options) {
  options.validate();
  const bool exact = options.exact_discretisation;
  const DisturbanceEstimate paper =
      run_pid(PidForceReconstruction(PidGains{}, options.reconstruction), p, exact).estimate;
  const DisturbanceEstimate fit = run_pid(PidForceReconstruction(fitted, options.reconstruction), p, exact).estimate;
  const DisturbanceEstimate dob = observer_estimate(p, options);
  std::ostringstream csv;
  csv << "t_s";
  for (const char* c : {"x_N", "y_N", "rot_Nm"})
    csv << ",u_" << c << ",d_hat_dob_" << c << ",d_hat_pid_paper_" << c << ",d_hat_pid_fitted_" << c;
  csv << "\n";
  char buf[64];
  for (Eigen::Index k = 0; k < paper.t_s.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%.6f", paper.t_s(k));
    csv << buf;
    for (int c = 0; c < 3; ++c)
      for (const double v : {paper.u(k, c), dob.d_hat(k, c), paper.d_hat(k, c), fit.d_hat(k, c)}) {
        std::snprintf(buf, sizeof buf, ",%.9g", v);
        csv << buf;
      }
    csv << "\n";
  }
  return csv.str();
}

double pid_objective(const std::vector<PidGainQuality>& qualities, PidFitProblem problem, double lambda) {
  std::vector<const PidGainQuality*> qs;
  for (const auto& q : qualities) qs.push_back(&q);
  const ObjectiveTerms t = objective_terms(qs, problem);
  return 0.5 * (t.tracking + lambda * t.roughness);
}

PidFitStudy run_pid_fit_study(const std::vector<PidFitPush>& pushes, const PidFitStudyOptions& options) {
  options.fit.validate();
  if (pushes.empty()) throw InputError("PID gain fit: no push to fit on (the set is empty)");
  PidFitStudy study;
  study.roughness_weight = options.fit.roughness_weight;
  study.joint = fit_pid_gains(pushes, options.fit);
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

nlohmann::json pid_fit_json(const PidFitStudy& s) {
  std::vector<const PidGainQuality*> paper, joint, own_paper, own;
  for (const auto& r : s.pushes) {
    paper.push_back(&r.paper);
    joint.push_back(&r.joint);
    if (r.own_quality) {
      own_paper.push_back(&r.paper);
      own.push_back(&*r.own_quality);
    }
  }
  const auto objective = [&](const std::vector<const PidGainQuality*>& qs) {
    nlohmann::json o = nlohmann::json::object();
    for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
      const ObjectiveTerms t = objective_terms(qs, problem);
      o[pid_fit_problem_name(problem)] = {{"tracking", t.tracking},
                                          {"roughness", t.roughness},
                                          {"objective", 0.5 * (t.tracking + s.roughness_weight * t.roughness)}};
    }
    return o;
  };
  nlohmann::json pushes = nlohmann::json::array();
  for (const auto& r : s.pushes) {
    nlohmann::json j = {{"source", r.source},
                        {"noise",
                         {{"pose_sigma_mm_deg", channels_json(r.noise.pose, 1e3, kRadToDeg)},
                          {"force_step_sigma_N_Nmm", channels_json(r.noise.force_step, 1, 1e3)},
                          {"rest_start_s", r.noise.rest_start_s},
                          {"rest_end_s", r.noise.rest_end_s},
                          {"rest_samples", r.noise.rest_samples}}},
                        {"paper", quality_json(r.paper)},
                        {"joint", quality_json(r.joint)}};
    if (r.own) {
      j["per_push_fit"] = fit_json(*r.own);
      j["per_push"] = quality_json(*r.own_quality);
    }
    pushes.push_back(j);
  }
  const auto listed = [](const std::vector<BatchFailure>& v) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& f : v) a.push_back({{"source", f.source}, {"reason", f.reason}});
    return a;
  };
  nlohmann::json out = {
      {"pushpred_version", kVersion},
      {"objective",
       {{"lambda", s.roughness_weight},
        {"definition", "1/2 sum_k,c [((r_meas - r_sim) / sigma_pose_c)^2 + lambda ((f_hat(k+1) - f_hat(k)) / "
                       "sigma_df_c)^2]; translation over x and y, rotation separately; see docs/pid_gains.md"}}},
      {"paper_gains", gains_json(PidGains{})},
      {"joint_fit", fit_json(s.joint)},
      {"objective_summed_over_pushes", {{"paper_gains", objective(paper)}, {"joint_gains", objective(joint)}}},
      {"pushes", pushes},
      {"skipped", listed(s.skipped)},
      {"failed", listed(s.failed)}};
  if (!own.empty()) {
    out["objective_summed_over_pushes"]["per_push_gains"] = objective(own);
    out["objective_summed_over_pushes"]["paper_gains_same_pushes"] = objective(own_paper);
  }
  return out;
}

std::string pid_fit_markdown(const PidFitStudy& s) {
  std::ostringstream md;
  const PidGains paper;
  md << "# PID gains fitted by Ceres\n\n";
  md << "Objective (docs/pid_gains.md): 1/2 sum over samples and channels of ((r_meas - r_sim) / sigma_pose)^2 + "
        "lambda ((f_hat(k+1) - f_hat(k)) / sigma_df)^2, lambda = "
     << fmt("%g", s.roughness_weight)
     << "; sigma_pose and sigma_df measured on each push while the object rests at the start. "
     << s.pushes.size() << " push(es) fitted";
  if (!s.skipped.empty()) md << ", " << s.skipped.size() << " skipped";
  if (!s.failed.empty()) md << ", " << s.failed.size() << " failed";
  md << ".\n\n## Gains\n\n";
  md << "| gains | kp [N/m] | ki [N/(m s)] | kd [N s/m] | lp [N m/rad] | li [N m/(rad s)] | ld [N m s/rad] |\n";
  md << "|---|---:|---:|---:|---:|---:|---:|\n";
  const auto gain_row = [&](const std::string& label, const PidGains& g) {
    md << "| " << label;
    for (double v : {g.kp, g.ki, g.kd, g.lp, g.li, g.ld})
      md << " | " << (v <= kGainFloor * (1 + 1e-9) ? std::string("floor") : fmt("%.4g", v));
    md << " |\n";
  };
  gain_row("paper (trial and error)", paper);
  gain_row("joint fit over " + std::to_string(s.joint.pushes) + " push(es)", s.joint.gains);
  std::vector<PidGains> own_gains;
  for (const auto& r : s.pushes)
    if (r.own) own_gains.push_back(r.own->gains);
  if (!own_gains.empty()) {
    // Nearest-rank order statistics of each gain over the per-push fits.
    const auto order_statistic = [&](double fraction) {
      PidGains g;
      for (double PidGains::*field : {&PidGains::kp, &PidGains::ki, &PidGains::kd, &PidGains::lp, &PidGains::li,
                                      &PidGains::ld}) {
        std::vector<double> v;
        for (const PidGains& o : own_gains) v.push_back(o.*field);
        std::sort(v.begin(), v.end());
        g.*field = v[static_cast<std::size_t>(fraction * static_cast<double>(v.size() - 1) + 0.5)];
      }
      return g;
    };
    gain_row("per push: lower quartile", order_statistic(0.25));
    gain_row("per push: median", order_statistic(0.5));
    gain_row("per push: upper quartile", order_statistic(0.75));
  }
  for (const auto& r : s.pushes)
    if (r.own) gain_row("per push: " + short_name(r.source), r.own->gains);
  md << "\n\"floor\": the gain ran to its lower clamp, 1e-6; the objective has no use for it there and its value is "
        "undetermined.\n";
  {
    const PidGains& g = s.joint.gains;
    const double m = s.mean_inertia(0), I = s.mean_inertia(2);
    md << "\nThe joint gains' PD part with the set's mean mass " << fmt("%.4g", m) << " kg and moment of inertia "
       << fmt("%.4g", I) << " kg m^2: translation poles at " << fmt("%.3g", std::sqrt(g.kp / m))
       << " rad/s with damping " << fmt("%.2g", g.kd / (2 * std::sqrt(g.kp * m))) << ", rotation poles at "
       << fmt("%.3g", std::sqrt(g.lp / I)) << " rad/s with damping " << fmt("%.2g", g.ld / (2 * std::sqrt(g.lp * I)))
       << " (the paper's: " << fmt("%.3g", std::sqrt(paper.kp / m)) << " rad/s, "
       << fmt("%.2g", paper.kd / (2 * std::sqrt(paper.kp * m))) << "; ld / I = " << fmt("%.3g", paper.ld / I)
       << " 1/s).\n";
  }
  md << "\nCeres, joint fit:\n\n";
  for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
    const PidFitSolve& f = problem == PidFitProblem::Translation ? s.joint.translation : s.joint.rotation;
    if (!f.fitted) {
      md << "- " << pid_fit_problem_name(problem) << ": not fitted\n";
      continue;
    }
    md << "- " << pid_fit_problem_name(problem) << ": cost " << fmt("%.6g", f.given_cost) << " at the paper's gains; "
       << "started from the " << f.start << " (cost " << fmt("%.6g", f.start_cost) << "); " << f.iterations
       << " iterations to " << fmt("%.6g", f.final_cost) << " (" << f.termination << ")\n";
  }

  std::vector<const PidGainQuality*> paper_q, joint_q, own_q;
  for (const auto& r : s.pushes) {
    paper_q.push_back(&r.paper);
    joint_q.push_back(&r.joint);
    if (r.own_quality) own_q.push_back(&*r.own_quality);
  }
  md << "\n## Objective, summed over the pushes\n\n"
        "tracking = sum of ((r_meas - r_sim) / sigma_pose)^2, roughness = sum of ((f_hat(k+1) - f_hat(k)) / "
        "sigma_df)^2; per sample (per step): divided by the channel-samples (channel-steps), 1 when the PID "
        "tracks at the pose noise and f_hat is as rough as the force noise.\n\n";
  md << "| problem | gains | tracking | per sample | roughness | per step | objective |\n"
        "|---|---|---:|---:|---:|---:|---:|\n";
  for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
    const auto row = [&](const std::string& label, const std::vector<const PidGainQuality*>& qs) {
      if (qs.empty()) return;
      const ObjectiveTerms t = objective_terms(qs, problem);
      double samples = 0, steps = 0;
      for (const PidGainQuality* q : qs) {
        samples += static_cast<double>(channels_of(problem).count * q->samples);
        steps += static_cast<double>(channels_of(problem).count * (q->samples - 1));
      }
      md << "| " << pid_fit_problem_name(problem) << " | " << label << " | " << fmt("%.4g", t.tracking) << " | "
         << fmt("%.4g", t.tracking / samples) << " | " << fmt("%.4g", t.roughness) << " | "
         << fmt("%.4g", t.roughness / steps) << " | "
         << fmt("%.4g", 0.5 * (t.tracking + s.roughness_weight * t.roughness)) << " |\n";
    };
    row("paper", paper_q);
    row("joint fit", joint_q);
    if (own_q.size() == s.pushes.size()) row("per-push fits", own_q);
  }

  md << "\n## What changes in the reconstructed force (mean over the pushes)\n\n"
        "Tracking: RMS of r_meas - r_sim. Roughness: RMS of f_hat(k+1) - f_hat(k) (one 4 ms grid step). "
        "d_hat vs dob: RMS of the PID's d_hat minus the disturbance observer's.\n\n";
  md << "| gains | tracking x [mm] | y [mm] | theta [deg] | roughness x [N] | y [N] | rot [N mm] | d_hat vs dob x [N] "
        "| y [N] | rot [N mm] |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  const auto quality_cells = [&](const Eigen::Vector3d& track, const Eigen::Vector3d& rough,
                                 const Eigen::Vector3d& dob) {
    md << " | " << fmt("%.3f", 1e3 * track(0)) << " | " << fmt("%.3f", 1e3 * track(1)) << " | "
       << fmt("%.3f", kRadToDeg * track(2)) << " | " << fmt("%.4f", rough(0)) << " | " << fmt("%.4f", rough(1))
       << " | " << fmt("%.3f", 1e3 * rough(2)) << " | " << fmt("%.4f", dob(0)) << " | " << fmt("%.4f", dob(1))
       << " | " << fmt("%.3f", 1e3 * dob(2)) << " |\n";
  };
  const auto mean_row = [&](const std::string& label, const std::vector<const PidGainQuality*>& qs) {
    if (qs.empty()) return;
    md << "| " << label;
    quality_cells(mean_of(qs, &PidGainQuality::tracking_rms), mean_of(qs, &PidGainQuality::roughness_rms),
                  mean_of(qs, &PidGainQuality::dob_rms));
  };
  mean_row("paper", paper_q);
  mean_row("joint fit", joint_q);
  if (own_q.size() == s.pushes.size()) mean_row("per-push fits", own_q);
  const Eigen::Vector3d u_rough = mean_of(paper_q, &PidGainQuality::input_roughness_rms);
  md << "| measured input u, for comparison | | | | " << fmt("%.4f", u_rough(0)) << " | " << fmt("%.4f", u_rough(1))
     << " | " << fmt("%.3f", 1e3 * u_rough(2)) << " | | | |\n";
  const auto closer = [&](bool own, int c) {
    int n = 0;
    for (const auto& r : s.pushes) {
      const PidGainQuality* q = own ? (r.own_quality ? &*r.own_quality : nullptr) : &r.joint;
      if (q && q->dob_rms(c) < r.paper.dob_rms(c)) ++n;
    }
    return std::to_string(n);
  };
  md << "\nPushes whose d_hat is closer to the observer's than with the paper's gains (x, y, rotation): joint gains "
     << closer(false, 0) << ", " << closer(false, 1) << ", " << closer(false, 2) << " of " << s.pushes.size();
  if (!own_q.empty())
    md << "; per-push gains " << closer(true, 0) << ", " << closer(true, 1) << ", " << closer(true, 2);
  md << ".\n";
  {
    std::vector<double> ratio[3];
    for (const auto& r : s.pushes)
      for (int c = 0; c < 3; ++c) ratio[c].push_back(r.paper.input_roughness_rms(c) / r.noise.force_step(c));
    md << "Median over the pushes of the measured input's step RMS over sigma_df (x, y, rotation):";
    for (int c = 0; c < 3; ++c) {
      std::sort(ratio[c].begin(), ratio[c].end());
      md << (c ? ", " : " ") << fmt("%.3g", ratio[c][ratio[c].size() / 2]);
    }
    md << ".\n";
  }

  md << "\n## Per push\n\n";
  md << "Noise during the rest at the start: sigma_pose x, y [mm], theta [deg]; sigma_df x, y [N], rot [N mm].\n\n";
  md << "| push | sigma_pose | sigma_df |\n|---|---|---|\n";
  for (const auto& r : s.pushes)
    md << "| " << short_name(r.source) << " | " << fmt("%.4f", 1e3 * r.noise.pose(0)) << ", "
       << fmt("%.4f", 1e3 * r.noise.pose(1)) << ", " << fmt("%.4f", kRadToDeg * r.noise.pose(2)) << " | "
       << fmt("%.4f", r.noise.force_step(0)) << ", " << fmt("%.4f", r.noise.force_step(1)) << ", "
       << fmt("%.3f", 1e3 * r.noise.force_step(2)) << " |\n";
  md << "\n| push | gains | tracking x [mm] | y [mm] | theta [deg] | roughness x [N] | y [N] | rot [N mm] | d_hat vs "
        "dob x [N] | y [N] | rot [N mm] |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : s.pushes) {
    const std::string name = short_name(r.source);
    const auto row = [&](const std::string& label, const PidGainQuality& q) {
      md << "| " << name << " | " << label;
      quality_cells(q.tracking_rms, q.roughness_rms, q.dob_rms);
    };
    row("paper", r.paper);
    row("joint", r.joint);
    if (r.own_quality) row("own", *r.own_quality);
  }
  if (!s.skipped.empty()) {
    md << "\n## Skipped\n\n";
    for (const auto& f : s.skipped) md << "- " << short_name(f.source) << ": " << f.reason << "\n";
  }
  if (!s.failed.empty()) {
    md << "\n## Failed\n\n";
    for (const auto& f : s.failed) md << "- " << short_name(f.source) << ": " << f.reason << "\n";
  }
  return md.str();
}

}  // namespace pushpred
