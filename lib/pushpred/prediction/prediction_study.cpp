#include "pushpred/prediction/prediction_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/reading/physical_bounds.hpp"

namespace pushpred {
namespace {

/// The study's observer: the linear Q-filter observer on its fast path, any other (the PID reconstruction) by name.
std::unique_ptr<DisturbanceEstimator> study_observer(const std::string& name, const QFilterObserverOptions& options) {
  if (name == "dob") return make_exact_q_filter_observer(options);
  return make_disturbance_estimator(name);
}

}  // namespace

double surface_friction_coefficient(const std::string& surface) {
  if (surface == "abs") return 0.14;
  throw MissingCoefficient("no friction coefficient known for surface '" + surface +
                           "', and the study gives none (the friction coefficient option)");
}

double simple_friction_coefficient(const SynchronisedPush& push, const StudyOptions& options) {
  return options.friction_coefficient >= 0 ? options.friction_coefficient
                                           : surface_friction_coefficient(push.push.surface);
}

PredictionModel simple_prediction_model(const ShapeInfo& shape, double friction_coefficient) {
  PredictionModel model = relation_prediction_model(shape, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  model.coulomb_force_N = friction_coefficient * shape.mass_kg * kGravity_m_s2;
  return model;
}

const std::vector<std::string>& prediction_method_names() {
  static const std::vector<std::string> names{"dob", "dob_velinit", "simple", "hold", "const_velocity",
                                                  "quasi_static"};
  return names;
}

PredictionErrors prediction_errors(const Eigen::MatrixX3d& predicted, const Eigen::MatrixX3d& measured) {
  const Eigen::MatrixX3d e = (predicted - measured).cwiseAbs();
  const Eigen::Index n = e.rows();
  auto mean = [&](int c) { return e.col(c).mean(); };
  auto stdev = [&](int c) {
    const double m = e.col(c).mean();
    return std::sqrt((e.col(c).array() - m).square().sum() / static_cast<double>(n));
  };
  constexpr double mm = 1e3, deg = 180.0 / M_PI;
  PredictionErrors r;
  r.pos_mm_mean = mm * e.leftCols<2>().rowwise().norm().mean();
  r.x_mm_mean = mm * mean(0);
  r.x_mm_std = mm * stdev(0);
  r.y_mm_mean = mm * mean(1);
  r.y_mm_std = mm * stdev(1);
  r.theta_deg_mean = deg * mean(2);
  r.theta_deg_std = deg * stdev(2);
  r.final_pos_mm = mm * e.row(n - 1).head<2>().norm();
  r.final_theta_deg = deg * e(n - 1, 2);
  return r;
}

CorrectionPredictor::CorrectionPredictor(std::shared_ptr<const PredictionCorrection> correction)
    : correction_(std::move(correction)) {
  if (!correction_) throw InputError("a correction predictor needs a correction");
}

namespace {
/// A correction may change what a push reads, never its time grid or pose. Throws InputError otherwise.
void require_same_grid_and_pose(const SynchronisedPush& corrected, const SynchronisedPush& push) {
  if (corrected.size() != push.size() || corrected.t_s != push.t_s || corrected.pose != push.pose)
    throw InputError(about(push.source, "a prediction correction must keep the push's time grid and pose"));
}
}  // namespace

void CorrectionPredictor::start_push(const SynchronisedPush& push, const StudyOptions& o) {
  push_ = correction_->corrected_push(push);
  require_same_grid_and_pose(push_, push);
  observer_ = correction_->observer(o.observer);
  estimator_ = make_relation_estimator(o.estimator);
  identification_.clear();
  relation_ = RelationParameters();
  pushing_model_ = correction_->predicts_with_pushing_model();
  if (pushing_model_) {
    pushing_push_ = correction_->pushing_model_push(push);
    require_same_grid_and_pose(pushing_push_, push);
    pushing_estimator_.reset(pushing_push_);
  }
}

void CorrectionPredictor::add_interval(const SynchronisedPush&, const TimeInterval& interval, const DisturbanceEstimate&) {
  DisturbanceEstimate cid = observer_->estimate(push_, interval.t0_s, interval.t1_s);
  velocity0_ = cid.velocity.row(cid.velocity.rows() - 1).transpose();
  correction_->remove_explained(push_, cid);
  estimator_->add_interval(cid.u, cid.d_hat);
  identification_.push_back(std::move(cid));
  if (pushing_model_) pushing_estimator_.add_interval(interval);
}

PhasePrediction CorrectionPredictor::predict(const PhaseContext& c) {
  std::string fallback_note;
  if (pushing_model_) {
    try {
      return as_phase_prediction(predict_quasi_static_phase(
          pushing_push_, c.identified, c.phase, c.plan_rate_hz, velocity0_, c.t_s, c.options.pushing_model_integrator,
          &pushing_estimator_, correction_->free_slide_terms(pushing_push_, c.pose0),
          correction_->contact_compliance_m_N()));
    } catch (const std::exception& e) {
      // e.g. CVODE failing on a contact the outline cannot resolve: the relation model predicts this phase instead.
      fallback_note = std::string("the pushing model failed (") + e.what() + "): the relation model predicted";
    }
  }
  relation_ = estimator_->ready() ? estimator_->parameters() : RelationParameters();
  PredictionModel corrected = relation_prediction_model(push_.shape, relation_.beta, relation_.eps);
  correction_->adjust_phase_model(push_, identification_, c.phase, c.plan_rate_hz, corrected);
  const PlannedForce plan = plan_from_measurement(push_, c.phase.t0_s, c.phase.t1_s, c.plan_rate_hz);
  const Eigen::Vector3d velocity0 =
      correction_->initial_velocity_from_observer() ? velocity0_ : Eigen::Vector3d::Zero().eval();
  // A correction that adds no term leaves the relation model, which the dob methods predict in closed form: so must
  // this.
  return {has_closed_form(corrected) ? predict_poses_exactly(corrected, plan, c.pose0, velocity0, c.t_s)
                               : predict_poses(corrected, plan, c.pose0, velocity0, c.t_s, c.options.integrator),
          fallback_note,
          {}};
}

PushStudy run_prediction_study(const SynchronisedPush& push, const StudyOptions& o) {
  if (push.flags.frozen_force_sensor)
    throw UnsuitableInput(about(push.source, "force sensor frozen: its force cannot be trusted for prediction"));
  // A nan here would fail every "< 0" test and silently mean "from the surface".
  if (!std::isfinite(o.friction_coefficient))
    throw InputError("friction coefficient of the simple baseline must be finite (negative: from the surface)");
  if (o.friction_coefficient > kMaxFrictionCoefficient)
    check_friction_coefficient(o.friction_coefficient, "friction coefficient of the simple baseline");
  const auto observer = study_observer(o.observer, o.observer_options);
  const auto estimator = make_relation_estimator(o.estimator);

  PushStudy study;
  study.source = push.source;
  study.span = schedule_span_name(o.schedule.span);
  study.intervals = split_into_intervals(push, o.schedule);
  study.methods = o.methods.empty() ? prediction_method_names() : o.methods;

  std::vector<std::unique_ptr<Predictor>> predictors;
  for (const auto& name : study.methods) {
    if (name == kCorrectedMethod) throw InputError("'corrected' is not a method to select: set StudyOptions::correction");
    predictors.push_back(make_predictor(name));
  }
  // The corrected method, when asked for: its own push, observer and relation estimator.
  CorrectionPredictor* corrected = nullptr;
  if (o.correction) {
    auto p = std::make_unique<CorrectionPredictor>(o.correction);
    corrected = p.get();
    predictors.push_back(std::move(p));
    study.methods.push_back(kCorrectedMethod);
  }
  // A method that lacks a coefficient for this push is left out of it, with a note in every phase.
  std::map<std::string, std::string> skipped;
  for (auto it = predictors.begin(); it != predictors.end();) {
    try {
      (*it)->start_push(push, o);
      ++it;
    } catch (const MissingCoefficient& e) {
      const std::string name = (*it)->name();
      skipped[name] = std::string("skipped: ") + e.what();
      study.methods.erase(std::remove(study.methods.begin(), study.methods.end(), name), study.methods.end());
      it = predictors.erase(it);
    }
  }

  for (size_t k = 1; k < study.intervals.size(); ++k) {
    const TimeInterval& previous = study.intervals[k - 1];
    const TimeInterval& phase = study.intervals[k];
    // Identification: the observer, initialised from the data at the interval's start, over the interval just
    // measured; its output joins the estimator.
    const auto observer_start = std::chrono::steady_clock::now();
    if (o.observer_run == StudyOptions::ObserverRun::Continuous)
      study.identification.push_back(estimate_rows_within(
          observer->estimate(push, study.intervals.front().t0_s, previous.t1_s), previous.t0_s, previous.t1_s, k == 1));
    else
      study.identification.push_back(observer->estimate(push, previous.t0_s, previous.t1_s));
    const DisturbanceEstimate& id = study.identification.back();
    const auto fit_start = std::chrono::steady_clock::now();
    study.observer_seconds += std::chrono::duration<double>(fit_start - observer_start).count();
    estimator->add_interval(id.u, id.d_hat);
    const bool ready = estimator->ready();
    RelationParameters relation;
    if (ready) relation = estimator->parameters();
    study.estimator_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();

    PhaseResult r;
    r.phase = static_cast<int>(k);
    r.interval = phase;
    const Eigen::Index i0 = push.index_at(phase.t0_s);
    Eigen::Index i1 = push.index_at(phase.t1_s);
    if (push.t_s(i1) > phase.t1_s + 1e-9) --i1;
    // The initial pose is the last measurement of the previous interval, at the phase's start time.
    const Eigen::Index first = i0 + (push.t_s(i0) <= phase.t0_s + 1e-9 ? 1 : 0);
    if (first > i1) throw InputError(about(push.source, "a prediction phase holds no grid samples"));
    r.t_s = push.t_s.segment(first, i1 - first + 1);
    r.measured = push.pose.middleRows(first, i1 - first + 1);
    const Eigen::Vector3d pose0 = push.pose.row(push.index_at(phase.t0_s)).transpose();
    r.initial_velocity = id.velocity.row(id.velocity.rows() - 1).transpose();
    r.method_notes = skipped;
    if (ready) r.relation = relation;
    else r.note = "relation not identifiable yet (" + estimator->not_ready_reason() + "); dob predicts with beta = eps = 0";

    const std::vector<TimeInterval> identified(study.intervals.begin(), study.intervals.begin() + static_cast<long>(k));
    const PhaseContext context{push,  identified, study.identification, phase, o.plan_rate_hz, pose0, r.initial_velocity,
                               relation, ready,   r.t_s,                o};
    for (auto& p : predictors) {
      const auto method_start = std::chrono::steady_clock::now();
      p->add_interval(push, previous, id);
      PhasePrediction prediction = p->predict(context);
      study.method_seconds[p->name()] +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - method_start).count();
      if (prediction.poses.rows() != r.t_s.size() || !prediction.poses.allFinite())
        throw SolverError(about(push.source, "prediction method '" + p->name() + "' returned " +
                                                 std::to_string(prediction.poses.rows()) + " poses for " +
                                                 std::to_string(r.t_s.size()) + " times, or non-finite ones"));
      r.predicted[p->name()] = std::move(prediction.poses);
      if (!prediction.note.empty()) r.method_notes[p->name()] = prediction.note;
      if (!prediction.parameters.empty()) r.method_parameters[p->name()] = std::move(prediction.parameters);
    }
    if (corrected) r.corrected_relation = corrected->last_relation();
    for (const auto& [method, poses] : r.predicted) r.errors[method] = prediction_errors(poses, r.measured);
    study.phases.push_back(std::move(r));
  }
  return study;
}

const char* observer_run_name(StudyOptions::ObserverRun run) {
  return run == StudyOptions::ObserverRun::Continuous ? "continuous" : "per-interval";
}

StudyOptions::ObserverRun parse_observer_run(const std::string& name) {
  if (name == "per-interval") return StudyOptions::ObserverRun::PerInterval;
  if (name == "continuous") return StudyOptions::ObserverRun::Continuous;
  throw InputError("unknown observer run '" + name + "' (known: per-interval, continuous)");
}

DisturbanceEstimate estimate_rows_within(const DisturbanceEstimate& estimate, double t0_s, double t1_s,
                                         bool from_start) {
  constexpr double tolerance_s = 1e-9;
  Eigen::Index first = 0, last = estimate.t_s.size() - 1;
  while (first <= last &&
         (estimate.t_s(first) < t0_s - tolerance_s || (!from_start && estimate.t_s(first) <= t0_s + tolerance_s)))
    ++first;
  while (last >= first && estimate.t_s(last) > t1_s + tolerance_s) --last;
  if (first > last) throw InputError("the observer's output holds no sample of an identification interval");
  const Eigen::Index n = last - first + 1;
  DisturbanceEstimate slice;
  slice.estimator = estimate.estimator;
  slice.t_s = estimate.t_s.segment(first, n);
  slice.u = estimate.u.middleRows(first, n);
  slice.d_hat = estimate.d_hat.middleRows(first, n);
  slice.velocity = estimate.velocity.middleRows(first, n);
  slice.total = estimate.total.middleRows(first, n);
  slice.nominal_inertia = estimate.nominal_inertia;
  return slice;
}

void drop_samples(PushStudy& study) {
  study.identification.clear();
  study.identification.shrink_to_fit();
  for (auto& phase : study.phases) {
    phase.t_s.resize(0);
    phase.measured.resize(0, 3);
    for (auto& [method, poses] : phase.predicted) poses.resize(0, 3);
  }
}

}  // namespace pushpred
