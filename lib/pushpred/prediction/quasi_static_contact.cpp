#include "pushpred/prediction/quasi_static_contact.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

Eigen::Vector2d perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

}  // namespace

Eigen::Vector2d body_frame_tip(const SynchronisedPush& push, Eigen::Index i) {
  return Eigen::Rotation2Dd(push.pose(i, 2)).inverse() *
         (push.tip_m.row(i).transpose() - push.pose.row(i).head<2>().transpose());
}

bool has_listed_outline(const ShapeInfo& shape) {
  try {
    Outline o(shape);
    return true;
  } catch (const InputError&) {
    return false;
  }
}

Eigen::Vector2d local_outward_normal(const SynchronisedPush& push, Eigen::Index i,
                                     const Eigen::Vector2d& plan_direction, Eigen::Index lookback) {
  const Eigen::Rotation2Dd R(push.pose(i, 2));
  const Eigen::Vector2d push_body = R.inverse() * plan_direction;
  Eigen::Index j = std::max<Eigen::Index>(0, i - lookback);
  while (j < i && !push.in_contact[static_cast<size_t>(j)]) ++j;
  const Eigen::Vector2d slide = body_frame_tip(push, i) - body_frame_tip(push, j);
  Eigen::Vector2d normal;
  const bool stuck = push.in_contact[static_cast<size_t>(i)] && j == i - lookback && slide.norm() < 5e-4 &&
                     (push.tip_m.row(i) - push.tip_m.row(j)).norm() >= 2e-3;
  if (push.in_contact[static_cast<size_t>(i)] && slide.norm() > 1.5e-3) {
    normal = perp(slide.normalized());
  } else if (stuck) {
    normal = -push_body;  // a rounded vertex pushed along the plan, as contact_outline_for takes it
  } else {
    normal = -(Eigen::Rotation2Dd(-push.push.angle_rad) * push_body);
  }
  if (normal.dot(push_body) > 0) normal = -normal;
  return normal.normalized();
}

std::shared_ptr<const ContactOutline> contact_outline_for(const SynchronisedPush& push, double t_s,
                                                          const Eigen::Vector2d& plan_direction) {
  if (has_listed_outline(push.shape)) return shape_outline(push.shape);
  // The outline is known only where the rod touched it: at the last contact sample up to t_s.
  Eigen::Index i = push.index_at(t_s);
  while (i > 0 && !push.in_contact[static_cast<size_t>(i)]) --i;
  if (!push.in_contact[static_cast<size_t>(i)]) i = push.index_at(t_s);
  const Eigen::Vector2d direction = plan_direction.norm() > 0 ? plan_direction.normalized() : Eigen::Vector2d::UnitX();
  const Eigen::Vector2d push_body = Eigen::Rotation2Dd(push.pose(i, 2)).inverse() * direction;
  // Stuck: over the last 0.1 s in contact the rod pushed (moved at least 2 mm) without sliding over the object (under
  // 0.5 mm). The contact is then taken as a rounded vertex ahead of the rod along the push, so the push stays on
  // its normal while the object turns (a rod stuck at a corner rolls around it).
  {
    const Eigen::Index back = static_cast<Eigen::Index>(std::lround(0.1 * push.rate_hz));
    const Eigen::Index j = i - back;
    if (j >= 0 && push.in_contact[static_cast<size_t>(j)] && (push.tip_m.row(i) - push.tip_m.row(j)).norm() >= 2e-3 &&
        (body_frame_tip(push, i) - body_frame_tip(push, j)).norm() < 5e-4) {
      constexpr double kVertexRadius_m = 5e-4;
      return circular_edge(body_frame_tip(push, i) + (kPusherRadius_m + kVertexRadius_m) * push_body, kVertexRadius_m);
    }
  }
  // The rod centre's trace over the object while in contact, back from t_s: a circle (of the outline's radius
  // plus the rod's) where it has slid far enough to show the outline's curvature.
  std::vector<Eigen::Vector2d> trace;
  double arc = 0;
  for (Eigen::Index j = i; j >= 0 && push.in_contact[static_cast<size_t>(j)] && arc < 0.015; --j) {
    const Eigen::Vector2d q = body_frame_tip(push, j);
    if (trace.empty() || (q - trace.back()).norm() >= 1e-3) {
      if (!trace.empty()) arc += (q - trace.back()).norm();
      trace.push_back(q);
    }
  }
  if (arc >= 0.004 && trace.size() >= 4) {
    Eigen::MatrixXd A(static_cast<Eigen::Index>(trace.size()), 3);
    Eigen::VectorXd b(A.rows());
    for (Eigen::Index k = 0; k < A.rows(); ++k) {
      const Eigen::Vector2d& q = trace[static_cast<size_t>(k)];
      A.row(k) << q.x(), q.y(), 1.0;
      b(k) = -q.squaredNorm();
    }
    const Eigen::Vector3d def = A.colPivHouseholderQr().solve(b);
    const Eigen::Vector2d centre = -0.5 * def.head<2>();
    const double r2 = centre.squaredNorm() - def(2);
    if (r2 > 0) {
      const double trace_radius = std::sqrt(r2);
      const Eigen::Vector2d outward = (trace.front() - centre).normalized();
      if (trace_radius > kPusherRadius_m + 0.005 && trace_radius < 1.0 && outward.dot(push_body) < 0)
        return circular_edge(centre, trace_radius - kPusherRadius_m);
    }
  }
  const Eigen::Vector2d normal =
      local_outward_normal(push, i, direction, static_cast<Eigen::Index>(std::lround(0.1 * push.rate_hz)));
  return straight_edge(body_frame_tip(push, i) - kPusherRadius_m * normal, normal);
}

QuasiStaticObject quasi_static_object(const SynchronisedPush& push, std::shared_ptr<const ContactOutline> outline) {
  QuasiStaticObject o;
  o.mass_kg = push.shape.mass_kg;
  o.inertia_kgm2 = push.shape.inertia_kgm2;
  o.centre_of_friction_m = push.shape.centroid_m;
  o.outline = std::move(outline);
  return o;
}

}  // namespace pushpred
