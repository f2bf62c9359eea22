#include "pushpred/prediction/prediction_study.hpp"

#include <chrono>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/prediction/quasi_static_identification.hpp"

namespace pushpred {

double surface_friction_coefficient(const std::string& surface) {
  if (surface == "abs") return 0.14;
  throw InputError("no friction coefficient known for surface '" + surface + "' (give --mu)");
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

PushStudy run_prediction_study(const SynchronisedPush& push, const StudyOptions& o) {
  if (push.flags.frozen_force_sensor)
    throw InputError(about(push.source, "force sensor frozen: its force cannot be trusted for prediction"));
  const double mu = o.friction_coefficient >= 0 ? o.friction_coefficient : surface_friction_coefficient(push.push.surface);
  const auto observer = make_disturbance_estimator(o.observer);
  const auto estimator = make_relation_estimator(o.estimator);

  PushStudy study;
  study.source = push.source;
  study.span = schedule_span_name(o.schedule.span);
  study.intervals = split_into_intervals(push, o.schedule);

  // The corrected method, when asked for: its own push, observer and relation estimator.
  SynchronisedPush corrected_push;
  std::unique_ptr<DisturbanceEstimator> corrected_observer;
  std::unique_ptr<RelationEstimator> corrected_estimator;
  std::vector<DisturbanceEstimate> corrected_identification;
  if (o.correction) {
    corrected_push = o.correction->corrected_push(push);
    if (corrected_push.size() != push.size() || corrected_push.t_s != push.t_s || corrected_push.pose != push.pose)
      throw InputError(about(push.source, "a prediction correction must keep the push's time grid and pose"));
    corrected_observer = o.correction->observer(o.observer);
    corrected_estimator = make_relation_estimator(o.estimator);
  }

  QuasiStaticEstimator quasi_static;
  quasi_static.reset(push);
  for (size_t k = 1; k < study.intervals.size(); ++k) {
    const TimeInterval& previous = study.intervals[k - 1];
    const TimeInterval& phase = study.intervals[k];
    // Identification: the observer, initialised from the data at the interval's start, over the interval just
    // measured; its output joins the estimator.
    study.identification.push_back(observer->estimate(push, previous.t0_s, previous.t1_s));
    const DisturbanceEstimate& id = study.identification.back();
    const auto fit_start = std::chrono::steady_clock::now();
    estimator->add_interval(id);
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

    const PlannedForce plan = plan_from_measurement(push, phase.t0_s, phase.t1_s, o.plan_rate_hz);
    PredictionModel model;
    model.mass_kg = push.shape.mass_kg;
    model.inertia_kgm2 = push.shape.inertia_kgm2;
    if (ready) {
      r.relation = relation;
      model.beta = r.relation.beta;
      model.eps = r.relation.eps;
    } else {
      r.note = "relation not identifiable yet (" + estimator->not_ready_reason() + "); dob predicts with beta = eps = 0";
    }
    r.predicted["dob"] = predict_poses(model, plan, pose0, Eigen::Vector3d::Zero(), r.t_s, o.integrator);
    r.predicted["dob_velinit"] = predict_poses(model, plan, pose0, r.initial_velocity, r.t_s, o.integrator);

    PredictionModel simple;
    simple.mass_kg = push.shape.mass_kg;
    simple.inertia_kgm2 = push.shape.inertia_kgm2;
    simple.coulomb_force_N = mu * push.shape.mass_kg * kGravity_m_s2;
    r.predicted["simple"] = predict_poses(simple, plan, pose0, Eigen::Vector3d::Zero(), r.t_s, o.integrator);

    Eigen::MatrixX3d hold(r.t_s.size(), 3), constant(r.t_s.size(), 3);
    for (Eigen::Index j = 0; j < r.t_s.size(); ++j) {
      hold.row(j) = pose0.transpose();
      constant.row(j) = (pose0 + (r.t_s(j) - phase.t0_s) * r.initial_velocity).transpose();
    }
    r.predicted["hold"] = hold;
    r.predicted["const_velocity"] = constant;
    quasi_static.add_interval(previous);
    const std::vector<TimeInterval> identified(study.intervals.begin(), study.intervals.begin() + static_cast<long>(k));
    r.predicted["quasi_static"] = predict_quasi_static_phase(push, identified, phase, o.plan_rate_hz, r.initial_velocity,
                                                             r.t_s, o.integrator, &quasi_static)
                                      .poses;
    if (o.correction) {
      DisturbanceEstimate cid = corrected_observer->estimate(corrected_push, previous.t0_s, previous.t1_s);
      const Eigen::Vector3d velocity0 = cid.velocity.row(cid.velocity.rows() - 1).transpose();
      o.correction->remove_explained(corrected_push, cid);
      corrected_estimator->add_interval(cid);
      corrected_identification.push_back(std::move(cid));
      PredictionModel corrected;
      corrected.mass_kg = corrected_push.shape.mass_kg;
      corrected.inertia_kgm2 = corrected_push.shape.inertia_kgm2;
      if (corrected_estimator->ready()) {
        r.corrected_relation = corrected_estimator->parameters();
        corrected.beta = r.corrected_relation.beta;
        corrected.eps = r.corrected_relation.eps;
      }
      o.correction->adjust_phase_model(corrected_push, corrected_identification, phase, o.plan_rate_hz, corrected);
      const PlannedForce corrected_plan = plan_from_measurement(corrected_push, phase.t0_s, phase.t1_s, o.plan_rate_hz);
      r.predicted[kCorrectedMethod] =
          predict_poses(corrected, corrected_plan, pose0,
                        o.correction->initial_velocity_from_observer() ? velocity0 : Eigen::Vector3d::Zero(), r.t_s,
                        o.integrator);
    }
    for (const auto& [method, poses] : r.predicted) r.errors[method] = prediction_errors(poses, r.measured);
    study.phases.push_back(std::move(r));
  }
  return study;
}

}  // namespace pushpred
