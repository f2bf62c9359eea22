#pragma once
// The model-adequacy test after the found effects: does the corrected model still leave structure that noise and
// parameter uncertainty do not explain? Four parts, each significant-and-above-a-floor like a candidate effect:
//
// - Force residual. The pushes' disturbance residual (the diagnosis reads every push, held-out ones too; the stand-in
//   check the fit pushes only) against the corrected friction model (the base friction law, its refinements and the
//   found force laws, on the data as the found data corrections left them; sliding samples the friction base uses)
//   is regressed on generic signatures of missing physics (residual_signatures()).
//   Statistic: per signature, R^2, the share of the residual's weighted variance it accounts for with the model's
//   own columns projected out (so the model's parameters are re-fitted with it: their uncertainty is in the null),
//   standardised by the null replicates' mean and standard deviation of that share; the statistic is the largest
//   over the signatures. Null: a block bootstrap of the model's residual (blocks of kAdequacyBlock_s drawn from any
//   push, the three channels together), which keeps the noise's autocorrelation and cross-channel correlation
//   and breaks any tie to the state; each replicate is projected off the model's columns again and its statistic
//   taken the same way. What is resampled is the residual of the model with the signatures (the unrestricted fit):
//   under the null it is the same noise, and where a signature holds structure the null does not carry it (resampling
//   the restricted residual let a drag twice its floor pass in two of three trials). Significant when the observed
//   statistic exceeds the replicates' (1 - alpha) quantile. Size: the RMS of the structured part (the
//   signatures' fit) over the sliding samples beyond what the signatures pick out of the replicates (the square
//   root of the observed mean square less the replicates' mean), force [N] and torque [N m], against the floor
//   kappa mu m g and kappa mu m g rho (FloorContext): a term below it changes the motion less than the support's
//   own variation. Like an effect's amount, the size must clear its floor by a margin of its standard errors (the
//   replicates' spread of the chance structure's RMS): structure_margin_std.
// - Motion. The corrected model's signed prediction error of each fit phase (predicted - measured, averaged over
//   the phase), in the world frame (x, y), in the frame of the phase's own travel (along, across) and in yaw.
//   Statistic: the largest |t| of the five components' means over the phases. Null: random sign flips of whole
//   phases (a complete model's errors are symmetric about zero; the flips keep each phase's components together).
//   Size: the mean bias [mm, deg] against kappa times how far the object moves in a fit phase (the mean error of
//   `hold`, which predicts no motion); in yaw at least the turn that moves the outline by the position floor.
// - Rest. Where nothing touches (the rests of the pushes whose rod rests clear, samples_without_contact) the
//   corrected model says the sensor reads zero. The force those rests share (rest_force_fit, the force-offset test's
//   estimate and score) counts when its score passes the search's BIC threshold and its size clears the force floor
//   by floor_margin_std of its standard error: a sensor bias no candidate took out.
// - Contact. The base model drives the object with the recorded tip: a rigid rod on a rigid object, whose centre
//   lies its radius outside the outline wherever it pushes, however hard. Where the recorded rod sits the deeper
//   inside the outline the harder it pushes, the pusher (arm, sensor, tip) or the contact gives way, and the contact
//   lags the recorded path by that compliance times the force. Per push (every push, held-out ones too, as the data
//   corrections left them), the penetration (rod radius less the rod centre's signed distance to the outline, body
//   frame) is regressed by least squares on the force's component into the object along the outline's normal, over
//   the samples in contact; the intercept takes up offsets of the outline, the tracking and the sensor's zero. The
//   compliance is the median of the pushes' slopes (robust to a push whose rod slides off a corner), its standard
//   error 1.2533 x 1.4826 x their median absolute deviation / sqrt(pushes). Size: the lag under the friction force,
//   compliance x mu m g [mm], against kappa times how far an object travels in a push (FloorContext::travel_m); it
//   counts when it clears the floor by floor_margin_std of its standard errors.
//
// "Explained" when no part is both significant and above its floor. Signatures that account for an unexplained
// residual are hints (ResidualHint), not findings.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/diagnosis/candidate_effect.hpp"
#include "pushpred/diagnosis/residual_regression.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// Bootstrap block length [s]: the Newey-West lag window (residual_regression.hpp), beyond the observer's and the
/// sensor noise's correlation times. Chosen between 0.1 and 0.4 s on tuning seeds 231000-232011 (docs/diagnosis.md).
inline constexpr double kAdequacyBlock_s = 0.2;

/// The diagnosis's verdict counts the force part's structure when its size clears the floor by this many times the
/// floor margin of its standard errors (AdequacyOptions::structure_margin_std). That standard error is noise's alone,
/// which shrinks as the verdict reads every push, while the clean simulator's pushes carry structure of about the floor
/// that the base model only approximates (the contact, the support's pressure): twice the margin keeps those
/// explained and a missing effect at twice its floor unexplained. Chosen between 1 and 2 on the tuning seeds
/// 362000-362654 (with it in the verdict and the stand-in check: clean explained 94 -> 96 of 100, hidden kinds
/// unexplained 127 -> 126 of 140, no finding changed there). The stand-in check, which reads the fit pushes only, keeps
/// the plain margin it was chosen with (test_diagnosis_steps' tilted-support trial needs it).
inline constexpr double kAdequacyStructureMargin = 2.0;

/// The outcome of the model-adequacy test (see above). Units as named; mm and degrees for the motion.
struct ModelAdequacy {
  bool tested = false;
  bool explained = true;
  /// The statistics, the null and the thresholds in words.
  std::string statistic;
  double alpha = 0.01;  ///< significance level of each part
  int replicates = 0;   ///< bootstrap replicates (force) and sign-flip draws (motion)
  // Force residual.
  bool force_tested = false;
  int force_pushes = 0;        ///< pushes the force residual was read on
  double force_share = 0;      ///< R^2 of all signatures together on the residual [-]
  double force_statistic = 0;  ///< the largest standardised R^2 of one signature (see above) [-]
  double force_threshold = 0;  ///< the null's (1 - alpha) quantile of that statistic
  double force_p_value = 1;
  double force_N = 0;    ///< RMS of the structured part beyond noise's, force channels (|(x, y)|) [N]
  double torque_Nm = 0;  ///< the same, torque channel [N m]
  double force_N_std = 0, torque_Nm_std = 0;  ///< their standard errors: the replicates' spread of that RMS
  double force_floor_N = 0;                   ///< kappa mu m g
  double torque_floor_Nm = 0;                 ///< kappa mu m g rho
  bool force_unexplained = false;             ///< the structure or the shared force (below) is unexplained
  bool structure_unexplained = false;         ///< the signatures' structure: significant and above a floor
  int pushes_zero_projected = 0;  ///< pushes whose unmeasured sensor zero was projected out (AdequacyOptions)
  int zero_measured_pushes = 0;   ///< pushes whose sensor zero is measured at rest (0 when fewer than two)
  /// The measured zeros' spread over the pushes [N] (NaN with fewer than two). Below the force floor the sensor is
  /// taken as zeroed on every push, and its zeros are left as recorded.
  double zero_spread_N = 0;
  /// The force those pushes share beyond their zeros' chance mean (a bias, a tilt) [N], its standard error, p.
  double shared_force_N = 0, shared_force_N_std = 0, shared_force_p_value = 1;
  bool shared_force_unexplained = false;  ///< significant and above the force floor
  // Rest.
  bool rest_tested = false;  ///< two or more fit pushes rest clear of the object
  int rest_pushes = 0;
  double rest_force_N = 0, rest_force_N_std = 0;  ///< |mean recorded force at rest| and its standard error [N]
  Eigen::Vector2d rest_bias_N = Eigen::Vector2d::Zero();  ///< the sensor bias those rests show (x, y) [N]
  double rest_score = 0;                          ///< Wald statistic less 2 ln N_eff
  double rest_threshold = 0;                      ///< the BIC threshold it must pass
  bool rest_unexplained = false;
  // Contact.
  bool contact_tested = false;  ///< kMinContactPushes or more pushes with a usable slope
  int contact_pushes = 0;
  double contact_compliance_m_N = 0, contact_compliance_m_N_std = 0;  ///< median slope and its standard error
  double contact_lag_mm = 0, contact_lag_mm_std = 0;                  ///< compliance x mu m g and its standard error
  double contact_floor_mm = 0;                                        ///< kappa x the mean travel of a push
  bool contact_unexplained = false;
  // Motion.
  bool motion_tested = false;
  int phases = 0;
  double motion_t = 0;            ///< the largest |t| of the components' mean errors
  double motion_t_threshold = 0;  ///< the sign-flip null's (1 - alpha) quantile of it
  double motion_p_value = 1;
  double position_bias_mm = 0;   ///< the larger of |mean (x, y)| and |mean (along, across)|
  double yaw_bias_deg = 0;       ///< |mean yaw error|
  double position_floor_mm = 0;  ///< kappa x mean travel of a fit phase (hold's error)
  /// kappa x mean rotation of a fit phase, at least the turn that moves the outline by the position floor
  double yaw_floor_deg = 0;
  bool motion_unexplained = false;
  /// How the floors were derived.
  std::string basis;
  /// Why a part was not tested (too few samples or phases); empty when both were.
  std::string note;
  /// "explained" or "unexplained residual: <size with units>".
  std::string verdict() const;
};

/// A generic signature of missing physics and how much of an unexplained residual it accounts for: a hint where to
/// look, not a finding.
struct ResidualHint {
  std::string signature;          ///< e.g. "world_force"
  std::string description;        ///< the physics it stands for
  double share = 0;               ///< R^2 of this signature alone on the residual [-]
  double share_of_structure = 0;  ///< share / the R^2 of all signatures together [-]
};

/// One group of signature columns, as EffectColumns: [column][push] (n x 3 each, as the observer sees it).
struct ResidualSignature {
  std::string name, description;
  EffectColumns columns;
};

/// The generic signatures on `pushes`: a constant force in the world frame; friction depending on the sliding
/// direction in the body frame; speed (drag, and friction growing with speed); travel; time since contact; the tip's
/// motion relative to the object (penetration and its rate); the force's rate; the push force's moment about a point
/// shifted in the body frame (lever arm; its force the one the motion implies, m a less the support's Coulomb
/// friction with `friction_coefficient`).
std::vector<ResidualSignature> residual_signatures(const std::vector<DiagnosisPush>& pushes,
                                                   double friction_coefficient);

struct AdequacyOptions {
  int replicates = 199;
  double block_s = kAdequacyBlock_s;  ///< bootstrap block length [s]
  /// A size counts when it exceeds its floor by this many of its standard errors (as an effect's amount must:
  /// DiagnosisOptions::floor_margin_std).
  double floor_margin_std = 1.0;
  /// The same for the force part's structure (kAdequacyStructureMargin).
  double structure_margin_std = 1.0;
  double alpha = 0.01;
  std::uint64_t seed = 0x5eed;  ///< fixed: the same data give the same verdict
  /// Make the force part invariant to each push's own sensor zero (see sensor_zero_columns()); false: the zeros
  /// are taken as recorded.
  bool sensor_zeros = true;
  /// The rig's known push-to-push spread of the sensor zero [N per axis], for the rest part (rest_force_fit).
  double sensor_zero_spread_N = 0;
};

/// The force part and the hints. `model` are the corrected model's columns in the friction base (every one whose
/// amount the residual still carries: the friction law, its refinements, the found force laws). Fills the force
/// fields of `adequacy` and returns the hints, largest share first (every signature, whatever the verdict).
std::vector<ResidualHint> test_residual_structure(const std::vector<DiagnosisPush>& pushes,
                                                  const std::vector<const EffectColumns*>& model,
                                                  const FloorContext& context, const AdequacyOptions& options,
                                                  ModelAdequacy& adequacy);

/// The rest part: fills the rest fields of `adequacy` from the clear rests of `pushes` (samples_without_contact with
/// `shared_rest_force_N`), against the force floor (FloorContext) and the search's `bic_threshold`.
void test_rest_force(const std::vector<SynchronisedPush>& pushes, const Eigen::Vector2d& shared_rest_force_N,
                     const FloorContext& context, double bic_threshold, const AdequacyOptions& options,
                     ModelAdequacy& adequacy);

/// The contact part's requirements: a push's slope needs this many samples in contact and this spread of the
/// normal force (standard deviation) [N] to resolve it; the part needs this many pushes with a slope.
inline constexpr int kMinContactSamples = 20;
inline constexpr double kMinContactForceSpread_N = 0.2;
inline constexpr int kMinContactPushes = 3;

/// One push's contact compliance [m/N]: the least-squares slope of the recorded rod's penetration into the outline
/// on the force's component into the object (see above); empty without an outline or without kMinContactSamples
/// samples in contact spanning kMinContactForceSpread_N.
std::optional<double> contact_compliance_m_N(const SynchronisedPush& push);
/// The slopes of contact_compliance_m_N of those of `pushes` that resolve one, in their order [m/N].
std::vector<double> contact_compliance_slopes_m_N(const std::vector<SynchronisedPush>& pushes);

/// The contact part: fills the contact fields of `adequacy` from `pushes` against kappa x context.travel_m.
void test_contact_compliance(const std::vector<SynchronisedPush>& pushes, const FloorContext& context,
                             const AdequacyOptions& options, ModelAdequacy& adequacy);

/// One fit phase's signed mean error of the corrected model.
struct PhaseBias {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  ///< mean (predicted - measured) x, y [m], world
  double yaw_rad = 0;
  /// Unit direction of the measured travel over the phase (zero when it moved less than 1 mm).
  Eigen::Vector2d travel_direction = Eigen::Vector2d::Zero();
};

/// The motion part: fills the motion fields of `adequacy`. `hold_position_mm`, `hold_yaw_deg`: the mean errors of
/// `hold` on the same phases (how far the object moves); `kappa` the relevance fraction. The yaw floor is kappa of
/// hold's yaw error, but at least the yaw that moves a point at `radius_of_gyration_m` by the position floor.
void test_motion_bias(const std::vector<PhaseBias>& phases, double hold_position_mm, double hold_yaw_deg, double kappa,
                      double radius_of_gyration_m, const AdequacyOptions& options, ModelAdequacy& adequacy);

}  // namespace pushpred
