#include "pushpred/mechanics/support_friction.hpp"

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

Eigen::Vector2d perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

}  // namespace

double uniform_pressure_torque_ratio(const Footprint& footprint, const Eigen::Vector2d& centre) {
  if (!(footprint.total_area_m2 > 0)) throw InputError("torque ratio: empty footprint");
  double moment = 0;
  for (size_t i = 0; i < footprint.area_m2.size(); ++i)
    moment += footprint.area_m2[i] * (footprint.centre_m[i] - centre).norm();
  return moment / footprint.total_area_m2;
}

Eigen::Vector3d integrated_friction_wrench(const Footprint& footprint, const Eigen::Vector2d& centre,
                                           double normal_force_N, double mu, const Eigen::Vector2d& v,
                                           double omega) {
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  if (v.squaredNorm() == 0 && omega == 0) return w;
  const double pressure = mu * normal_force_N / footprint.total_area_m2;
  for (size_t i = 0; i < footprint.area_m2.size(); ++i) {
    const Eigen::Vector2d r = footprint.centre_m[i] - centre;
    const Eigen::Vector2d vi = v + omega * perp(r);
    const double speed = vi.norm();
    if (speed == 0) continue;
    const Eigen::Vector2d f = -(pressure * footprint.area_m2[i] / speed) * vi;
    w.head<2>() += f;
    w(2) += perp(r).dot(f);
  }
  return w;
}

}  // namespace pushpred
