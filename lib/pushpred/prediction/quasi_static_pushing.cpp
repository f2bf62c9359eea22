#include "pushpred/prediction/quasi_static_pushing.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

Eigen::Vector2d perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

}  // namespace

void QuasiStaticParameters::validate() const {
  require_positive_finite(pusher_friction, "quasi-static model: pusher friction mu_p");
  require_positive_finite(torque_ratio_m, "quasi-static model: limit-surface ratio c");
  require_positive_finite(support_friction, "quasi-static model: support friction mu_s");
  require_positive_finite(rod_radius_m, "quasi-static model: rod radius");
  require_positive_finite(gravity_m_s2, "quasi-static model: gravity");
  require_positive_finite(stop_speed_m_s, "quasi-static model: stop speed");
  require_positive_finite(relaxation_s, "quasi-static model: relaxation time");
  require_positive_finite(contact_band_m, "quasi-static model: contact band");
  require_positive_finite(gap_time_s, "quasi-static model: gap time");
  require_not_negative_finite(contact_compliance_m_N, "quasi-static model: contact compliance");
  require_positive_finite(creep_speed_m_s, "quasi-static model: creep speed");
  if (!std::isfinite(contact_offset_m) || !(rod_radius_m + contact_offset_m > 0))
    throw InputError("quasi-static model: contact offset must be finite and keep the rod radius positive");
}

const char* contact_mode_name(ContactMode mode) {
  switch (mode) {
    case ContactMode::None: return "none";
    case ContactMode::Sticking: return "sticking";
    case ContactMode::SlidingLeft: return "sliding_left";
    case ContactMode::SlidingRight: return "sliding_right";
  }
  return "?";
}

QuasiStaticMotion quasi_static_motion(const Eigen::Vector2d& rc, const Eigen::Vector2d& n, const Eigen::Vector2d& vp,
                                      double mu_p, double c) {
  return quasi_static_motion_of<double>(rc, n, vp, mu_p, c);
}

QuasiStaticMotion quasi_static_motion_on(const PolynomialLimitSurface& surface, const Eigen::Vector2d& rc,
                                         const Eigen::Vector2d& n, const Eigen::Vector2d& vp, double mu_p,
                                         Eigen::Vector2d* force_hint) {
  QuasiStaticMotion m;
  const double normal_speed = n.dot(vp);
  if (!(normal_speed > 0)) return m;
  const double rho = surface.torque_ratio_m();
  const Eigen::Vector2d rp = perp(rc);
  Eigen::Matrix<double, 3, 2> G;  // f -> u = (f, rc x f / rho)
  G << 1, 0, 0, 1, rp.x() / rho, rp.y() / rho;
  // Sticking: minimise H(G f) - vp . f. Start from the previous force, or from the ellipsoid's answer for c = rho,
  // scaled so that the contact speed along vp matches (H is homogeneous of degree 4).
  Eigen::Vector2d f;
  if (force_hint && force_hint->squaredNorm() > 0) {
    f = *force_hint;
  } else {
    f = vp - rp * (rp.dot(vp) / (rho * rho + rp.squaredNorm()));
  }
  if (!force_hint || force_hint->squaredNorm() == 0) {
    const double along = (G.transpose() * surface.scaled_gradient(G * f)).dot(vp);
    if (along > 0) f *= std::cbrt(vp.squaredNorm() / along);
  }
  Eigen::Vector3d g;
  Eigen::Matrix3d h;
  const double scale2 = vp.squaredNorm();
  for (int iteration = 0; iteration < 40; ++iteration) {
    const Eigen::Vector3d u = G * f;
    surface.scaled_derivatives(u, g, h);
    const Eigen::Vector2d residual = G.transpose() * g - vp;
    if (residual.squaredNorm() <= 1e-20 * scale2) break;
    const Eigen::Matrix2d hess = G.transpose() * h * G;
    const Eigen::Vector2d step = hess.inverse() * residual;  // closed form for 2 x 2, positive definite
    // A short Newton step is taken whole (quadratic convergence near the answer); a long one backtracks on the
    // convex objective.
    double alpha = 1;
    if (step.squaredNorm() > 0.01 * f.squaredNorm()) {
      const double objective = surface.scaled_value(u) - vp.dot(f);
      for (int k = 0; k < 30; ++k, alpha *= 0.5) {
        const Eigen::Vector2d trial = f - alpha * step;
        if (surface.scaled_value(G * trial) - vp.dot(trial) <= objective - 1e-4 * alpha * residual.dot(step)) break;
      }
    }
    f -= alpha * step;
    // A whole step this short leaves an error of the order of its square (quadratic convergence): done.
    if (alpha == 1 && step.squaredNorm() <= 1e-10 * f.squaredNorm()) break;
  }
  if (force_hint) *force_hint = f;
  const Eigen::Vector2d t = perp(n);
  const double fn = f.dot(n), ft = f.dot(t);
  if (fn > 0 && std::abs(ft) <= mu_p * fn) {
    const Eigen::Vector3d twist = surface.scaled_gradient(G * f);
    m.velocity_m_s = twist.head<2>();
    m.omega_rad_s = twist(2) / rho;
    m.mode = ContactMode::Sticking;
    return m;
  }
  const double s = ft >= 0 ? 1.0 : -1.0;
  const Eigen::Vector2d fe = n + s * mu_p * t;
  const Eigen::Vector3d twist = surface.scaled_gradient(G * fe);
  const double normal_rate = n.dot(G.transpose() * twist);  // the contact point's normal speed per unit k
  if (!(normal_rate > 1e-12)) return m;
  const double k = normal_speed / normal_rate;
  m.velocity_m_s = k * twist.head<2>();
  m.omega_rad_s = k * twist(2) / rho;
  m.mode = s > 0 ? ContactMode::SlidingLeft : ContactMode::SlidingRight;
  return m;
}

PlannedTipPath::PlannedTipPath(PlannedTipVelocity velocity, const Eigen::Vector2d& start)
    : velocity_(std::move(velocity)) {
  if (velocity_.signal.channels() != 2) throw InputError("planned tip path: the velocity needs 2 channels");
  if (!start.allFinite()) throw InputError("planned tip path: start must be finite");
  const Eigen::VectorXd& t = velocity_.signal.times();
  waypoint_m_.resize(t.size(), 2);
  waypoint_m_.row(0) = start.transpose();
  for (Eigen::Index k = 1; k < t.size(); ++k)
    waypoint_m_.row(k) = waypoint_m_.row(k - 1) + (t(k) - t(k - 1)) * velocity_.signal.values().row(k - 1);
}

void PlannedTipPath::evaluate_within(double t, double lo, double hi, Eigen::Vector2d& position,
                                     Eigen::Vector2d& velocity) const {
  velocity_.signal.evaluate_within(t, lo, hi, velocity);
  // The waypoint of the held segment: the last sample at or before the interval's start.
  const Eigen::VectorXd& times = velocity_.signal.times();
  const double inside = hi > lo ? 0.5 * (lo + hi) : t;
  Eigen::Index k = static_cast<Eigen::Index>(std::upper_bound(times.data(), times.data() + times.size(), inside) -
                                             times.data()) - 1;
  k = std::max<Eigen::Index>(k, 0);
  position = waypoint_m_.row(k).transpose() + (std::max(t, times(0)) - times(k)) * velocity;
}

QuasiStaticPushSystem::QuasiStaticPushSystem(QuasiStaticObject object, QuasiStaticParameters parameters,
                                             PlannedTipPath path)
    : object_(std::move(object)), p_(parameters), path_(std::move(path)) {
  p_.validate();
  require_positive_finite(object_.mass_kg, "quasi-static model: mass");
  require_positive_finite(object_.inertia_kgm2, "quasi-static model: inertia");
  if (!object_.outline) throw InputError("quasi-static model: no outline to push on");
}

std::vector<double> QuasiStaticPushSystem::discontinuities(double t0, double t1) const {
  return path_.velocity().signal.jumps(t0, t1);
}

Eigen::VectorXd QuasiStaticPushSystem::state_from(const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity) const {
  Eigen::VectorXd x(6);
  x.head<3>() = pose;
  const Eigen::Vector2d cof_arm = Eigen::Rotation2Dd(pose(2)) * object_.centre_of_friction_m;
  x.segment<2>(3) = velocity.head<2>() + velocity(2) * perp(cof_arm);
  x(5) = velocity(2);
  return x;
}

QuasiStaticPushSystem::Push QuasiStaticPushSystem::push_at(double t, const Eigen::Ref<const Eigen::VectorXd>& x) const {
  return push_within(t, t, t, x);
}

QuasiStaticPushSystem::Push QuasiStaticPushSystem::push_within(double t, double lo, double hi,
                                                               const Eigen::Ref<const Eigen::VectorXd>& x) const {
  Push push;
  Eigen::Vector2d tip, tip_velocity;
  path_.evaluate_within(t, lo, hi, tip, tip_velocity);
  const Eigen::Rotation2Dd R(x(2));
  const Eigen::Vector2d origin = x.head<2>();
  const Outline::Closest c = object_.outline->closest(R.inverse() * (tip - origin));
  push.penetration_m = p_.rod_radius_m + p_.contact_offset_m - c.signed_distance_m;
  if (push.penetration_m <= 0 || tip_velocity.norm() < p_.stop_speed_m_s) return push;
  const Eigen::Vector2d n = -(R * c.normal);
  const Eigen::Vector2d contact_from_cof = R * (c.point_m - object_.centre_of_friction_m);
  // The gap keeper's pusher velocity, holding the penetration at the contact band plus `give_m`.
  const auto pusher_velocity = [&](double give_m) -> Eigen::Vector2d {
    return tip_velocity + n * ((push.penetration_m - p_.contact_band_m - give_m) / p_.gap_time_s);
  };
  push.motion = quasi_static_motion(contact_from_cof, n, pusher_velocity(0), p_.pusher_friction, p_.torque_ratio_m);
  if (push.motion.mode == ContactMode::None) return push;
  if (p_.contact_compliance_m_N > 0) {
    // The pusher balances the support's friction wrench, which lies on the ellipsoid along the pushed twist whatever
    // the twist's size: its normal force is that wrench's force along -n.
    const Eigen::Vector2d& v = push.motion.velocity_m_s;
    const double omega = push.motion.omega_rad_s, c = p_.torque_ratio_m;
    const double normal_force =
        limit_surface_sliding_speed(v, omega, c, 0.0) > 0
            ? std::max(0.0, -ellipsoidal_limit_surface_wrench(v, omega, sliding_force_N(), c, 0.0).head<2>().dot(n))
            : 0.0;
    push.motion = quasi_static_motion(contact_from_cof, n, pusher_velocity(p_.contact_compliance_m_N * normal_force),
                                      p_.pusher_friction, p_.torque_ratio_m);
    if (push.motion.mode == ContactMode::None) return push;
  }
  const double s = std::min(1.0, push.penetration_m / p_.contact_band_m);
  push.weight = s * s * (3 - 2 * s);
  return push;
}

void QuasiStaticPushSystem::derivative(const IntegrationInterval& interval, double t,
                                       const Eigen::Ref<const Eigen::VectorXd>& x,
                                       Eigen::Ref<Eigen::VectorXd> xdot) const {
  const Push push = push_within(t, interval.t0_s, interval.t1_s, x);
  const Eigen::Vector2d v = x.segment<2>(3);
  const double omega = x(5);
  const double c = p_.torque_ratio_m;
  const double F = sliding_force_N();
  const Eigen::Vector3d friction = ellipsoidal_limit_surface_wrench(v, omega, F, c, p_.creep_speed_m_s);
  Eigen::Vector2d free_acceleration = friction.head<2>() / object_.mass_kg;
  double free_angular = friction(2) / object_.inertia_kgm2;
  const double w = push.weight;
  const Eigen::Vector2d cof_arm = Eigen::Rotation2Dd(x(2)) * object_.centre_of_friction_m;
  xdot.head<2>() = v - omega * perp(cof_arm);
  if (!object_.free_slide_terms.empty() && w < 1) {
    PlanarState state;
    state << x.head<3>(), xdot.head<2>(), omega;  // the tracked centre's pose and twist
    Eigen::Vector3d generalized = Eigen::Vector3d::Zero();
    for (const auto& term : object_.free_slide_terms) term->add(interval, t, state, Eigen::Vector3d::Zero(), generalized);
    // Each term fades as the limit surface's friction does: by s / sqrt(s^2 + eps^2).
    generalized *= limit_surface_sliding_speed(v, omega, c, 0.0) /
                   limit_surface_sliding_speed(v, omega, c, p_.creep_speed_m_s);
    free_acceleration = generalized.head<2>() / object_.mass_kg;
    free_angular = generalized(2) / object_.inertia_kgm2;
  }
  xdot(2) = omega;
  xdot.segment<2>(3) = w * (push.motion.velocity_m_s - v) / p_.relaxation_s + (1 - w) * free_acceleration;
  xdot(5) = w * (push.motion.omega_rad_s - omega) / p_.relaxation_s + (1 - w) * free_angular;
}

IntegratorOptions quasi_static_integrator_options() {
  IntegratorOptions o;
  o.relative_tolerance = 1e-6;
  o.absolute_tolerance = 1e-9;
  return o;
}

Eigen::MatrixX3d predict_quasi_static_poses(const QuasiStaticObject& object, const QuasiStaticParameters& parameters,
                                            const PlannedTipPath& path, const Eigen::Vector3d& pose0,
                                            const Eigen::Vector3d& velocity0, const Eigen::VectorXd& output_times,
                                            const IntegratorOptions& integrator) {
  const QuasiStaticPushSystem system(object, parameters, path);
  const Eigen::MatrixXd states =
      integrate(system, integrator, path.velocity().t0_s, system.state_from(pose0, velocity0), output_times);
  return states.leftCols<3>();
}

}  // namespace pushpred
