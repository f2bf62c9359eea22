#pragma once
// Coulomb friction between a planar rigid object and its support, written once for the simulator, the prediction
// model and the diagnosis's friction laws.
//
// The law: a point of the object sliding at v under a friction force of magnitude F = mu N [N] feels
//     f = -F v / sqrt(|v|^2 + eps^2),
// regularised over the speed eps [m/s] so that the dynamics stay smooth: f -> -F v / |v| for |v| >> eps and
// f -> 0 at rest. Over a footprint (mechanics/outline.hpp: area elements) each element i at r_i from a reference
// point moves at v + omega x r_i and carries its own F_i; the wrench is the sum of the elements' forces and of
// their moments about the reference point.
//
// Frames: none is imposed; every result is in the frame its inputs are given in (world or body, the same for the
// twist and the offsets). Units SI: m, m/s, rad/s, N, N m. Nothing here allocates: right-hand sides call it.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>

#include "pushpred/mechanics/outline.hpp"

namespace pushpred {

/// Velocity [m/s] of the point at `offset_m` from a reference point of a rigid body whose reference point moves
/// at `velocity_m_s` and which turns at `omega_rad_s`: v + omega x r.
inline Eigen::Vector2d rigid_point_velocity(const Eigen::Vector2d& velocity_m_s, double omega_rad_s,
                                            const Eigen::Vector2d& offset_m) {
  return {velocity_m_s.x() - omega_rad_s * offset_m.y(), velocity_m_s.y() + omega_rad_s * offset_m.x()};
}

/// The moment [N m] of the force `force_N` applied at `offset_m` about the reference point: r x f.
inline double planar_moment(const Eigen::Vector2d& offset_m, const Eigen::Vector2d& force_N) {
  return offset_m.x() * force_N.y() - offset_m.y() * force_N.x();
}

/// Regularised Coulomb friction [N] on a point sliding at `velocity_m_s` with friction force magnitude
/// `sliding_force_N` (mu N): -F v / sqrt(|v|^2 + eps^2), eps = `regularisation_m_s`.
inline Eigen::Vector2d regularised_coulomb_force(const Eigen::Vector2d& velocity_m_s, double sliding_force_N,
                                                 double regularisation_m_s) {
  return -(sliding_force_N /
           std::sqrt(velocity_m_s.squaredNorm() + regularisation_m_s * regularisation_m_s)) * velocity_m_s;
}

/// The surface's sliding speed s = sqrt(|v|^2 + c^2 omega^2 + eps^2) [m/s] of ellipsoidal_limit_surface_wrench below
/// (eps = 0: the twist's own speed on the surface).
inline double limit_surface_sliding_speed(const Eigen::Vector2d& velocity_m_s, double omega_rad_s,
                                          double torque_ratio_m, double regularisation_m_s) {
  const double c2 = torque_ratio_m * torque_ratio_m;
  return std::sqrt(velocity_m_s.squaredNorm() + c2 * omega_rad_s * omega_rad_s +
                   regularisation_m_s * regularisation_m_s);
}

/// The ellipsoidal limit surface (Lee & Cutkosky 1991; Howe & Cutkosky 1996): the support's friction wrench on an
/// object sliding with velocity `velocity_m_s` (v, of the centre of friction) and yaw rate `omega_rad_s`, for the
/// largest friction force F = mu N `sliding_force_N` [N] and the ratio c `torque_ratio_m` [m] of the largest
/// torque about the centre of friction to F:
///     f = -F v / s,   m = -F c^2 omega / s,   s = sqrt(|v|^2 + c^2 omega^2 + eps^2),
/// eps = `regularisation_m_s`. The wrench lies on |f|^2 + (m / c)^2 = F^2 (up to the regularisation) with the twist
/// normal to it. For c = 0 it is regularised_coulomb_force on the whole body (no torque). Returns [f_x [N], f_y [N],
/// m [N m]] in the twist's frame. The one formula of the prediction model's Coulomb term, the quasi-static model's
/// slide to rest and (to come) the diagnosis's limit-surface friction.
inline Eigen::Vector3d ellipsoidal_limit_surface_wrench(const Eigen::Vector2d& velocity_m_s, double omega_rad_s,
                                                        double sliding_force_N, double torque_ratio_m,
                                                        double regularisation_m_s) {
  const double k =
      sliding_force_N / limit_surface_sliding_speed(velocity_m_s, omega_rad_s, torque_ratio_m, regularisation_m_s);
  return {-k * velocity_m_s.x(), -k * velocity_m_s.y(), -k * (torque_ratio_m * torque_ratio_m) * omega_rad_s};
}

/// The largest friction force F [N] of the ellipsoidal limit surface of ratio `torque_ratio_m` (c) through the
/// wrench (f, m): sqrt(|f|^2 + (m / c)^2), m about the centre of friction. A quasi-statically sliding object is
/// held by a wrench on the surface, so this is mu N there. T: double or an automatic-differentiation scalar
/// (ceres::Jet, found by argument-dependent lookup of sqrt).
template <class T>
T ellipsoidal_limit_surface_force(const T& force_x_N, const T& force_y_N, const T& moment_Nm, const T& torque_ratio_m) {
  using std::sqrt;
  const T m = moment_Nm / torque_ratio_m;
  return sqrt(force_x_N * force_x_N + force_y_N * force_y_N + m * m);
}

/// The regularised Coulomb friction of `element_count` footprint elements, summed: element i is at
/// offset_m(i) (an Eigen::Vector2d) from the reference point, which moves at `velocity_m_s` while the body turns
/// at `omega_rad_s`; it slides at v_i = v + omega x r_i and carries the friction force magnitude
/// sliding_force_N(i, r_i, |v_i|^2) (mu times its load; an element with 0 is left out). Returns the force [N]
/// and the torque about the reference point [N m]: [f_x, f_y, m].
template <class Offset, class SlidingForce>
Eigen::Vector3d footprint_friction_wrench(std::size_t element_count, Offset&& offset_m,
                                          const Eigen::Vector2d& velocity_m_s, double omega_rad_s,
                                          double regularisation_m_s, SlidingForce&& sliding_force_N) {
  Eigen::Vector3d wrench = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < element_count; ++i) {
    const Eigen::Vector2d r = offset_m(i);
    const Eigen::Vector2d v = rigid_point_velocity(velocity_m_s, omega_rad_s, r);
    const double force = sliding_force_N(i, r, v.squaredNorm());
    if (force == 0) continue;
    const Eigen::Vector2d f = regularised_coulomb_force(v, force, regularisation_m_s);
    wrench(0) += f.x();
    wrench(1) += f.y();
    wrench(2) += planar_moment(r, f);
  }
  return wrench;
}

/// c for a uniform pressure over `footprint` about `centre_m` (body frame): the mean distance of the footprint's
/// area from the centre, M_max / F_max of Coulomb friction integrated over it. For a square of side a it is
/// a (sqrt 2 + ln(1 + sqrt 2)) / 6 = 0.3826 a.
double uniform_pressure_torque_ratio(const Footprint& footprint, const Eigen::Vector2d& centre_m);

/// The support's friction wrench [f_x, f_y [N], m [N m]] of Coulomb friction integrated over `footprint` (uniform
/// pressure carrying `normal_force_N`, coefficient mu) for the twist (v of `centre_m`, omega), body frame, without
/// regularisation: the exact limit surface that an ellipsoid approximates. Returns zero for a zero twist.
Eigen::Vector3d integrated_friction_wrench(const Footprint& footprint, const Eigen::Vector2d& centre_m,
                                           double normal_force_N, double mu, const Eigen::Vector2d& velocity_m_s,
                                           double omega_rad_s);

}  // namespace pushpred
