#pragma once
// A rigid planar object on a support surface, pushed by a rod that follows a prescribed path: the continuous
// system the simulator integrates with CvodeIntegrator.
//
// State (6): mass-centre position X, Y [m], yaw theta [rad], mass-centre velocity vX, vY [m/s], yaw rate
// omega [rad/s], all in the world frame (the robot frame of the recordings). The tracked centre that a pose
// sensor reports is the body-frame origin of reading/shape_table.hpp, which is not the mass centre when the
// shape's centroid or a com_offset moves it.
//
// Forces:
// - support friction, distributed over the footprint (area elements of Footprint): each element carries a share
//   of the weight m g (uniform pressure, tilted to a plane just enough that the centre of pressure lies under
//   the mass centre, so that the object is in moment balance on the table) and resists its own velocity with
//   Coulomb friction mu |N_i| v_i / sqrt(|v_i|^2 + eps^2) (mechanics/support_friction.hpp); eps regularises the
//   stick phase so the object stops.
//   Optional: Stribeck rise of mu at low element speed, a disk patch of other friction, viscous drag.
// - the rod: a circle of radius r whose centre is on the PusherPath. Penetration delta = r - d, d the signed
//   distance of the rod centre to the outline; normal force k delta + c delta_dot (the damping blended in
//   over the first `damping_blend_m` of penetration so the force is continuous at touch, never pulling), and
//   Coulomb friction on the slip between rod and outline. The compliance stands for the robot arm, sensor and
//   contact together (docs/simulator.md: chosen so the force rises and rings at a push's start as the real one).
#include <Eigen/Core>
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/reading/shape_table.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/simulation/pusher_path.hpp"
#include "pushpred/systems/continuous_system.hpp"
#include "pushpred/mechanics/gravity.hpp"

namespace pushpred {

/// The object as simulated (true values, which may differ from the shape table's nominal ones).
struct ObjectProperties {
  double mass_kg = 1.0;
  double inertia_kgm2 = 1e-3;                               ///< about the mass centre
  Eigen::Vector2d mass_centre_m = Eigen::Vector2d::Zero();  ///< body frame
  /// The nominal values of `shape`: its mass, inertia and centroid.
  static ObjectProperties nominal(const ShapeInfo& shape);
};

struct SupportFriction {
  double gravity_m_s2 = kGravity_m_s2;  ///< the weight m g is what the surface carries
  double coefficient = 0.35;   ///< Coulomb mu between object and surface
  /// eps in v / sqrt(|v|^2 + eps^2). Under a load f below mu N a resting object creeps at about eps f / (mu N):
  /// at 1e-5 m/s that is under a micrometre over a rest period, below the tracker's noise.
  double regularisation_m_s = 1e-5;
  double stribeck_excess = 0;  ///< mu(v) = mu (1 + excess exp(-(v / stribeck_speed)^2))
  double stribeck_speed_m_s = 0.01;
  double patch_excess = 0;  ///< mu (1 + excess) inside the patch disk (world frame)
  Eigen::Vector2d patch_centre_m = Eigen::Vector2d::Zero();
  double patch_radius_m = 0.02;
  double patch_edge_m = 0.002;  ///< width of the smooth step at the patch rim
  double viscous_per_kg = 0;    ///< extra drag -c m v and -c I omega [1/s = N s/m per kg]
  /// Radial shape of the pressure (PushScenario::pressure_rim_weight): p ~ 1 + w (|r - c|^2 / <|r - c|^2> - 1).
  double pressure_rim_weight = 0;
  /// A support tilted by `tilt_rad` whose downhill direction is `downhill` (world, unit): gravity pulls the mass
  /// centre with m g sin(tilt) along it and the support carries m g cos(tilt).
  double tilt_rad = 0;
  Eigen::Vector2d downhill = Eigen::Vector2d::UnitX();
  /// mu_x / mu_y along the body axes, mean (mu_x + mu_y) / 2 = mu: elliptic Coulomb friction of maximum dissipation,
  /// f = -F A^2 v / sqrt(|A v|^2 + eps^2), A = diag(mu_x, mu_y) / mu, so that (f_x / A_x)^2 + (f_y / A_y)^2 = F^2.
  double anisotropy = 1;
};

struct RodContact {
  double rod_radius_m = kPusherRadius_m;
  double stiffness_N_m = 1e4;
  double damping_N_s_m = 25.0;
  double damping_blend_m = 5e-5;
  double friction = 0.25;  ///< Coulomb mu between rod and object
  double regularisation_m_s = 1e-5;
  /// A compliant pusher: the tip is a small mass on a spring of this compliance [m/N] behind the commanded path,
  /// damped at `tip_damping_ratio`; 0: the tip is the path. The sensor, behind the spring, reads the spring's force.
  double pusher_compliance_m_N = 0;
  double tip_mass_kg = 0.02;
  double tip_damping_ratio = 0.7;
};

/// What the rod does to the object at one instant.
struct RodWrench {
  bool touching = false;
  double penetration_m = 0;
  Eigen::Vector2d force_on_object_N = Eigen::Vector2d::Zero();  ///< world frame
  Eigen::Vector2d contact_point_m = Eigen::Vector2d::Zero();    ///< on the outline, world frame
  Eigen::Vector2d rod_centre_m = Eigen::Vector2d::Zero();
  /// Torque of force_on_object_N about the rod axis, (contact point - rod centre) x force [N m]: T_C of
  /// preprocessing/synchronised_push.hpp. The sensor reads the negative of both.
  double torque_about_rod_Nm = 0;
};

/// Net force [N] and torque about the mass centre [N m] of one group of forces, world frame.
struct PlanarWrench {
  Eigen::Vector2d force_N = Eigen::Vector2d::Zero();
  double torque_Nm = 0;
};

class PushedObjectSystem final : public ContinuousSystem {
 public:
  /// Throws InputError for non-positive mass, inertia, friction or stiffness, or a mass centre so far from
  /// the footprint's centroid that a planar pressure would turn negative.
  PushedObjectSystem(const ShapeInfo& shape, const ObjectProperties& object, const SupportFriction& support,
                     const RodContact& contact, const PusherPath& path);

  /// X, Y, yaw, their rates; with a compliant pusher also the tip's position and velocity (world), 10.
  int state_size() const override { return compliant() ? 10 : 6; }
  bool compliant() const { return contact_.pusher_compliance_m_N > 0; }
  /// The pusher path has no held inputs: `interval` is not used.
  void derivative(const IntegrationInterval& interval, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                  Eigen::Ref<Eigen::VectorXd> xdot) const override;
  /// Stiff: the rod's contact (1e4 N/m, 25 N s/m) and the friction regularised over 1e-5 m/s act in well under a
  /// millisecond: BDF (difference-quotient Jacobian).
  bool stiff() const override { return true; }
  std::vector<double> discontinuities(double t0_s, double t1_s) const override;

  /// The state at rest with the tracked centre at `tracked_pose` (x, y [m], yaw [rad]).
  Eigen::VectorXd state_at_rest(const Eigen::Vector3d& tracked_pose) const;
  /// The tracked centre's pose (x, y, yaw unwrapped) and velocity of a state.
  Eigen::Vector3d tracked_pose(const Eigen::Ref<const Eigen::VectorXd>& x) const;

  RodWrench rod_wrench(double t, const Eigen::Ref<const Eigen::VectorXd>& x) const;
  PlanarWrench support_wrench(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// Gravity along a tilted support, on the mass centre [N], world: m g sin(tilt) downhill.
  Eigen::Vector2d gravity_along_support_N() const;
  /// The tip's centre: the commanded path's point, or with a compliant pusher the tip's state.
  Eigen::Vector2d tip_position_m(double t, const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// The force the arm's spring puts on the tip [N], world (zero without a compliant pusher).
  Eigen::Vector2d pusher_spring_force_N(double t, const Eigen::Ref<const Eigen::VectorXd>& x) const;

  const Outline& outline() const { return outline_; }
  const PusherPath& path() const { return path_; }
  const ObjectProperties& object() const { return object_; }
  /// Normal load carried by each footprint element [N]; sums to m g.
  const std::vector<double>& element_loads_N() const { return load_; }

 private:
  template <class SlidingForce>
  Eigen::Vector3d anisotropic_friction_wrench(const Eigen::Vector2d& v_body, double omega,
                                              SlidingForce&& sliding_force_N) const;

  Outline outline_;
  ObjectProperties object_;
  SupportFriction support_;
  RodContact contact_;
  PusherPath path_;
  std::vector<Eigen::Vector2d> element_from_mass_centre_;  // body frame
  std::vector<double> load_;
};

}  // namespace pushpred
