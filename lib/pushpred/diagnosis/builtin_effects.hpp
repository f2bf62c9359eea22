#pragma once
// The candidate effects of the standard library (EffectLibrary::standard()), each a physical term the paper's
// model lacks. Regressors as in candidate_effect.hpp; m, I the shape table's mass and moment of inertia,
// g = 9.81 m/s^2, v the object velocity, omega its yaw rate, rho = sqrt(I / m) its radius of gyration.
//
// Friction of the object on the table is written with an ellipsoidal limit surface: a sliding object of twist
// (v, omega) feels the wrench  -mu m g (v, rho^2 omega) / s,  s = sqrt(|v|^2 + rho^2 omega^2 + v_reg^2),
// which is Coulomb friction (magnitude mu m g, opposing the velocity) for translation and its counterpart for
// rotation; v_reg (kFrictionRegularisation_m_s) keeps it smooth at rest, where the observer's velocity is noise.
//
// - time_offset [s] (direct; corrects data): the force stream lags the pose by tau, f_rec(t) = f(t - tau).
//   Then d_hat carries Q(f - f_rec) ~ tau (Q u)'. Found by a search over tau against the Coulomb law (direct);
//   with three or more pushes, the pushes' own delays must agree (their spread bounds the standard error and the
//   score). Applied by reading the force stream tau later.
// - force_offset [N] (direct; corrects data): the sensor's fx, fy read a bias b. Estimated from the samples
//   before the tip moves on pushes whose rod rests clear of the object (samples_without_contact: a preload is no
//   bias), where the true force is zero; scored by the same BIC on those
//   samples (model: zero mean vs mean b). Applied by removing b.
// - viscous_friction [1/s]: drag -c (m v, I omega) (uniform drag per unit mass over the footprint).
// - coulomb_friction [-]: the limit-surface friction above with coefficient mu: friction that opposes the
//   velocity, so the object slows and stops when the push ends, where beta u + eps would not stop it.
// - friction_torque [-] (base model): the support's friction torque scaled by (mu + k) / mu, a pressure that
//   loads the rim or the middle more than a uniform one; a nuisance of the friction base, fitted beside mu when
//   the data resolve it.
// - stribeck_friction [-]: extra friction at low speed, mu_s exp(-(s / v_s)^2) times the Coulomb shape; v_s is
//   chosen on a grid (5, 10, 20, 40 mm/s).
// - position_friction [1/m]: the support's friction coefficient changing along the way, mu + g s(r), s(r) =
//   max(0, |r - r0| - s0) [m] the distance the tracked centre has travelled beyond an onset s0 from the push's first
//   measured position r0 (a table whose friction changes where the object slides: a patch of other friction that the
//   object's leading edge reaches after s0, and that carries more of the footprint as it slides on; push-relative,
//   so pushes in any direction share it). g is in mu's unit per metre (the relative gradient is g / mu); the
//   regressor, the law's derivative in g, is s(r) times the unit Coulomb law's force (x, y [N per unit mu]); its
//   torque is left out: a friction that differs under part of the footprint turns the object by a torque that
//   depends on which part, which the travel does not tell. s0 is chosen on a grid (0, 5, 10 mm: s0 = 0 is a uniform
//   gradient along the travel).
// - com_offset [m]: the mass centre sits at delta (body frame) from the tracked centre, so the pusher's torque
//   about it is u_theta - (R(theta) delta) x f_C; rotation-channel regressors -(R(theta) e_x) x f_C and
//   -(R(theta) e_y) x f_C (the torque error of a wrong lever arm).
// - inertia_mismatch [-] (regression; corrects data): true mass and inertia (1 + theta) times nominal; the
//   observer then reads d_hat = Q d - theta M (Q y)''; regressor -M (Q y)'' (the observer's total force and
//   torque). Applied by scaling the nominal mass and inertia; reported as the factor 1 + theta.
// - initial_velocity (prediction): each prediction phase starts from the observer's velocity instead of rest
//   (the paper starts at rest because velocity is not measured; the observer estimates it).
// - quasi_static [N] (prediction): the quasi-static push law replaces the relation in the prediction
//   (corrected_prediction.hpp, QuasiStaticPushTerm); the stop fraction is chosen on a grid.
// - pusher_stop (prediction; refines quasi_static): the quasi-static push also needs the pusher to move, its
//   planned tip speed (prediction/planned_force.hpp, PlannedTipVelocity) above a stop speed of 5 mm/s: a pusher
//   that stops but keeps pressing with a force near the law's stop force no longer drives the object.
#include <memory>

#include "pushpred/diagnosis/candidate_effect.hpp"
#include "pushpred/mechanics/gravity.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// v_reg of the limit-surface friction [m/s].
inline constexpr double kFrictionRegularisation_m_s = 5e-4;

std::unique_ptr<DataCorrectionEffect> make_time_offset_effect();
std::unique_ptr<DataCorrectionEffect> make_force_offset_effect();
/// The force the sensor reads where nothing touches, shared by `pushes` (their rests clear of the object,
/// samples_without_contact with `shared_rest_force_N`): theta the bias b = -mean recorded f_C [N, world frame], its
/// covariance, the score (Wald statistic less 2 ln N_eff; -inf with fewer than two such pushes, which cannot tell a
/// shared bias from one push's own zero) and the pushes that rest clear. The mean's variance per axis is at least
/// sensor_zero_spread_N^2 / P over P clear rests (the rig's known zero spread, DiagnosisOptions); where the rests'
/// means spread beyond what that spread and their noise allow, the Wald statistic is replaced by the chi^2_2 statistic
/// of the same tail probability under F(2, 2 (P - 1)). force_offset's test, and the adequacy test's rest part.
DirectFit rest_force_fit(const std::vector<const SynchronisedPush*>& pushes, const Eigen::Vector2d& shared_rest_force_N,
                         double sensor_zero_spread_N = 0);
std::unique_ptr<ForceLawEffect> make_viscous_friction_effect();
std::unique_ptr<ForceLawEffect> make_coulomb_friction_effect();
std::unique_ptr<ForceLawEffect> make_friction_torque_effect();
std::unique_ptr<ForceLawEffect> make_stribeck_friction_effect();
std::unique_ptr<ForceLawEffect> make_position_friction_effect();
std::unique_ptr<ForceLawEffect> make_com_offset_effect();
std::unique_ptr<DataCorrectionEffect> make_inertia_mismatch_effect();
std::unique_ptr<PredictionStructureEffect> make_initial_velocity_effect();
std::unique_ptr<PredictionStructureEffect> make_quasi_static_effect();
std::unique_ptr<PredictionStructureEffect> make_pusher_stop_effect();
/// The base model's prediction by the quasi-static pushing model (ModelCorrection::pushing_model).
std::unique_ptr<PredictionStructureEffect> make_pushing_model_effect();

/// Unit-coefficient Coulomb friction wrench of the object on the table (multiply by mu): force [N] and torque
/// about the tracked centre [N m], world frame, when the tracked centre is at `pose` (x, y [m], yaw [rad]) and
/// moves with twist `velocity` (x', y' [m/s], yaw' [rad/s]). For a shape with an outline, summed over the
/// footprint's area elements under uniform pressure (each element resisting its own velocity,
/// v_i / sqrt(|v_i|^2 + v_reg^2)); otherwise the ellipsoidal limit surface above. `footprint` is
/// FrictionFootprint::of(shape), resolved once by the caller (candidate_effect.hpp): no lock, no allocation, so
/// right-hand sides call this form.
Eigen::Vector3d coulomb_friction_wrench(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity,
                                        const ShapeInfo& shape, const FrictionFootprint& footprint);
/// The same with each element's share scaled by exp(-(|v_i| / v_s)^2) (ellipsoid: the sliding speed s).
Eigen::Vector3d stribeck_friction_wrench(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity,
                                         const ShapeInfo& shape, const FrictionFootprint& footprint,
                                         double speed_scale_m_s);
/// The same with each element's share scaled by its world coordinate `axis` (0: x, 1: y) minus origin_m(axis) [m].
Eigen::Vector3d position_friction_wrench(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity,
                                         const ShapeInfo& shape, const FrictionFootprint& footprint,
                                         const Eigen::Vector2d& origin_m, int axis);
/// The three laws above resolving the footprint on each call (FrictionFootprint::of: a lock and a cache look-up),
/// for one-off evaluations; not for right-hand sides.
Eigen::Vector3d coulomb_friction_wrench(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity,
                                        const ShapeInfo& shape);
Eigen::Vector3d stribeck_friction_wrench(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity,
                                         const ShapeInfo& shape, double speed_scale_m_s);
Eigen::Vector3d position_friction_wrench(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity,
                                         const ShapeInfo& shape, const Eigen::Vector2d& origin_m, int axis);
/// position_friction's onsets [m] (its setting, chosen on this grid): the travel before the friction starts to change.
const std::vector<double>& position_friction_onsets_m();
/// position_friction's travel variable [m]: how far the tracked centre at `pose` has travelled beyond `onset_m`
/// from `start_pose` (the push's first measured pose), max(0, |r - r0| - onset).
double position_friction_travel(const Eigen::Vector3d& pose, const Eigen::Vector3d& start_pose, double onset_m);
/// coulomb_friction_wrench at yaw 0 (orientation matters only for the footprint's torque arms).
Eigen::Vector3d limit_surface_friction(const Eigen::Vector3d& velocity, const ShapeInfo& shape);
/// s / 1 of the limit surface without the regulariser: sqrt(|v|^2 + rho^2 omega^2) [m/s].
double sliding_speed(const Eigen::Vector3d& velocity, const ShapeInfo& shape);

}  // namespace pushpred
