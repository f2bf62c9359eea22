#pragma once
// A ModelCorrection as the prediction study's `corrected` method uses it (prediction_study.hpp): the push with
// its data corrected, the paper's observer with the corrected nominal mass, the force laws' share of d_hat removed
// before the paper's online relation estimator sees it, and the force laws added to the prediction model. The
// relation d_hat = beta u + eps is still identified online per push, as in the paper: the correction only
// changes what it is fitted to and what the model holds besides it.
#include <optional>

#include "pushpred/diagnosis/candidate_effect.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/prediction/prediction_study.hpp"

namespace pushpred {

/// A force law as a term of the prediction model: its generalized force at the predicted state and planned input.
class ForceLawTerm final : public GeneralizedForceTerm {
 public:
  /// Resolves the shape's friction footprint here, once (FrictionFootprint), not in add().
  ForceLawTerm(FittedForceLaw law, ShapeInfo shape, const Eigen::Vector3d& start_pose)
      : law_(std::move(law)),
        shape_(std::move(shape)),
        footprint_(FrictionFootprint::of(shape_)),
        start_pose_(start_pose) {}
  std::string name() const override { return law_.effect->kind(); }
  void add(const IntegrationInterval& interval, double t_s, const PlanarState& state,
           const Eigen::Vector3d& planned_input, Eigen::Vector3d& generalized_force) const override;

 private:
  FittedForceLaw law_;
  ShapeInfo shape_;
  FrictionFootprint footprint_;  // of shape_
  Eigen::Vector3d start_pose_;
};

/// The quasi-static push law of ModelCorrection::QuasiStatic as a term of the prediction model (whose beta and
/// eps are then zero). With s the sliding speed (builtin_effects.hpp), g = s / sqrt(s^2 + v_reg^2) (0 at rest,
/// 1 sliding) and w = 1 / (1 + exp((|f| - F_stop) / (0.05 F_stop))) (1 once the applied force |f| falls below
/// F_stop):
///     generalized force = -(1 - w) u + w (g K - (1 - g) u),
/// K the kinetic friction: the force laws, plus Coulomb friction of magnitude F_stop when none of them replaces
/// the relation. So a pushed object keeps its velocity, an object no longer pushed slides to a stop, and a
/// resting one stays.
///
/// With a PusherStopCriterion (the pusher_stop effect) the push needs the pusher to move as well: with
/// m = 1 / (1 + exp(-(|v_tip| - v_stop) / (0.05 v_stop))) (1 while the planned tip speed |v_tip| is above v_stop),
/// pushing = force above F_stop AND tip moving:
///     generalized force = -(1 - w) m u + w (g K - (1 - g) u) + (1 - w) (1 - m) (g K - u).
/// A pusher that has stopped but still presses on the object drives it no more: its force is then a reaction
/// that does no work, so kinetic friction alone stops a sliding object and static friction holds a resting one.
/// Without the criterion m = 1 and this is the law above.
struct PusherStopCriterion {
  PlannedTipVelocity planned_tip;  ///< the phase's planned tip velocity [m/s], on the planned force's times
  double stop_speed_m_s = 0;       ///< v_stop, positive
};

class QuasiStaticPushTerm final : public GeneralizedForceTerm {
 public:
  /// Throws InputError for a stop force or, with `pusher_stop`, a stop speed that is not positive. Resolves the
  /// shape's friction footprint here, once (FrictionFootprint), not in add().
  QuasiStaticPushTerm(double stop_force_N, std::vector<FittedForceLaw> laws, ShapeInfo shape,
                      const Eigen::Vector3d& start_pose, std::optional<PusherStopCriterion> pusher_stop = std::nullopt);
  std::string name() const override { return "quasi_static"; }
  /// The planned tip velocity as held inside `interval`, the integrator's jump-free interval around t_s.
  void add(const IntegrationInterval& interval, double t_s, const PlanarState& state,
           const Eigen::Vector3d& planned_input, Eigen::Vector3d& generalized_force) const override;
  /// The weight of "pushed", (1 - w) m above, for an applied force of magnitude `applied_force_N` at time t_s
  /// inside `interval` (empty: the tip velocity held at t_s itself): the force criterion, times the pusher's
  /// motion criterion when there is one.
  double push_weight(const IntegrationInterval& interval, double t_s, double applied_force_N) const;

 private:
  double stop_force_N_;
  std::vector<FittedForceLaw> laws_;
  ShapeInfo shape_;
  FrictionFootprint footprint_;  // of shape_
  Eigen::Vector3d start_pose_;
  bool coulomb_from_stop_force_ = true;
  std::optional<PusherStopCriterion> pusher_stop_;

  double pressing_weight(double applied_force_N) const;  ///< 1 - w
  /// m (1 without the criterion), the held tip velocity read as held inside `interval`.
  double moving_weight(const IntegrationInterval& interval, double t_s) const;
};

/// The push's force level for the quasi-static law: mean |f_C| over the samples of `identification` where the
/// object slides faster than 5 mm/s; `fallback_N` when there are fewer than 10 of them.
double push_force_level(const std::vector<DisturbanceEstimate>& identification, const ShapeInfo& shape,
                        double fallback_N);

class CorrectedPrediction final : public PredictionCorrection {
 public:
  explicit CorrectedPrediction(ModelCorrection correction, QFilterObserverOptions observer = {})
      : correction_(std::move(correction)), observer_(std::move(observer)) {}

  SynchronisedPush corrected_push(const SynchronisedPush& push) const override;
  /// "dob": the Q-filter observer with this correction's options (nominal mass from the corrected push's shape);
  /// other names: make_disturbance_estimator(name).
  std::unique_ptr<DisturbanceEstimator> observer(const std::string& name) const override;
  void remove_explained(const SynchronisedPush& push, DisturbanceEstimate& estimate) const override;
  /// Mass and inertia from the corrected push's shape; the quasi-static law (beta = eps = 0) or the force laws.
  /// Without the phase it cannot read the planned tip motion: the pusher_stop criterion needs adjust_phase_model.
  void adjust_model(const SynchronisedPush& push, const std::vector<DisturbanceEstimate>& identification,
                    PredictionModel& model) const override;
  /// adjust_model, and with ModelCorrection::QuasiStatic::pusher_stop_speed_m_s the quasi-static law also reads
  /// the phase's planned tip velocity (plan_tip_velocity_from_measurement over `phase` at `plan_rate_hz`).
  void adjust_phase_model(const SynchronisedPush& push, const std::vector<DisturbanceEstimate>& identification,
                          const TimeInterval& phase, double plan_rate_hz, PredictionModel& model) const override;
  bool initial_velocity_from_observer() const override { return correction_.initial_velocity; }
  bool predicts_with_pushing_model() const override { return correction_.pushing_model; }
  /// corrected_push with the shape's mass centre moved by ModelCorrection::mass_centre_offset_m.
  SynchronisedPush pushing_model_push(const SynchronisedPush& push) const override;
  double contact_compliance_m_N() const override { return correction_.contact_compliance_m_N; }
  /// Every force law of the correction (the friction law of the base model and the laws found with it) as the
  /// pushing model's friction while not pushed; none without force laws (the pushing model's own identified Coulomb
  /// friction).
  std::vector<std::shared_ptr<const GeneralizedForceTerm>> free_slide_terms(
      const SynchronisedPush& push, const Eigen::Vector3d& start_pose) const override;

  const ModelCorrection& correction() const { return correction_; }

 private:
  /// The model of one phase; `pusher_stop` is given to the quasi-static law when set.
  void build_model(const SynchronisedPush& push, const std::vector<DisturbanceEstimate>& identification,
                   const std::optional<PusherStopCriterion>& pusher_stop, PredictionModel& model) const;

  ModelCorrection correction_;
  QFilterObserverOptions observer_;
};

/// The force laws' share of `estimate.d_hat` (n x 3), at the estimate's rows of `push`, seen as the diagnosis's
/// regressors see it (DiagnosisPush::as_observed, with the Q filter of `observer`): the laws at the pose and
/// velocity smoothed without lag over the estimate's span and the measured input, zero where the object is
/// stuck, Q-filtered. When a law replaces the paper's relation (Coulomb friction), static friction balances the
/// push where the object is stuck (d = -u, as in Relation::Friction), and that is explained too: what is left for
/// the online relation estimator is then only what the laws do not explain, as in the diagnosis's regression.
Eigen::MatrixX3d explained_disturbance(const std::vector<FittedForceLaw>& laws, const SynchronisedPush& push,
                                       const DisturbanceEstimate& estimate, const QFilterObserverOptions& observer = {});

}  // namespace pushpred
