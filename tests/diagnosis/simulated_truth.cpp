#include "simulated_truth.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/simulation/pushed_object_system.hpp"

namespace pushpred::testing {

std::vector<SimulatedPush> simulate_with_states(const std::vector<PushScenario>& scenarios,
                                                std::vector<SynchronisedPush>& pushes) {
  std::vector<SimulatedPush> sims;
  for (const auto& s : scenarios) {
    sims.push_back(simulate_push(s));
    pushes.push_back(synchronise(as_read(sims.back().recording), ShapeTable::published().find(s.shape)));
  }
  return sims;
}

double patch_gradient_per_unit_excess(const std::vector<SimulatedPush>& sims, double onset_m) {
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d right = Eigen::Vector2d::Zero();
  for (const SimulatedPush& sim : sims) {
    const PushScenario& s = sim.scenario;
    const ShapeInfo& shape = ShapeTable::published().find(s.shape);
    // The patch where scenario.hpp puts it: 2.5 cm beyond the object's leading point along the push, radius 2 cm.
    const Outline outline(shape);
    const Outline::Closest side = outline.point_on_side(s.contact_side, s.contact_position);
    const Eigen::Rotation2Dd R0(s.initial_yaw_rad), angle(s.push_angle_rad);
    const Eigen::Vector2d direction_body = angle * (-side.normal);
    SupportFriction with, without;
    with.coefficient = without.coefficient = s.surface_friction;
    with.pressure_rim_weight = without.pressure_rim_weight = s.pressure_rim_weight;
    with.patch_excess = 1;
    with.patch_radius_m = 0.02;
    with.patch_centre_m = Eigen::Vector2d(s.initial_x_m, s.initial_y_m) +
                          (outline.extent_along(direction_body) + 0.025) * (R0 * direction_body);
    const PusherPath path(Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitX(), 0.0, PusherMotion{});
    const PushedObjectSystem a(shape, ObjectProperties::nominal(shape), with, RodContact{}, path);
    const PushedObjectSystem b(shape, ObjectProperties::nominal(shape), without, RodContact{}, path);
    const FrictionFootprint footprint = FrictionFootprint::of(shape);
    // The candidate's column is the ramp less its mean over the push's sliding samples (builtin_effects.cpp).
    std::vector<Eigen::Vector2d> coulomb, ramp, extra;
    Eigen::Vector2d ramp_sum = Eigen::Vector2d::Zero();
    for (Eigen::Index k = 0; k < sim.t_s.size(); ++k) {
      Eigen::VectorXd x(6);
      x << sim.tracked_pose.row(k).transpose(), sim.mass_centre_velocity.row(k).transpose();
      if (sliding_speed(x.tail<3>(), shape) < 5e-3) continue;
      extra.push_back(a.support_wrench(x).force_N - b.support_wrench(x).force_N);
      const double travelled =
          std::max(0.0, (sim.tracked_pose.row(k).head<2>() - sim.tracked_pose.row(0).head<2>()).norm() - onset_m);
      coulomb.push_back(coulomb_friction_wrench(x.head<3>(), x.tail<3>(), shape, footprint).head<2>());
      ramp.push_back(travelled * coulomb.back());
      ramp_sum += ramp.back();
    }
    for (std::size_t k = 0; k < ramp.size(); ++k) {
      Eigen::Matrix2d columns;
      columns << coulomb[k], ramp[k] - ramp_sum / static_cast<double>(ramp.size());
      normal += columns.transpose() * columns;
      right += columns.transpose() * extra[k];
    }
  }
  return normal.ldlt().solve(right)(1);
}

}  // namespace pushpred::testing
