#pragma once
// The classical quasi-static pushing model (Mason 1986; Lynch, Tanaka & Mason 1992; Lynch & Mason 1996), driven
// by the pusher's planned motion, with the slide to rest after the push, as a continuous system on CVODE.
//
// Frames, signs and units (SI), stated once for the model:
// - {R}, world: as preprocessing/synchronised_push.hpp. The body frame is the shape table's (origin at the tracked
//   centre, reading/shape_table.hpp). The centre of friction (CoF) is the mass centre `shape.centroid_m` (body
//   frame): a pressure distribution that holds the object in moment balance puts its centre there.
// - State (6): [x, y, theta] the tracked centre's pose in {R} (yaw counter-clockwise), [vx, vy] the CoF's
//   velocity in {R} [m/s], omega the yaw rate [rad/s].
// - Contact: the rod (a disk of radius r = kPusherRadius_m + contact_offset_m) with centre on the planned tip
//   path p(t). With q = R^T (p - origin) the rod centre in the body frame, the outline's closest point, its
//   outward normal n_out and signed distance d give the penetration pen = r - d; n = -n_out (world) is the
//   inward normal, t = (-n_y, n_x) the tangent, rc the contact point relative to the CoF (world),
//   rp = (-rc_y, rc_x) (so that rc x f = rp . f).
//
// Equations:
// - Limit surface (ellipsoidal): the support's friction wrench (f, m) on a sliding object lies on
//   |f|^2 / F^2 + m^2 / (c F)^2 = 1 with F = mu_s m g and c [m] the ratio of maximum torque to maximum force;
//   the twist is normal to it: v ~ f, omega ~ m / c^2.
// - Pushing with velocity v_p at the contact (sticking, Lynch et al. 1992): a force f at rc moves the contact
//   point with A f, A = I + rp rp^T / c^2. Sticking needs f = A^-1 v_p inside the friction cone
//   |f . t| <= mu_p f . n; then the CoF moves with v = A^-1 v_p and omega = rp . v / c^2 (the motion cone).
//   Otherwise the contact slides and f lies on the cone's edge f_e = n + s mu_p t (s the sign of f . t):
//   v = k f_e, omega = k rp . f_e / c^2 with k = (n . v_p) / (n . A f_e), so the normal velocities agree.
//   No push when n . v_p <= 0 (the pusher leaves the surface).
// - The pusher velocity at the contact is the planned tip velocity plus a gap keeper that holds the
//   penetration at `contact_band_m` plus the contact's give s_c f_n (s_c = `contact_compliance_m_N`, f_n the normal
//   part of the force on the limit surface, F (v . n) / sqrt(|v|^2 + c^2 omega^2) for the pushed twist): v_p = v_tip +
//   n (pen - contact_band - s_c f_n) / gap_time.
// - Dynamics: with w in [0, 1] the push's weight (0 when the tip is out of contact, the planned tip speed is below
//   `stop_speed_m_s`, or n . v_p <= 0; a smooth step of pen over [0, contact_band] otherwise):
//     v' = w (v_qs - v) / tau + (1 - w) f_s / m,   omega' = w (omega_qs - omega) / tau + (1 - w) m_s / I,
//   tau = `relaxation_s` (the quasi-static motion is approached with this time constant), and (f_s, m_s) the limit
//   surface's friction opposing the twist: f_s = -F v / s, m_s = -F c^2 omega / s, s = sqrt(|v|^2 + c^2 omega^2 +
//   eps^2). Free, a translating object slides to rest in v^2 / (2 mu_s g).
//
// Assumptions (docs/prediction.md says where they fail): a flat support with uniform-ish pressure (the limit
// surface an ellipsoid), quasi-static pushing (inertia only in the slide to rest), point contact with Coulomb
// friction, a pusher that follows its plan (rigid, or giving way along the contact's normal by s_c f_n), the object's
// outline known (or one of the local outlines of quasi_static_identification.hpp where the shape table lists none).
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/mechanics/contact_outline.hpp"
#include "pushpred/mechanics/gravity.hpp"
#include "pushpred/mechanics/pressure_limit_surface.hpp"
#include "pushpred/mechanics/support_friction.hpp"
#include "pushpred/prediction/planned_force.hpp"
#include "pushpred/prediction/prediction_system.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/systems/continuous_system.hpp"
#include "pushpred/systems/cvode_integrator.hpp"

namespace pushpred {

/// The parameters of the model. The first four are what identification estimates; the rest are numerical
/// constants of the continuous system, not physics.
struct QuasiStaticParameters {
  double pusher_friction = 0.25;   ///< mu_p, rod on object [-]
  double torque_ratio_m = 0.03;    ///< c = max torque / max force of the support [m]
  double support_friction = 0.3;   ///< mu_s, object on support [-]
  double contact_offset_m = 0;     ///< added to the rod radius: the measured rod-outline distance in contact
  double rod_radius_m = kPusherRadius_m;
  double gravity_m_s2 = kGravity_m_s2;
  double stop_speed_m_s = 2e-3;    ///< a planned tip slower than this does not push
  /// tau: how fast the object's velocity follows the quasi-static one while pushed. Half the rig's measured
  /// 5-95 % speed ramp (0.049 s, docs/simulator.md; a first-order lag of tau has the mean delay of a ramp of 2 tau):
  /// the object keeps its measured velocity at a phase's start for that long and comes up to the pusher's speed
  /// no faster than the rig changes speed (docs/prediction.md, "Fit half and held-out half").
  double relaxation_s = 0.025;
  double contact_band_m = 2e-4;    ///< the push's weight rises over this penetration
  /// The contact's compliance [m/N]: the rod sinks into the outline by this times the normal force (arm, sensor
  /// and contact giving way), so the gap keeper holds the penetration at contact_band + compliance f_n, f_n the
  /// normal part of the force the limit surface carries. 0: a rigid contact.
  double contact_compliance_m_N = 0;
  double gap_time_s = 0.05;        ///< the gap keeper's time constant
  double creep_speed_m_s = 1e-4;   ///< eps of the friction's regularisation
  /// Throws InputError naming the parameter that is not positive and finite (contact_offset_m may be negative).
  void validate() const;
};

/// How the contact behaves at one instant.
enum class ContactMode { None, Sticking, SlidingLeft, SlidingRight };  ///< Left: sliding along +t
const char* contact_mode_name(ContactMode mode);

/// The quasi-static motion of the object under a push: CoF velocity [m/s] and yaw rate [rad/s] in the frame the
/// inputs are given in (any frame: the relations are rotation-invariant). T is double, or ceres::Jet where the
/// identification differentiates the motion with respect to mu_p, c and the CoF.
template <class T>
struct BasicQuasiStaticMotion {
  Eigen::Matrix<T, 2, 1> velocity_m_s = Eigen::Matrix<T, 2, 1>::Zero();
  T omega_rad_s = T(0);
  ContactMode mode = ContactMode::None;
};
using QuasiStaticMotion = BasicQuasiStaticMotion<double>;

/// The motion of the object pushed at `contact_from_cof_m` (rc) with inward unit normal `inward_normal` by a
/// pusher moving at `pusher_velocity_m_s` (v_p), for friction mu_p and ratio c (equations above). No allocation.
QuasiStaticMotion quasi_static_motion(const Eigen::Vector2d& contact_from_cof_m, const Eigen::Vector2d& inward_normal,
                                      const Eigen::Vector2d& pusher_velocity_m_s, double pusher_friction,
                                      double torque_ratio_m);

/// quasi_static_motion for a scalar type T that carries derivatives (ceres::Jet) through rc, mu_p and c: the
/// identification's residual differentiates it exactly, where difference quotients cost five evaluations per
/// sample and an error of their own. With T = double it is quasi_static_motion, operation for operation. The
/// contact mode is chosen on the values, so the derivative is that of the mode the values are in.
template <class T>
BasicQuasiStaticMotion<T> quasi_static_motion_of(const Eigen::Matrix<T, 2, 1>& contact_from_cof_m,
                                                 const Eigen::Vector2d& n, const Eigen::Vector2d& vp,
                                                 const T& pusher_friction, const T& torque_ratio_m) {
  using std::abs;
  BasicQuasiStaticMotion<T> m;
  const double normal_speed = n.x() * vp.x() + n.y() * vp.y();
  if (!(normal_speed > 0)) return m;
  const T rpx = -contact_from_cof_m.y(), rpy = contact_from_cof_m.x();  // rp = perp(rc)
  const T c2 = torque_ratio_m * torque_ratio_m;
  // A^-1 = I - rp rp^T / (c^2 + |rp|^2) (Sherman-Morrison).
  const T k_stick = (rpx * vp.x() + rpy * vp.y()) / (c2 + (rpx * rpx + rpy * rpy));
  const T fx = vp.x() - rpx * k_stick, fy = vp.y() - rpy * k_stick;
  const double tx = -n.y(), ty = n.x();  // t = perp(n)
  const T fn = fx * n.x() + fy * n.y(), ft = fx * tx + fy * ty;
  if (fn > 0.0 && abs(ft) <= pusher_friction * fn) {
    m.velocity_m_s << fx, fy;
    m.omega_rad_s = (rpx * fx + rpy * fy) / c2;
    m.mode = ContactMode::Sticking;
    return m;
  }
  const double s = ft >= 0.0 ? 1.0 : -1.0;
  const T s_mu = s * pusher_friction;
  const T fex = n.x() + s_mu * tx, fey = n.y() + s_mu * ty;  // f_e = n + s mu_p t
  const T k_rate = (rpx * fex + rpy * fey) / c2;
  const T normal_rate = n.x() * (fex + rpx * k_rate) + n.y() * (fey + rpy * k_rate);  // n . A f_e
  if (!(normal_rate > 1e-12)) return m;  // the edge cannot push this way (not for convex contact geometry)
  const T k = normal_speed / normal_rate;
  m.velocity_m_s << k * fex, k * fey;
  m.omega_rad_s = k * (rpx * fex + rpy * fey) / c2;
  m.mode = s > 0 ? ContactMode::SlidingLeft : ContactMode::SlidingRight;
  return m;
}

/// quasi_static_motion on the limit surface of the support's pressure (mechanics/pressure_limit_surface.hpp) in place
/// of the ellipsoid, with no ratio c. With u(f) = (f, rc x f) the wrench of a pusher force f at rc, the twist is along
/// grad H(u) and the contact point moves with G^T grad H(G f) (G the map f -> u):
/// - sticking: f solves G^T grad H(G f) = v_p (Newton on the convex H(G f) - v_p . f, from `force_hint` when given:
///   the previous step's f, updated), kept when inside the friction cone of mu_p;
/// - sliding: f on the cone's edge f_e = n + s mu_p t, the twist k grad H(G f_e) with k matching the normal speeds.
/// Inputs in the surface's frame (the body frame), rc from its centre. No allocation.
QuasiStaticMotion quasi_static_motion_on(const PolynomialLimitSurface& surface,
                                         const Eigen::Vector2d& contact_from_cof_m,
                                         const Eigen::Vector2d& inward_normal,
                                         const Eigen::Vector2d& pusher_velocity_m_s, double pusher_friction,
                                         Eigen::Vector2d* force_hint = nullptr);

/// The planned tip path: the planned tip velocity (planned_force.hpp) integrated from the tip's position at its
/// start; piecewise linear, exact for the held velocity.
class PlannedTipPath {
 public:
  PlannedTipPath(PlannedTipVelocity velocity, const Eigen::Vector2d& start_m);
  /// Position and velocity at t as seen from inside [lo, hi] (see SampledSignal::evaluate_within). No allocation.
  void evaluate_within(double t_s, double lo_s, double hi_s, Eigen::Vector2d& position_m,
                       Eigen::Vector2d& velocity_m_s) const;
  const PlannedTipVelocity& velocity() const { return velocity_; }

 private:
  PlannedTipVelocity velocity_;
  Eigen::MatrixX2d waypoint_m_;  // position at each sample time
};

/// What the object and its support are, for the model.
struct QuasiStaticObject {
  double mass_kg = 1;
  double inertia_kgm2 = 1e-3;                                ///< about the CoF
  Eigen::Vector2d centre_of_friction_m = Eigen::Vector2d::Zero();  ///< body frame
  std::shared_ptr<const ContactOutline> outline;
  /// The support's friction while the object is not pushed, as generalized forces on the tracked centre (a friction
  /// law fitted elsewhere, e.g. by the diagnosis, with the planned input zero), each scaled by s / sqrt(s^2 + eps^2)
  /// (s as in the limit surface, eps = creep_speed_m_s) so that it fades smoothly at rest. Empty: the limit
  /// surface's Coulomb friction of mu_s. Terms must not allocate.
  std::vector<std::shared_ptr<const GeneralizedForceTerm>> free_slide_terms;
};

class QuasiStaticPushSystem final : public ContinuousSystem {
 public:
  /// Throws InputError for bad parameters, a non-positive mass or inertia, or no outline.
  QuasiStaticPushSystem(QuasiStaticObject object, QuasiStaticParameters parameters, PlannedTipPath path);
  int state_size() const override { return 6; }
  /// The planned tip as held inside `interval`; the free-slide terms get the same interval.
  void derivative(const IntegrationInterval& interval, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                  Eigen::Ref<Eigen::VectorXd> xdot) const override;
  /// Stiff: the velocity relaxes to the quasi-static one with tau (25 ms) and the support friction, regularised
  /// over 0.1 mm/s, stops a free object at mu g / creep speed (3e4 1/s): BDF (difference-quotient Jacobian).
  bool stiff() const override { return true; }
  std::vector<double> discontinuities(double t0, double t1) const override;

  /// What the push does at (t, x): the push's weight w, the quasi-static motion and the penetration [m]; the
  /// planned tip as held from t on.
  struct Push {
    double weight = 0;
    double penetration_m = 0;
    QuasiStaticMotion motion;
  };
  Push push_at(double t, const Eigen::Ref<const Eigen::VectorXd>& x) const;

  /// The state with tracked pose `pose` and the tracked centre moving with `velocity` (x, y [m/s], yaw rate).
  Eigen::VectorXd state_from(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity) const;

 private:
  Push push_within(double t, double lo, double hi, const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// F = mu_s m g [N], the limit surface's largest friction force.
  double sliding_force_N() const { return p_.support_friction * object_.mass_kg * p_.gravity_m_s2; }

  QuasiStaticObject object_;
  QuasiStaticParameters p_;
  PlannedTipPath path_;
};

/// The tolerances the model is integrated with by default: rtol 1e-6, atol 1e-9 (metres, radians and their rates),
/// looser than the shared default (1e-8, 1e-10), which the observer's agreement with its exact discretisation set.
/// The model has no exact solution; against a 1e-11 / 1e-13 integration these moved the predictions of the 77 ABS
/// pushes by at most 1.5e-4 mm and 1.4e-4 deg (the shared default: 2.5e-6 mm), under a five-hundredth of the pose
/// measurement's noise, and cut the integration's steps (docs/performance.md, "What the defaults integrate with").
IntegratorOptions quasi_static_integrator_options();

/// Predicted tracked poses (n x 3) at `output_times_s` from `pose0` and tracked-centre velocity `velocity0` at the
/// path's start.
Eigen::MatrixX3d predict_quasi_static_poses(const QuasiStaticObject& object, const QuasiStaticParameters& parameters,
                                            const PlannedTipPath& path, const Eigen::Vector3d& pose0,
                                            const Eigen::Vector3d& velocity0, const Eigen::VectorXd& output_times_s,
                                            const IntegratorOptions& integrator = quasi_static_integrator_options());

}  // namespace pushpred
