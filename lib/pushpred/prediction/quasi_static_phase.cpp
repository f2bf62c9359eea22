#include "pushpred/prediction/quasi_static_identification.hpp"

#include "pushpred/prediction/quasi_static_contact.hpp"

#include <Eigen/Geometry>

namespace pushpred {

QuasiStaticPhase predict_quasi_static_phase(const SynchronisedPush& push, const std::vector<TimeInterval>& identified,
                                            const TimeInterval& phase, double plan_rate_hz,
                                            const Eigen::Vector3d& velocity0, const Eigen::VectorXd& output_times_s,
                                            const IntegratorOptions& integrator,
                                            const QuasiStaticEstimator* fed_estimator,
                                            std::vector<std::shared_ptr<const GeneralizedForceTerm>> free_slide_terms,
                                            double contact_compliance_m_N) {
  QuasiStaticEstimator own;
  if (!fed_estimator) {
    own.reset(push);
    for (const auto& interval : identified) own.add_interval(interval);
    fed_estimator = &own;
  }
  QuasiStaticPhase out;
  out.identification = fed_estimator->identify();
  PlannedTipVelocity plan = plan_tip_velocity_from_measurement(push, phase.t0_s, phase.t1_s, plan_rate_hz);
  Eigen::Vector2d direction = Eigen::Vector2d::Zero();
  for (Eigen::Index k = 0; k < plan.signal.samples(); ++k) direction += plan.signal.values().row(k).transpose();
  const Eigen::Index i0 = push.index_at(phase.t0_s);
  auto outline = contact_outline_for(push, phase.t0_s, direction);
  // Start in contact exactly when the data do: the rod-outline distance measured at the phase's start.
  QuasiStaticParameters& p = out.identification.parameters;
  const Eigen::Vector3d pose0 = push.pose.row(i0).transpose();
  p.contact_compliance_m_N = contact_compliance_m_N;
  if (push.in_contact[static_cast<size_t>(i0)]) {
    const Outline::Closest c = outline->closest(body_frame_tip(push, i0));
    p.contact_offset_m = c.signed_distance_m - p.rod_radius_m + p.contact_band_m;
    if (p.contact_compliance_m_N > 0) {
      // The rod sits compliance x f_n deeper than a rigid contact under the force measured at the start.
      const Eigen::Vector2d inward = -(Eigen::Rotation2Dd(pose0(2)) * c.normal);
      p.contact_offset_m += p.contact_compliance_m_N * std::max(0.0, inward.dot(push.force_N.row(i0).transpose()));
    }
    out.identification.sources[3] = "measured at the phase's start (in contact)";
    // A rod centre deeper inside the tracked outline than half its radius is a tracking or outline error, not a
    // contact: the model's rod keeps at least half its radius, as out of contact below.
    if (!(p.contact_offset_m >= -0.5 * p.rod_radius_m)) {
      p.contact_offset_m = -0.5 * p.rod_radius_m;
      out.identification.sources[3] = "measured at the phase's start (in contact), limited to half the rod radius";
    }
    out.identification.std(3) = 0;
  } else if (!has_listed_outline(push.shape)) {
    // Out of contact at the start on an unlisted outline: the local outline, extrapolated from the last contact, may
    // reach under the rod. Take the straight edge just ahead of the rod, along the local normal, instead.
    const Eigen::Vector2d q0 = body_frame_tip(push, i0);
    const Eigen::Vector2d normal = outline->closest(q0).normal;
    outline = straight_edge(q0 - p.rod_radius_m * normal, normal);
    p.contact_offset_m = -p.contact_band_m;
    out.identification.sources[3] = "out of contact at the phase's start: the rod just off a straight edge";
    out.identification.std(3) = 0;
  } else {
    // Out of contact at the start: the rod must not start inside the outline either.
    const double largest = outline->closest(body_frame_tip(push, i0)).signed_distance_m - p.rod_radius_m;
    if (p.contact_offset_m > largest) {
      p.contact_offset_m = std::max(largest, -0.5 * p.rod_radius_m);
      out.identification.sources[3] = "measured at the phase's start (out of contact: no penetration)";
      out.identification.std(3) = 0;
    }
  }
  out.note = has_listed_outline(push.shape)
                 ? ""
                 : "outline not listed: a local outline from the rod's trace at the last contact";
  const PlannedTipPath path(std::move(plan), push.tip_m.row(i0).transpose());
  QuasiStaticObject object = quasi_static_object(push, outline);
  object.centre_of_friction_m += out.identification.centre_offset_m;
  object.free_slide_terms = std::move(free_slide_terms);
  out.poses = predict_quasi_static_poses(object, p, path, pose0, velocity0, output_times_s, integrator);
  return out;
}

}  // namespace pushpred
