#pragma once
// Where the quasi-static model's rod meets a recorded push's object: the contact outline (the shape table's, or a
// local one inferred from the rod's trace for an outline the table lacks) and the object the model pushes. Body
// frame: the outline's (reading/shape_table.hpp); {R} as preprocessing/synchronised_push.hpp; SI units.
#include <Eigen/Core>
#include <memory>

#include "pushpred/prediction/quasi_static_pushing.hpp"

namespace pushpred {

/// The tip's (rod centre's) position at sample i in the object's body frame [m].
Eigen::Vector2d body_frame_tip(const SynchronisedPush& push, Eigen::Index i);

/// Whether the shape table gives `shape` an outline (rectangles, triangles, hexagon, ellipses; not butter).
bool has_listed_outline(const ShapeInfo& shape);

/// Outward normal (body frame) of an unknown outline at sample i: along the tip's slide over the object where it
/// slides (more than 1.5 mm over the last `lookback` samples), against the push where the rod is stuck (see
/// contact_outline_for), else the plan's direction ({R}) turned back by the push angle.
Eigen::Vector2d local_outward_normal(const SynchronisedPush& push, Eigen::Index i,
                                     const Eigen::Vector2d& plan_direction, Eigen::Index lookback);

/// The outline the model pushes on for `push`: the shape table's where it lists one; otherwise (butter) a local
/// outline at the last measured contact up to `t_s`: a circle fitted to the rod centre's trace over the object
/// where the rod has slid at least 4 mm along it (and the circle is convex towards the push), else a straight
/// edge through the contact point, normal to the last 0.1 s of slide, or, where the rod has not slid, to the
/// plan's push direction turned back by the push angle of the file name (the planner's angle to the normal).
/// `plan_direction` is the planned tip direction ({R}).
std::shared_ptr<const ContactOutline> contact_outline_for(const SynchronisedPush& push, double t_s,
                                                          const Eigen::Vector2d& plan_direction);

/// The model's description of the object of `push`: nominal mass and inertia, CoF at the centroid, and `outline`.
QuasiStaticObject quasi_static_object(const SynchronisedPush& push, std::shared_ptr<const ContactOutline> outline);

}  // namespace pushpred
