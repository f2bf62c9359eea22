#include "pushpred/simulation/pushed_object_system.hpp"

#include <Eigen/LU>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/nominal_inertia.hpp"
#include "pushpred/mechanics/pressure_limit_surface.hpp"
#include "pushpred/mechanics/support_friction.hpp"

namespace pushpred {
namespace {

Eigen::Matrix2d rotation(double yaw) { return Eigen::Rotation2Dd(yaw).toRotationMatrix(); }

}  // namespace

ObjectProperties ObjectProperties::nominal(const ShapeInfo& shape) {
  ObjectProperties p;
  const Eigen::Vector3d inertia = nominal_inertia(shape);  // the choice every model makes (mechanics/)
  p.mass_kg = inertia(0);
  p.inertia_kgm2 = inertia(2);
  p.mass_centre_m = shape.centroid_m;
  return p;
}

PushedObjectSystem::PushedObjectSystem(const ShapeInfo& shape, const ObjectProperties& object,
                                       const SupportFriction& support, const RodContact& contact,
                                       const PusherPath& path)
    : outline_(shape), object_(object), support_(support), contact_(contact), path_(path) {
  require_positive_finite(object.mass_kg, "object mass");
  require_positive_finite(object.inertia_kgm2, "object moment of inertia");
  if (!(support.coefficient >= 0) || !std::isfinite(support.coefficient))
    throw InputError("support friction coefficient must not be negative");
  require_positive_finite(support.regularisation_m_s, "support friction regularisation speed");
  require_positive_finite(contact.stiffness_N_m, "contact stiffness");
  require_positive_finite(contact.rod_radius_m, "rod radius");
  require_positive_finite(contact.regularisation_m_s, "contact friction regularisation speed");
  if (!(contact.damping_N_s_m >= 0) || !(contact.friction >= 0) || !(contact.damping_blend_m > 0))
    throw InputError("contact damping and friction must not be negative");
  if (!(support.viscous_per_kg >= 0)) throw InputError("viscous friction must not be negative");
  if (!(support.stribeck_excess >= 0) || !(support.stribeck_speed_m_s > 0))
    throw InputError("Stribeck excess must not be negative and its speed must be positive");
  if (!(support.patch_excess > -1))
    throw InputError("patch friction change must be above -1 (friction stays positive)");
  if (!object.mass_centre_m.allFinite()) throw InputError("mass centre must be finite");
  if (!(std::abs(support.tilt_rad) < M_PI / 2) || !support.downhill.allFinite() ||
      std::abs(support.downhill.norm() - 1) > 1e-9)
    throw InputError("support tilt must be within 90 degrees and its downhill direction a unit vector");
  if (!(support.anisotropy > 0) || !std::isfinite(support.anisotropy))
    throw InputError("friction anisotropy must be positive");
  if (!(contact.pusher_compliance_m_N >= 0) || !std::isfinite(contact.pusher_compliance_m_N))
    throw InputError("pusher compliance must not be negative");
  if (contact.pusher_compliance_m_N > 0 && (!(contact.tip_mass_kg > 0) || !(contact.tip_damping_ratio >= 0)))
    throw InputError("a compliant pusher needs a positive tip mass and a non-negative damping ratio");

  // Planar pressure p_i = 1 + g . (r_i - c) over the footprint: its centre of pressure is c + J g / A, which
  // must be the mass centre for the object to rest on the table without tipping.
  const Footprint footprint = make_footprint(outline_);
  const Eigen::Vector2d g =
      footprint.total_area_m2 * footprint.second_moment_m4.inverse() * (object.mass_centre_m - footprint.centroid_m);
  // The radial shape about the centroid (symmetric footprints keep their centre of pressure there).
  // (mechanics/pressure_limit_surface.hpp's pressure_rim_shape, clamped at zero where it would turn negative.)
  if (!(support.pressure_rim_weight >= -0.5 && support.pressure_rim_weight <= 1))
    throw InputError("pressure rim weight must be in [-0.5, 1]");
  std::vector<double> radial = pressure_rim_shape(footprint, support.pressure_rim_weight);
  for (double& r : radial) r = std::max(0.0, r);
  double total = 0;
  load_.resize(footprint.area_m2.size());
  for (size_t i = 0; i < load_.size(); ++i) {
    const double p = 1 + g.dot(footprint.centre_m[i] - footprint.centroid_m);
    if (p < 0)
      throw InputError("mass centre (" + std::to_string(object.mass_centre_m.x()) + ", " +
                       std::to_string(object.mass_centre_m.y()) +
                       ") m is too far from the footprint's centroid: the pressure under the object would turn "
                       "negative");
    load_[i] = p * footprint.area_m2[i] * radial[i];
    total += load_[i];
  }
  // A tilted support carries the normal component of the weight.
  for (auto& l : load_) l *= object.mass_kg * support.gravity_m_s2 * std::cos(support.tilt_rad) / total;
  element_from_mass_centre_.reserve(load_.size());
  for (const auto& c : footprint.centre_m) element_from_mass_centre_.push_back(c - object.mass_centre_m);
}

Eigen::VectorXd PushedObjectSystem::state_at_rest(const Eigen::Vector3d& pose) const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(state_size());
  x.head<2>() = pose.head<2>() + rotation(pose(2)) * object_.mass_centre_m;
  x(2) = pose(2);
  if (compliant()) x.segment<2>(6) = path_.start_m();  // the tip at rest where the path starts, spring relaxed
  return x;
}

Eigen::Vector2d PushedObjectSystem::tip_position_m(double t, const Eigen::Ref<const Eigen::VectorXd>& x) const {
  return compliant() ? Eigen::Vector2d(x.segment<2>(6)) : path_.position_m(t);
}

Eigen::Vector2d PushedObjectSystem::pusher_spring_force_N(double t, const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (!compliant()) return Eigen::Vector2d::Zero();
  const double k = 1 / contact_.pusher_compliance_m_N;
  const double c = 2 * contact_.tip_damping_ratio * std::sqrt(k * contact_.tip_mass_kg);
  return k * (path_.position_m(t) - x.segment<2>(6)) + c * (path_.velocity_m_s(t) - x.segment<2>(8));
}

Eigen::Vector2d PushedObjectSystem::gravity_along_support_N() const {
  return object_.mass_kg * support_.gravity_m_s2 * std::sin(support_.tilt_rad) * support_.downhill;
}

Eigen::Vector3d PushedObjectSystem::tracked_pose(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  Eigen::Vector3d pose;
  pose.head<2>() = x.head<2>() - rotation(x(2)) * object_.mass_centre_m;
  pose(2) = x(2);
  return pose;
}

RodWrench PushedObjectSystem::rod_wrench(double t, const Eigen::Ref<const Eigen::VectorXd>& x) const {
  RodWrench w;
  const Eigen::Matrix2d R = rotation(x(2));
  const Eigen::Vector2d mass_centre = x.head<2>();
  const Eigen::Vector2d origin = mass_centre - R * object_.mass_centre_m;
  w.rod_centre_m = tip_position_m(t, x);
  const Outline::Closest c = outline_.closest(R.transpose() * (w.rod_centre_m - origin));
  w.penetration_m = contact_.rod_radius_m - c.signed_distance_m;
  w.contact_point_m = origin + R * c.point_m;
  if (w.penetration_m <= 0) return w;

  const Eigen::Vector2d n = R * c.normal;  // outward normal of the object, world
  const Eigen::Vector2d tangent(-n.y(), n.x());
  const Eigen::Vector2d v_centre = x.segment<2>(3);
  const double omega = x(5);
  const Eigen::Vector2d arm = w.contact_point_m - mass_centre;
  const Eigen::Vector2d v_material = v_centre + omega * Eigen::Vector2d(-arm.y(), arm.x());
  const Eigen::Vector2d v_tip = compliant() ? Eigen::Vector2d(x.segment<2>(8)) : path_.velocity_m_s(t);
  const Eigen::Vector2d v_rel = v_tip - v_material;  // rod relative to the object's surface
  const double penetration_rate = -n.dot(v_rel);
  const double blend = std::min(1.0, w.penetration_m / contact_.damping_blend_m);
  const double normal =
      std::max(0.0, contact_.stiffness_N_m * w.penetration_m + contact_.damping_N_s_m * penetration_rate * blend);
  if (normal <= 0) return w;
  const double slip = tangent.dot(v_rel);
  const double tangential = contact_.friction * normal * slip /
                            std::sqrt(slip * slip + contact_.regularisation_m_s * contact_.regularisation_m_s);
  w.touching = true;
  w.force_on_object_N = -normal * n + tangential * tangent;
  w.torque_about_rod_Nm = planar_moment(w.contact_point_m - w.rod_centre_m, w.force_on_object_N);
  return w;
}

PlanarWrench PushedObjectSystem::support_wrench(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  const Eigen::Matrix2d R = rotation(x(2));
  const Eigen::Vector2d v_body = R.transpose() * x.segment<2>(3);
  const double omega = x(5);
  const bool stribeck = support_.stribeck_excess > 0;
  const bool patch = support_.patch_excess != 0;
  const double vs2 = support_.stribeck_speed_m_s * support_.stribeck_speed_m_s;
  // In the body frame, about the mass centre: each element's mu (Stribeck rise, patch) times its load.
  const auto sliding_force_N =
      [&](std::size_t i, const Eigen::Vector2d& r, double speed2) {
        double mu = support_.coefficient;
        if (stribeck) mu *= 1 + support_.stribeck_excess * std::exp(-speed2 / vs2);
        if (patch) {
          const Eigen::Vector2d where = x.head<2>() + R * r;
          const double inside =
              (support_.patch_radius_m + 0.5 * support_.patch_edge_m - (where - support_.patch_centre_m).norm()) /
              support_.patch_edge_m;
          const double s = std::clamp(inside, 0.0, 1.0);
          mu *= 1 + support_.patch_excess * s * s * (3 - 2 * s);  // smooth step: the force stays continuous
        }
        return mu * load_[i];
      };
  const Eigen::Vector3d body = support_.anisotropy == 1
                                   ? footprint_friction_wrench(
                                         load_.size(), [&](std::size_t i) { return element_from_mass_centre_[i]; },
                                         v_body, omega, support_.regularisation_m_s, sliding_force_N)
                                   : anisotropic_friction_wrench(v_body, omega, sliding_force_N);
  PlanarWrench w;
  w.force_N = R * body.head<2>();
  w.torque_Nm = body(2);
  if (support_.viscous_per_kg > 0) {
    w.force_N -= support_.viscous_per_kg * object_.mass_kg * x.segment<2>(3);
    w.torque_Nm -= support_.viscous_per_kg * object_.inertia_kgm2 * omega;
  }
  return w;
}

template <class SlidingForce>
Eigen::Vector3d PushedObjectSystem::anisotropic_friction_wrench(const Eigen::Vector2d& v_body, double omega,
                                                                SlidingForce&& sliding_force_N) const {
  // A = diag(2 r, 2) / (1 + r): mu_x / mu_y = r, (mu_x + mu_y) / 2 = mu. Maximum dissipation on the ellipse
  // (f_x / A_x)^2 + (f_y / A_y)^2 = F^2 gives f = -F A^2 v / |A v|; eps regularises |A v| as in the isotropic law.
  const double r = support_.anisotropy;
  const Eigen::Array2d a(2 * r / (1 + r), 2 / (1 + r));
  const double eps2 = support_.regularisation_m_s * support_.regularisation_m_s;
  Eigen::Vector3d wrench = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < load_.size(); ++i) {
    const Eigen::Vector2d& offset = element_from_mass_centre_[i];
    const Eigen::Vector2d v = rigid_point_velocity(v_body, omega, offset);
    const double force = sliding_force_N(i, offset, v.squaredNorm());
    if (force == 0) continue;
    const Eigen::Array2d av = a * v.array();
    const Eigen::Vector2d f = (-force / std::sqrt(av.matrix().squaredNorm() + eps2) * (a * av)).matrix();
    wrench.head<2>() += f;
    wrench(2) += planar_moment(offset, f);
  }
  return wrench;
}

void PushedObjectSystem::derivative(const IntegrationInterval&, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                                    Eigen::Ref<Eigen::VectorXd> xdot) const {
  const PlanarWrench support = support_wrench(x);
  const RodWrench rod = rod_wrench(t, x);
  Eigen::Vector2d force = support.force_N;
  if (support_.tilt_rad != 0) force += gravity_along_support_N();
  double torque = support.torque_Nm;
  if (rod.touching) {
    force += rod.force_on_object_N;
    torque += planar_moment(rod.contact_point_m - x.head<2>(), rod.force_on_object_N);
  }
  xdot.head<3>() = x.segment<3>(3);
  xdot.segment<2>(3) = force / object_.mass_kg;
  xdot(5) = torque / object_.inertia_kgm2;
  if (compliant()) {
    // The tip: its spring to the commanded path, and the object's reaction at the contact.
    xdot.segment<2>(6) = x.segment<2>(8);
    Eigen::Vector2d on_tip = pusher_spring_force_N(t, x);
    if (rod.touching) on_tip -= rod.force_on_object_N;
    xdot.segment<2>(8) = on_tip / contact_.tip_mass_kg;
  }
}

std::vector<double> PushedObjectSystem::discontinuities(double t0, double t1) const {
  std::vector<double> out;
  for (double b : path_.phase_boundaries())
    if (b > t0 && b < t1) out.push_back(b);
  return out;
}

}  // namespace pushpred
