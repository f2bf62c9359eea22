#pragma once
// Candidate effects: physical terms the paper's model lacks, each with its own regressor and parameters, tested
// by a diagnosis (diagnosis.hpp) against what the paper's method leaves unexplained. An analysis program adds
// its own by deriving from one of the role classes (ForceLawEffect, DataCorrectionEffect,
// PredictionStructureEffect) and registering it in an EffectLibrary.
//
// The residual model, on the samples a diagnosis fits, per push p and channel c (0 = x force [N], 1 = y force
// [N], 2 = torque about the tracked centre [N m]; frames, units and signs as in
// preprocessing/synchronised_push.hpp):
//
//     d_hat_c(t) = beta_pc (Q u_c)(t) + eps_pc + sum_e sum_j Phi_ejc(t) theta_ej + r_c(t),
//
// with beta and eps per push and channel (the paper's relation; u Q-filtered like d_hat, so that the filter's
// lag is not read as an effect) and theta_e shared by all pushes (physical constants). Phi_ej is effect e's
// regressor: its contribution to d_hat per unit of its parameter j, on the observer's time base.
//
// How an effect is tested:
// - Regression: its regressor columns join the regression above; it is scored by the drop of an information
//   criterion (residual_regression.hpp).
// - Direct: it estimates its parameters from data of its own (the force offset: samples where the tip does not
//   touch) and scores itself with the same criterion.
// - Prediction: it changes the structure of the prediction (the initial velocity) and is scored on the
//   prediction error of the fit pushes.
// How it corrects the model is its role (EffectRole): apply() writes into a ModelCorrection either a force law added
// to the observer's residual and to the prediction model (a GeneralizedForceTerm built from unit_force()), a change
// of the data (force stream delay, sensor bias, nominal mass) or a change of the prediction structure. Its size is
// judged as one value (EffectSize: amount, floor, plausibility).
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/reading/shape_table.hpp"

namespace pushpred {

struct DiagnosisPush;
struct SynchronisedPush;
class CandidateEffect;
class ForceLawEffect;

struct EffectParameter {
  std::string name;
  std::string unit;
};

/// What a force law sees at one instant. In the regression: the measured pose, the observer's (Q-filtered)
/// velocity and the Q-filtered input; in the prediction: the predicted state and the planned input.
struct EffectState {
  Eigen::Vector3d pose = Eigen::Vector3d::Zero();        ///< x, y [m], theta [rad], {R}
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();    ///< x', y' [m/s], theta' [rad/s]
  Eigen::Vector3d input = Eigen::Vector3d::Zero();       ///< f_x, f_y [N], torque about the centre [N m]
  Eigen::Vector3d start_pose = Eigen::Vector3d::Zero();  ///< the push's first measured pose
};

/// An object's footprint on its support as area elements (mechanics/outline.hpp, 16 cells across, 4 subsamples),
/// for the friction laws (builtin_effects.hpp): element centres in the body frame, origin at the tracked centre
/// [m], and each element's share of the weight under uniform pressure [-] (the shares sum to 1).
struct FrictionElements {
  std::vector<Eigen::Vector2d> centre_m;
  std::vector<double> share;
};

/// A shape's friction footprint, resolved once when whatever evaluates a friction law is built (a prediction
/// model's force term, a push's regressors), so that the evaluation itself, inside a right-hand side, neither
/// formats a key nor takes a lock nor searches a cache. A small value: it refers to elements held by a shape-keyed
/// cache for the rest of the program. A shape without an outline has no elements: its friction laws use the
/// ellipsoidal limit surface of its mass and inertia.
class FrictionFootprint {
 public:
  /// The footprint of `shape` (keyed by its name, geometry, dimensions and vertices; mass and inertia do not matter).
  /// Takes a lock and, on a shape's first use, builds the elements: call it when building, not while integrating.
  static FrictionFootprint of(const ShapeInfo& shape);
  /// The elements, or null for a shape without an outline.
  const FrictionElements* elements() const { return elements_; }
  /// How often of() has been called in this process: tests check that a right-hand side never calls it.
  static long resolutions();

 private:
  explicit FrictionFootprint(const FrictionElements* elements) : elements_(elements) {}
  const FrictionElements* elements_ = nullptr;
};

/// A force law with fitted parameters, as the correction carries it.
struct FittedForceLaw {
  std::shared_ptr<const ForceLawEffect> effect;
  Eigen::VectorXd theta;  ///< in the units of effect->parameters()
  double setting = 0;     ///< the setting chosen from effect->settings() (0 when it has none)
  /// Generalized force [f_x, f_y] [N], torque [N m] of the law at `state`, `footprint` being
  /// FrictionFootprint::of(shape) resolved beforehand (ForceLawEffect::resolved_unit_force). No lock, no cache.
  Eigen::Vector3d force(const EffectState& state, const ShapeInfo& shape, const FrictionFootprint& footprint) const;
  /// The same, resolving the footprint on each call (a lock): not for right-hand sides.
  Eigen::Vector3d force(const EffectState& state, const ShapeInfo& shape) const;
};

/// Everything the selected effects change, as one value: what the corrected method of the prediction study
/// (corrected_prediction.hpp) and the corrected observer read.
struct ModelCorrection {
  /// The force stream lags the pose: the force stamped t happened at t - delay, so f(t) := f_recorded(t + delay).
  double force_delay_s = 0;
  /// Bias of the sensor's fx, fy reading [N] (the reading is the reaction on the pusher, -f_C): removed.
  Eigen::Vector2d sensor_bias_N = Eigen::Vector2d::Zero();
  /// True mass and moment of inertia = factor x the shape table's.
  double inertia_factor = 1;
  /// Predictions start from the observer's velocity estimate instead of rest.
  bool initial_velocity = false;
  /// The quasi-static push law replaces the paper's relation in the prediction (quasi_static effect): while the
  /// applied force stays above stop_fraction x the push's force level, it is balanced and the object keeps its
  /// velocity; below, kinetic friction (the force laws, or Coulomb friction of that level when none is a friction
  /// law replacing the relation) stops it; at rest static friction holds it. The push's force level is the mean
  /// |f_C| while sliding in its identification data, or fallback_push_force_N before it slides.
  struct QuasiStatic {
    bool enabled = false;
    double stop_fraction = 0.5;
    double fallback_push_force_N = 0;
    /// When fallback_push_force_N is 0: the fallback is this coefficient times the object's weight.
    double fallback_friction_coefficient = 0;
    /// The pusher_stop effect: when positive, the push also needs the pusher to move. It counts as on only while
    /// the planned tip speed (prediction/planned_force.hpp, PlannedTipVelocity) stays above this [m/s]: a pusher
    /// that has stopped but still presses on the object does not drive it; static or kinetic friction takes over.
    /// 0: the force criterion alone.
    double pusher_stop_speed_m_s = 0;
  } quasi_static;
  std::vector<FittedForceLaw> force_laws;
  /// The quasi-static pushing model predicts (pushing_model effect, prediction/quasi_static_identification.hpp),
  /// identified online on the corrected push; the relation model with the settings above predicts only where it
  /// cannot. The found effects enter it as data corrections of its push, the mass-centre offset below as its
  /// centre of friction, and the force laws as the support's friction of its slide to rest.
  bool pushing_model = false;
  /// The mass centre's offset from the shape table's (body frame) [m]: the com_offset effect's delta. The relation
  /// model reads it through com_offset's force law; the pushing model moves its centre of friction by it.
  Eigen::Vector2d mass_centre_offset_m = Eigen::Vector2d::Zero();
  /// The pushing model's contact compliance [m/N] (QuasiStaticParameters::contact_compliance_m_N): how far the rod
  /// sinks into the outline per newton of normal force, measured on the fit pushes (DiagnosisContext).
  double contact_compliance_m_N = 0;

  bool empty() const;
  /// One line per change, for reports.
  std::vector<std::string> describe() const;
};

/// Parameters estimated outside the regression (EffectTest::Direct).
struct DirectFit {
  Eigen::VectorXd theta;
  Eigen::MatrixXd covariance;
  double score = 0;   ///< drop of the information criterion (positive: the effect explains data)
  long samples = 0;   ///< samples used
  int pushes = 0;     ///< pushes whose samples were used
  double effective_samples = 0;
  std::string note;
};

/// What an effect's size floor is derived from: the physics of the object and surface and the data being
/// diagnosed (diagnosis/effect_floor.hpp measures it on the fit pushes; validation computes it from a scenario).
/// The common yardstick is the support friction: a term whose force stays below `relevance_fraction` of the
/// friction force mu m g (torque: mu m g rho) changes the object's motion less than the surface's own variation.
struct FloorContext {
  double mass_kg = 0, inertia_kgm2 = 0;
  double radius_of_gyration_m = 0;       ///< sqrt(I / m)
  double friction_coefficient = 0;       ///< Coulomb mu of the support (fitted on the data, or the scenario's)
  /// Spread of mu from push to push (standard deviation of the per-push fits; 0 when unknown): the surface's own
  /// variation, reported beside the floors. No built-in floor uses it: the friction laws that vary from push to
  /// push (Stribeck, position-dependent) make this spread themselves (builtin_effects.cpp).
  double friction_spread = 0;
  double relevance_fraction = 0.05;      ///< kappa: the share of the friction force that matters
  double sample_period_s = 0.004;        ///< of the force stream
  double sliding_speed_m_s = 0;          ///< typical (RMS) speed while the object slides
  double acceleration_m_s2 = 0;          ///< typical acceleration (RMS of |a| while sliding)
  double travel_m = 0;                   ///< mean distance an object travels in a push
  /// Speeds while sliding where the smoothed speed is resolved (DiagnosisPush::blurred; a sample of at most a
  /// few thousand) [m/s]: how much of the data a speed-dependent term acts on.
  std::vector<double> sliding_speeds_m_s;
  double friction_force_N() const;       ///< mu m g
  /// RMS over the sliding speeds of exp(-(v / v_s)^2), the share of a low-speed (Stribeck) term that acts on the
  /// data; zero when no speeds are listed.
  double low_speed_exposure(double v_s_m_s) const;
  /// Standard deviation of the sliding speeds about their mean [m/s] (0 with fewer than two listed): how far the
  /// data's speeds vary, which is what tells a speed-dependent force from a changed mu.
  double sliding_speed_spread_m_s() const;
};

/// The smallest amount of an effect that matters, in the unit of CandidateEffect::amount(), and why.
struct EffectFloor {
  double amount = 0;
  std::string basis;  ///< e.g. "5 % of the friction force mu m g = 4.8 N"
};

/// Whether fitted parameters are physically possible for an effect. A fit outside the physical range is not taken as
/// the effect, whatever its score.
struct Plausibility {
  std::string why_not;  ///< empty: plausible; otherwise why not (e.g. "negative drag")
  /// Data corrections only: the nearest amount inside the range, from which a re-fit may continue (it applies the
  /// correction, re-runs the observer and fits the rest; where it settles is judged again). Empty: the fit is not
  /// taken. Why: a data correction's first, linearised fit can be biased in proportion to the amount (the mass
  /// factor's, where smoothing leaves the acceleration regressor short of what d_hat holds), while at the re-fit's
  /// fixed point the residual amount is zero and the bias with it.
  std::optional<Eigen::VectorXd> restart;
  bool plausible() const { return why_not.empty(); }
  static Plausibility yes() { return {}; }
  static Plausibility no(std::string why, std::optional<Eigen::VectorXd> restart = std::nullopt) {
    return {std::move(why), std::move(restart)};
  }
};

/// An effect's parameters judged as one value (CandidateEffect::judge): the size, the smallest size that matters
/// and whether the parameters are physical.
struct EffectSize {
  double amount = 0;  ///< CandidateEffect::amount(theta), in `unit`
  std::string unit;
  EffectFloor floor;  ///< infinite when it cannot be stated (a quantity it needs was not measured)
  Plausibility plausibility;
  /// The amount clears the floor by `margin` (e.g. a number of standard errors times the amount's standard error).
  bool matters(double margin = 0) const { return amount - margin >= floor.amount; }
};

enum class EffectTest { Regression, Direct, Prediction };
const char* effect_test_name(EffectTest test);  ///< "regression", "direct", "prediction"

/// What an effect changes in the model: the role decides how the diagnosis tests it and how it corrects the model.
enum class EffectRole {
  /// A generalized force added to the observer's residual and to the prediction model (ForceLawEffect).
  ForceLaw,
  /// A change of the data the observer reads: a delay, a sensor bias, the nominal mass (DataCorrectionEffect). The
  /// diagnosis applies it, re-runs the observer and re-fits; what it finds next is a residual amount to compose.
  DataCorrection,
  /// A change of the pushing model's prediction structure, scored on prediction error (PredictionStructureEffect).
  PredictionStructure,
};
const char* effect_role_name(EffectRole role);  ///< "force law", "data correction", "prediction structure"

class DataCorrectionEffect;
class PredictionStructureEffect;

/// What every candidate states: its name, parameters, size and floor, and how it changes the model. An effect
/// derives from one of the three role classes below, never from this one directly.
class CandidateEffect {
 public:
  virtual ~CandidateEffect() = default;

  /// Short identifier, e.g. "viscous_friction"; unique within a library.
  virtual std::string kind() const = 0;
  /// One line: the physical term and its regressor.
  virtual std::string description() const = 0;
  virtual std::vector<EffectParameter> parameters() const = 0;
  virtual EffectRole role() const = 0;
  /// How it is tested: force laws by regression, prediction structures by prediction, data corrections either way.
  virtual EffectTest test() const = 0;

  /// A structural constant tried on a grid (e.g. the Stribeck speed); the diagnosis keeps the best and counts
  /// the choice as one more parameter. Empty: none.
  virtual std::vector<double> settings() const { return {}; }
  virtual EffectParameter setting_name() const { return {}; }

  /// Part of the corrected base model (diagnosis.hpp): a fix of the paper's model structure that is always in the
  /// corrected model, not a physical effect to be found. Default: none (the role classes say otherwise).
  virtual bool in_base_model() const { return false; }
  /// Tested only against a friction law (Relation::Friction): against the paper's free relation the effect is
  /// confounded with the relation's own misfit (a friction change is mirrored by the push force and absorbed;
  /// the relation's misfit at accelerations reads as a mass error).
  virtual bool needs_friction_base() const { return false; }

  // --- Its size: the amount compared with the floor, and the physical range.
  /// The effect's size as one non-negative number (its unit: amount_unit()), compared with floor(): e.g. |delay|,
  /// |bias|, |offset|, |mass factor - 1|. Default: the norm of theta.
  virtual double amount(const Eigen::VectorXd& theta) const { return theta.size() ? theta.norm() : 0.0; }
  virtual std::string amount_unit() const {
    const auto p = parameters();
    return p.empty() ? "-" : p.front().unit;
  }
  /// The smallest amount that matters physically (see FloorContext). An effect that passes its test below it is
  /// "significant, negligible": reported, not found. Default: 0 (no floor).
  virtual EffectFloor floor(const FloorContext& /*context*/) const { return {0.0, "no floor stated"}; }
  /// Whether `theta` is physically possible, for the object and data of `context` (as measured for the floors; a
  /// default FloorContext when nothing is known). Default: always.
  virtual Plausibility plausibility(const Eigen::VectorXd& /*theta*/, const FloorContext& /*context*/) const {
    return Plausibility::yes();
  }
  /// amount, floor and plausibility of `theta` together.
  EffectSize judge(const Eigen::VectorXd& theta, const FloorContext& context) const;
  /// Amounts for reports derived from the parameters (e.g. an inertia factor), as name, unit, value.
  struct Derived {
    std::string name, unit;
    double value = 0;
  };
  virtual std::vector<Derived> derived(const Eigen::VectorXd& /*theta*/) const { return {}; }

  // --- How it is fitted (by test()).
  /// Regression: per parameter j, its contribution to d_hat per unit of theta_j at every row of push.estimate
  /// (n x 3 each). Force laws: unit_force() at push.state(row) for every row. Default: throws.
  virtual std::vector<Eigen::MatrixX3d> regressors(const DiagnosisPush& push, double setting) const;
  /// Direct effects, and prediction structures with parameters: estimates theta from the fit pushes (as corrected so
  /// far). For prediction structures the score is not used. Default: throws.
  virtual DirectFit fit_directly(const std::vector<DiagnosisPush>& pushes) const;
  /// The same, where the effect may also read what the held-out pushes record before the tip moves (`held_out`,
  /// corrected like `pushes`): no prediction phase holds those samples. Default: fit_directly(pushes).
  virtual DirectFit fit_directly(const std::vector<DiagnosisPush>& pushes,
                                 const std::vector<SynchronisedPush>& held_out) const;

  // --- How it corrects the model.
  /// Adds the effect with parameters `theta` (and `setting`) to `correction`. `self` is this effect, shared, for
  /// force laws to keep.
  virtual void apply(const Eigen::VectorXd& theta, double setting, const std::shared_ptr<const CandidateEffect>& self,
                     ModelCorrection& correction) const = 0;

  /// This effect in its role, or null when it has another.
  const ForceLawEffect* as_force_law() const;
  const DataCorrectionEffect* as_data_correction() const;
  const PredictionStructureEffect* as_prediction_structure() const;
};

/// Where a force law sits in the support's friction (the base model's friction law and its refinements).
enum class SupportFrictionPart {
  None,              ///< a force of its own (drag, a lever-arm error, a friction refinement with a shape of its own)
  ReplacesRelation,  ///< the friction law that replaces the paper's relation as the base (at most one is selected)
  /// Its one parameter adds to the friction law's coefficient in the torque channel only (the support's friction
  /// torque scales with mu + theta): the sum must stay positive, or the fitted friction would drive the rotation
  /// (DiagnosisContext::support_coefficients in the diagnosis).
  ScalesTorque,
};

/// A generalized force law: f = sum_j theta_j unit_force(j, setting, state, shape). Tested by regression on the
/// observer's residual; applied as a FittedForceLaw in the observer and the prediction model.
class ForceLawEffect : public CandidateEffect {
 public:
  EffectRole role() const final { return EffectRole::ForceLaw; }
  EffectTest test() const final { return EffectTest::Regression; }
  /// The friction law that replaces the relation is part of the base model.
  bool in_base_model() const override { return support_friction() == SupportFrictionPart::ReplacesRelation; }

  /// The generalized force [f_x, f_y [N], torque [N m]] per unit of parameter j at `state`.
  virtual Eigen::Vector3d unit_force(int parameter, double setting, const EffectState& state,
                                     const ShapeInfo& shape) const = 0;
  /// unit_force() with the shape's friction footprint resolved beforehand (`footprint` is
  /// FrictionFootprint::of(shape)): what the prediction model's terms and the regressors call, each having resolved
  /// the footprint once when it was built. The library's friction laws override it so that evaluating them inside
  /// a right-hand side takes no lock. Default: unit_force(parameter, setting, state, shape).
  virtual Eigen::Vector3d resolved_unit_force(int parameter, double setting, const EffectState& state,
                                              const ShapeInfo& shape, const FrictionFootprint& footprint) const;
  virtual SupportFrictionPart support_friction() const { return SupportFrictionPart::None; }
  /// True when the law also changes how the pushing model moves the object (the mass-centre offset moves its centre
  /// of friction). Such an effect is a claim about the motion, so the fit pushes' own motion must confirm it: it is
  /// found only if the corrected model predicts the fit pushes' phases better with it than without it, on the mean
  /// by kMotionConfirmationGain (10 %) or more (part of the torque of physics the catalogue lacks, taken up, lowers it
  /// a little). A residual the motion contradicts is some other term of the same shape.
  virtual bool confirmed_by_motion() const { return false; }

  /// unit_force() at push.state(row) for every row, as the observer sees it.
  std::vector<Eigen::MatrixX3d> regressors(const DiagnosisPush& push, double setting) const override;
  /// Appends a FittedForceLaw.
  void apply(const Eigen::VectorXd& theta, double setting, const std::shared_ptr<const CandidateEffect>& self,
             ModelCorrection& correction) const override;
};

/// A change of the data the observer reads (ModelCorrection's force delay, sensor bias, inertia factor): tested by
/// regression (regressors()) or directly on data of its own (fit_directly()).
class DataCorrectionEffect : public CandidateEffect {
 public:
  EffectRole role() const final { return EffectRole::DataCorrection; }
  EffectTest test() const override { return EffectTest::Regression; }
  /// The total amount after applying `applied` and then finding `residual` on the corrected data.
  virtual Eigen::VectorXd compose(const Eigen::VectorXd& applied, const Eigen::VectorXd& residual) const {
    return applied + residual;
  }

  /// The found correction `theta` scored again with `nuisance` fitted beside the support's friction law (columns as
  /// the observer sees them, [column][push] on `pushes`, which this correction has not been applied to): the
  /// stand-in check's question to a found data correction where the residual holds structure the catalogue lacks.
  /// `spanned_share` is how much of the correction's own change of the residual the nuisance spans (where it spans
  /// most of it, the nuisance is the generic form of this effect and no test beside it could pass).
  struct BesideFit {
    DirectFit fit;
    double spanned_share = 0;
  };
  /// Empty where the effect has no such test (the default).
  virtual std::optional<BesideFit> fit_directly_beside(
      const std::vector<DiagnosisPush>& /*pushes*/, const Eigen::VectorXd& /*theta*/,
      const std::vector<std::vector<Eigen::MatrixX3d>>& /*nuisance*/) const {
    return std::nullopt;
  }
};

/// A change of the prediction's structure (the initial velocity, the quasi-static push law, the pushing model),
/// scored on the fit pushes' prediction error; part of the base model unless it says otherwise.
class PredictionStructureEffect : public CandidateEffect {
 public:
  EffectRole role() const final { return EffectRole::PredictionStructure; }
  EffectTest test() const final { return EffectTest::Prediction; }
  bool in_base_model() const override { return true; }
  /// The kind of the structure whose law it only refines (e.g. pusher_stop refines quasi_static): tried only in
  /// combinations that hold that one, since alone it changes nothing. Empty: a structure of its own.
  virtual std::string refines() const { return ""; }
};

/// Role questions the diagnosis asks (each false for an effect of another role).
bool replaces_relation(const CandidateEffect& effect);
bool scales_support_torque(const CandidateEffect& effect);
bool corrects_data(const CandidateEffect& effect);
bool confirmed_by_motion(const CandidateEffect& effect);

/// The candidate effects a diagnosis tests, in a fixed order. A user registers their own.
class EffectLibrary {
 public:
  /// The standard catalogue: time_offset, force_offset, viscous_friction, stribeck_friction,
  /// position_friction, com_offset, inertia_mismatch, initial_velocity, coulomb_friction; and the prediction
  /// structure quasi_static with its refinement pusher_stop.
  static EffectLibrary standard();

  /// Adds `effect`; throws InputError for a null effect, an empty kind or a kind already registered.
  void register_effect(std::unique_ptr<CandidateEffect> effect);
  /// Removes the effect called `kind`; throws InputError when there is none.
  void remove(const std::string& kind);
  /// The effect called `kind` or null.
  std::shared_ptr<const CandidateEffect> find(const std::string& kind) const;
  const std::vector<std::shared_ptr<const CandidateEffect>>& effects() const { return effects_; }
  std::vector<std::string> kinds() const;

 private:
  std::vector<std::shared_ptr<const CandidateEffect>> effects_;
};

}  // namespace pushpred
