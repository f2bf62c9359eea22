#pragma once
// The outline a pusher touches, as contact geometry: for a point in the body frame (reading/shape_table.hpp: origin
// at the tracked centre, metres), the closest outline point, its outward unit normal and the signed distance
// (negative inside). The shape's own outline where the shape table lists one, or a local stand-in (a straight edge,
// a circle) where it does not; the quasi-static pushing model and its identification push on these.
#include <Eigen/Core>
#include <memory>

#include "pushpred/mechanics/outline.hpp"

namespace pushpred {

/// The outline the model pushes on, in the body frame: closest point, outward normal and signed distance of a
/// point. Must not allocate.
class ContactOutline {
 public:
  virtual ~ContactOutline() = default;
  virtual Outline::Closest closest(const Eigen::Vector2d& point_body_m) const = 0;
};

/// The shape table's outline (outline.hpp); throws InputError for a shape without one (butter).
std::shared_ptr<const ContactOutline> shape_outline(const ShapeInfo& shape);

/// A straight edge through `point_body_m` with outward normal `outward_normal_body` (body frame): the local
/// outline where the shape's is not known.
std::shared_ptr<const ContactOutline> straight_edge(const Eigen::Vector2d& point_body_m,
                                                    const Eigen::Vector2d& outward_normal_body);

/// A circle of `radius_m` about `centre_body_m` (body frame), the object inside: a convex local outline.
std::shared_ptr<const ContactOutline> circular_edge(const Eigen::Vector2d& centre_body_m, double radius_m);

}  // namespace pushpred
