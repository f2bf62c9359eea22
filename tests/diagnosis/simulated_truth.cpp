#include "simulated_truth.hpp"

#include <Eigen/Geometry>

#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/simulation/pushed_object_system.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred::testing {

double position_friction_truth(const std::vector<PushScenario>& scenarios, std::vector<SynchronisedPush>& pushes) {
  double num = 0, den = 0;
  for (const auto& s : scenarios) {
    const SimulatedPush sim = simulate_push(s);
    const ShapeInfo& shape = ShapeTable::published().find(s.shape);
    pushes.push_back(synchronise(as_read(sim.recording), shape));
    // The patch as scenario.hpp defines it: a 2 cm radius disk on the push line, centred 2.5 cm beyond the
    // object's leading point at the start.
    const Outline outline(shape);
    const Outline::Closest side = outline.point_on_side(s.contact_side, s.contact_position);
    const Eigen::Rotation2Dd R0(s.initial_yaw_rad), angle(s.push_angle_rad);
    const Eigen::Vector2d direction_body = angle * (-side.normal);
    SupportFriction with, without;
    with.coefficient = without.coefficient = s.surface_friction;
    with.patch_excess = s.effects.position_friction_excess;
    with.patch_radius_m = 0.02;
    with.patch_centre_m = Eigen::Vector2d(s.initial_x_m, s.initial_y_m) +
                          (outline.extent_along(direction_body) + 0.025) * (R0 * direction_body);
    const PusherPath path(Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitX(), 0.0, PusherMotion{});
    const PushedObjectSystem a(shape, ObjectProperties::nominal(shape), with, RodContact{}, path);
    const PushedObjectSystem b(shape, ObjectProperties::nominal(shape), without, RodContact{}, path);
    const FrictionFootprint footprint = FrictionFootprint::of(shape);
    for (Eigen::Index k = 0; k < sim.t_s.size(); ++k) {
      Eigen::VectorXd x(6);
      x << sim.tracked_pose.row(k).transpose(), sim.mass_centre_velocity.row(k).transpose();
      if (sliding_speed(x.tail<3>(), shape) < 5e-3) continue;
      const PlanarWrench wa = a.support_wrench(x), wb = b.support_wrench(x);
      const Eigen::Vector2d extra = wa.force_N - wb.force_N;
      const double travelled = (sim.tracked_pose.row(k).head<2>() - sim.tracked_pose.row(0).head<2>()).norm();
      const Eigen::Vector3d phi = travelled * coulomb_friction_wrench(x.head<3>(), x.tail<3>(), shape, footprint);
      num += phi.head<2>().dot(extra);
      den += phi.head<2>().squaredNorm();
    }
  }
  return den > 0 ? num / den : 0.0;
}

}  // namespace pushpred::testing
