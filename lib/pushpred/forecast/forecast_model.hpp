#pragma once
// The whole-push forecast: where an object pushed along a planned tip path goes, from the start until it rests,
// by the quasi-static pushing model (prediction/quasi_static_pushing.hpp: ellipsoidal limit surface, motion cone
// with its stick/slide switch) integrated with a fixed step, and the slide to rest after the tip lets go.
//
// Frames and units (SI): world {R} as preprocessing/synchronised_push.hpp; the body frame is the outline's (origin at
// the tracked centre, reading/shape_table.hpp). Poses are the tracked centre's (x, y [m], yaw [rad]).
//
// The model, per step dt (a fixed step: the tip moves at most `max_tip_step_m` per step while it moves, `slide_step_s`
// after; the quasi-static motion is not stiff, only the slide's Coulomb friction is, and it is stepped exactly):
// - contact: the rod (radius `rod_radius_m`) about the planned tip p(t); with q = R^T (p - origin) the closest
//   outline point, its outward normal and the penetration pen = r - d. The tip pushes when pen > -contact_slack_m
//   and its velocity, plus a gap keeper n pen / (gap_steps dt) that holds pen at zero, points into the object.
// - pushed: the CoF's velocity and yaw rate are the quasi-static motion (quasi_static_motion: sticking inside the
//   friction cone of mu_p, sliding on its edge otherwise) for the ratio c of the limit surface.
// - let go: when the tip does not push, or when the object sliding freely would leave the tip's normal speed behind
//   (the tip stops faster than friction stops the object), the object slides under the ellipsoidal limit surface's
//   Coulomb friction of mu_s m g, to rest.
// - with LimitSurfaceKind::Outline the limit surface is not the ellipsoid of ratio c but the one of a planar pressure
//   over the outline centred at the centre of friction (mechanics/pressure_limit_surface.hpp, a fitted quartic):
//   pushed, quasi_static_motion_on; let go, its friction wrench; c is not used. It is body-fixed, so the contact and
//   the twist are taken into the body frame for it.
// The planned tip follows its path exactly (a position-controlled robot far stiffer than the contact).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/mechanics/gravity.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/mechanics/pressure_limit_surface.hpp"
#include "pushpred/reading/physical_bounds.hpp"
#include "pushpred/reading/shape_table.hpp"

namespace pushpred {

/// The outline the rod pushes on, body frame [m]: a polygon (counter-clockwise, any number of vertices; closest points
/// searched near the last one found, so a 600-vertex outline costs as little per step as a square) or an ellipse
/// (exact, mechanics/outline.hpp), with a description for the object file.
class ForecastOutline {
 public:
  /// A polygon; throws InputError for fewer than 3 vertices, non-finite ones, or a non-positive area (clockwise).
  static ForecastOutline polygon(std::vector<Eigen::Vector2d> vertices_m, std::string description = "polygon");
  /// An ellipse of semi-axes a along body x and b along y; a circle when a == b.
  static ForecastOutline ellipse(double a_m, double b_m);
  /// The shape table's outline of `shape` (rect, tri, hex: their polygon; ellip: the ellipse). InputError when it has
  /// none.
  static ForecastOutline of_shape(const ShapeInfo& shape);

  /// Closest outline point to `point_body_m`; `hint` (an edge index, -1: unknown) is read and updated for polygons:
  /// edges within a window of it are searched, all of them when it is unknown or the answer lies at the window's end.
  Outline::Closest closest(const Eigen::Vector2d& point_body_m, int& hint) const;
  bool is_polygon() const { return !ellipse_; }
  const std::vector<Eigen::Vector2d>& vertices_m() const { return vertices_; }
  double semi_axis_a_m() const { return a_; }
  double semi_axis_b_m() const { return b_; }
  const std::string& description() const { return description_; }
  /// The outline point at fraction `fraction` (0..1) of the perimeter, counter-clockwise from vertex 0 (a polygon) or
  /// from (a, 0) (an ellipse), with the outward normal of the edge it lies on (the edge that starts there at a vertex),
  /// as the dataset's files use it. InputError for a fraction outside [0, 1].
  Outline::Closest point_at_perimeter_fraction(double fraction) const;
  /// Vertices for drawing (an ellipse sampled at 96 points).
  std::vector<Eigen::Vector2d> drawing_m() const;
  /// The ratio c = max torque / max force of the support under uniform pressure about `centre_m` [m].
  double uniform_pressure_torque_ratio_m(const Eigen::Vector2d& centre_m) const;
  Eigen::Vector2d area_centroid_m() const;
  /// Its extent, narrowest width and area (reading/physical_bounds.hpp), computed once when it is made.
  const OutlineSize& size() const { return size_; }
  /// The footprint's area elements (mechanics/outline.hpp's grid of 20 x 20 cells), for the pressure's limit surface.
  const Footprint& footprint() const { return *footprint_; }

 private:
  bool ellipse_ = false;
  double a_ = 0, b_ = 0;
  std::vector<Eigen::Vector2d> vertices_, normals_;
  std::string description_;
  OutlineSize size_;
  std::shared_ptr<const Outline> exact_;  ///< the ellipse
  std::shared_ptr<const Footprint> footprint_;
};

/// Which limit surface the forecast's support friction has: the ellipsoid of ratio c (a parameter fitted per push), or
/// the one of a planar pressure over the outline centred at the centre of friction (no c).
enum class LimitSurfaceKind { Ellipsoid, Outline };
const char* limit_surface_name(LimitSurfaceKind kind);  ///< "ellipsoid", "outline"
/// "ellipsoid" or "outline"; InputError naming the value otherwise.
LimitSurfaceKind limit_surface_named(const std::string& name);

/// What the model needs of the object besides its parameters.
struct ForecastObject {
  std::string name;
  std::shared_ptr<const ForecastOutline> outline;
  double mass_kg = 1;
  double inertia_kgm2 = 1e-3;                                      ///< about the mass centre
  Eigen::Vector2d centre_of_friction_m = Eigen::Vector2d::Zero();  ///< body frame
  LimitSurfaceKind limit_surface = LimitSurfaceKind::Ellipsoid;
  /// With LimitSurfaceKind::Outline: the radial shape of the support's pressure (mechanics/pressure_limit_surface.hpp,
  /// pressure_rim_shape: 0 uniform, > 0 loading the rim, < 0 the middle), learned or 0.
  double pressure_rim_weight = 0;
  /// With LimitSurfaceKind::Outline: the pressure's limit surface about centre_of_friction_m with pressure_rim_weight
  /// (set_centre_of_friction, set_pressure_shape and use_limit_surface keep it so).
  std::shared_ptr<const PolynomialLimitSurface> pressure_surface;
  /// Throws InputError for no outline, a name (when given) that is not letters and digits (is_shape_name), an
  /// outline, mass or inertia no pushed tabletop object has (check_outline_size, check_mass_and_inertia:
  /// reading/physical_bounds.hpp); std::logic_error for an outline limit surface about another centre or of another rim weight than the object's.
  void validate() const;
};

/// Makes `object` forecast with the limit surface `kind` (for Outline: fits the pressure's surface about its centre
/// of friction; InputError when the centre lies too far off the outline for a planar pressure).
void use_limit_surface(ForecastObject& object, LimitSurfaceKind kind);
/// Moves the centre of friction, refitting the pressure's limit surface when the object uses one.
void set_centre_of_friction(ForecastObject& object, const Eigen::Vector2d& centre_m);
/// Sets the centre of friction and the pressure's rim weight at once (one refit of the pressure's limit surface when
/// the object uses one). InputError for a rim weight outside the outline's rim_weight_range.
void set_pressure_shape(ForecastObject& object, const Eigen::Vector2d& centre_m, double rim_weight);

/// The parameters that vary from object to object and push to push: what `learn` identifies.
struct ForecastParameters {
  double pusher_friction = 0.25;  ///< mu_p, rod on object [-]
  double torque_ratio_m = 0.03;   ///< c, max torque / max force of the support [m]
  double support_friction = 0.4;  ///< mu_s, object on support [-]
  static constexpr int kCount = 3;
  Eigen::Vector3d vector() const { return {pusher_friction, torque_ratio_m, support_friction}; }
  static ForecastParameters from_vector(const Eigen::Vector3d& v) { return {v(0), v(1), v(2)}; }
  static const char* name(int i);  ///< "pusher_friction", "torque_ratio_m", "support_friction"
  /// InputError for a value not positive and finite, or above what a pushed object can have: a friction coefficient
  /// above kMaxFrictionCoefficient, a torque ratio above kMaxTorqueRatio_m (an object file of absurd numbers would
  /// otherwise give absurd forecasts).
  void validate() const;
  static constexpr double kMaxFrictionCoefficient = pushpred::kMaxFrictionCoefficient;  ///< reading/physical_bounds.hpp
  static constexpr double kMaxTorqueRatio_m = 10;        ///< c is about a third of an object's size
};

/// The numerical and rig constants of the forecast (not identified).
struct ForecastSettings {
  double rod_radius_m = 4.745e-3;  ///< the MCube rod
  double max_tip_step_m = 2.5e-4;  ///< the tip's largest advance per step
  double max_step_s = 5e-3;
  double slide_step_s = 1e-3;     ///< the step once the tip has stopped
  double contact_slack_m = 2e-5;  ///< the rod pushes from this far off the outline
  double gap_steps = 4;           ///< the gap keeper's time constant, in steps
  double max_slide_s = 2.0;       ///< the slide to rest is cut off after this
  double gravity_m_s2 = kGravity_m_s2;
};

/// InputError "LABEL: x of 1e+03 m is beyond the plausible 10 m from the robot" for a position farther than a
/// recording's may be (PlausibilityLimits::max_position_m); the pose also for a yaw beyond a turn (max_yaw_rad). A
/// forecast's start pose, a plan's tip positions.
void check_plausible_position(const Eigen::Vector2d& position_m, const std::string& label);
void check_plausible_pose(const Eigen::Vector3d& pose_m_rad, const std::string& label);

/// The planned tip path: a straight push (start, direction, cruise speed, length, with the rig's raised-cosine speed
/// ramps of `ramp_s` at both ends, as simulation/pusher_path.hpp) or a time-stamped polyline (held between points).
/// Time 0 is the plan's start; the tip rests at its end after `end_time_s`.
class TipPlan {
 public:
  /// The MCube rig's speed ramp: a raised cosine rising in 0.07 s (0.049 s from 5 to 95 % of the speed).
  static constexpr double kRigRamp_s = 0.07;
  /// Throws InputError for a non-positive speed, length or ramp, or a zero direction.
  static TipPlan straight(const Eigen::Vector2d& start_m, const Eigen::Vector2d& direction, double speed_m_s,
                          double length_m, double ramp_s = kRigRamp_s);
  /// Times strictly increasing from 0 (seconds since the plan's start), n x 2 positions [m]; InputError otherwise.
  static TipPlan waypoints(const Eigen::VectorXd& times_s, const Eigen::MatrixX2d& positions_m);

  /// Position and velocity at t (clamped to the plan; velocity 0 outside it). No allocation.
  void evaluate(double t_s, Eigen::Vector2d& position_m, Eigen::Vector2d& velocity_m_s) const;
  double end_time_s() const { return end_s_; }
  double peak_speed_m_s() const { return peak_speed_; }
  Eigen::Vector2d start_m() const;
  Eigen::Vector2d end_m() const;
  bool is_straight() const { return straight_; }
  Eigen::Vector2d direction() const { return direction_; }
  double speed_m_s() const { return speed_; }
  double length_m() const { return length_; }

 private:
  double distance(double t) const;
  double rate(double t) const;
  bool straight_ = true;
  Eigen::Vector2d start_ = Eigen::Vector2d::Zero(), direction_ = Eigen::Vector2d::UnitX();
  double speed_ = 0, length_ = 0, ramp_ = kRigRamp_s, rise_ = 0, hold_end_ = 0, end_s_ = 0, peak_speed_ = 0;
  Eigen::VectorXd times_;
  Eigen::MatrixX2d points_;
};

/// The push direction of a dataset file: the outline's inward normal at contact side `side`, position `position`
/// (outline.hpp's convention) rotated counter-clockwise by `angle_rad`, in the body frame.
Eigen::Vector2d dataset_push_direction_body(const ShapeInfo& shape, int side, double position, double angle_rad);
/// For an outline the shape table does not list (butter): the inward normal at fraction `position` of the perimeter
/// (ForecastOutline::point_at_perimeter_fraction), rotated by `angle_rad`; butter's files follow this convention
/// (side 0; the recorded first 5 mm of tip motion agree with it to about a degree).
Eigen::Vector2d perimeter_push_direction_body(const ForecastOutline& outline, double position, double angle_rad);
/// For a plan of one's own: the inward normal at the outline point closest to `tip_body_m`, rotated by `angle_rad`.
Eigen::Vector2d closest_normal_push_direction_body(const ForecastOutline& outline, const Eigen::Vector2d& tip_body_m,
                                                   double angle_rad);

/// One forecast trajectory, written into caller-owned storage so that many can be run without allocating.
struct ForecastRun {
  double rest_time_s = 0;       ///< when the object came to rest (or the cut-off), plan time
  double contact_time_s = 0;    ///< how long the tip pushed
  double sliding_fraction = 0;  ///< share of the pushed time the contact slid
  bool reached_rest = true;
};

/// Integrates the forecast from `pose0` (object at rest) under `plan`, writing the pose at each of `output_times_s`
/// (plan time, increasing) into the rows of `poses` (resized by the caller to output_times_s.size() x 3; poses after
/// rest are the rest pose). Allocates nothing.
ForecastRun forecast_into(const ForecastObject& object, const ForecastParameters& parameters, const TipPlan& plan,
                          const Eigen::Vector3d& pose0, const Eigen::VectorXd& output_times_s,
                          Eigen::Ref<Eigen::MatrixX3d> poses, const ForecastSettings& settings = {});

/// InputError "LABEL: the tip starts 12.3 mm inside the object's outline ..." (with "plan N" after the label when
/// `plan_index` >= 0) where the plan's first tip position lies inside the outline of `object` (validated: it has one)
/// at `pose0`: no push starts with the rod inside the object (the gap keeper would throw the object off). A forecast of
/// a plan checks it; fits of recorded pushes do not (their tracking may put the rod a little inside). Allocates nothing
/// unless it throws.
void check_tip_starts_outside(const ForecastObject& object, const TipPlan& plan, const Eigen::Vector3d& pose0_m_rad,
                              const char* label, long plan_index = -1);

/// forecast_into with its own storage.
Eigen::MatrixX3d forecast_poses(const ForecastObject& object, const ForecastParameters& parameters, const TipPlan& plan,
                                const Eigen::Vector3d& pose0, const Eigen::VectorXd& output_times_s,
                                const ForecastSettings& settings = {}, ForecastRun* run = nullptr);

/// The rest time of the forecast (plan time): the output span a caller needs to see the whole push.
double forecast_rest_time_s(const ForecastObject& object, const ForecastParameters& parameters, const TipPlan& plan,
                            const Eigen::Vector3d& pose0, const ForecastSettings& settings = {});

}  // namespace pushpred
