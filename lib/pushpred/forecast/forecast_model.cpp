#include "pushpred/forecast/forecast_model.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "pushpred/core/error.hpp"
#include "pushpred/prediction/quasi_static_pushing.hpp"
#include "pushpred/preprocessing/plausibility.hpp"

namespace pushpred {
namespace {

Eigen::Vector2d perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

/// Closest point of segment [a, b] to p: squared distance and the point.
double segment_closest(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p,
                       Eigen::Vector2d& point) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double u = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  point = a + u * ab;
  return (p - point).squaredNorm();
}

bool polygon_contains(const std::vector<Eigen::Vector2d>& v, const Eigen::Vector2d& p) {
  bool inside = false;
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if ((v[i].y() > p.y()) != (v[j].y() > p.y()) &&
        p.x() < (v[j].x() - v[i].x()) * (p.y() - v[i].y()) / (v[j].y() - v[i].y()) + v[i].x())
      inside = !inside;
  }
  return inside;
}

}  // namespace

ForecastOutline ForecastOutline::polygon(std::vector<Eigen::Vector2d> vertices, std::string description) {
  if (vertices.size() < 3)
    throw InputError("outline polygon: needs at least 3 vertices, got " + std::to_string(vertices.size()));
  double area2 = 0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!vertices[i].allFinite()) throw InputError("outline polygon: vertex " + std::to_string(i) + " is not finite");
    const Eigen::Vector2d& a = vertices[i];
    const Eigen::Vector2d& b = vertices[(i + 1) % vertices.size()];
    area2 += a.x() * b.y() - b.x() * a.y();
  }
  if (!(area2 > 0)) throw InputError("outline polygon: its area is not positive (vertices must run counter-clockwise)");
  ForecastOutline o;
  o.vertices_ = std::move(vertices);
  o.normals_.resize(o.vertices_.size());
  for (std::size_t i = 0; i < o.vertices_.size(); ++i) {
    const Eigen::Vector2d edge = o.vertices_[(i + 1) % o.vertices_.size()] - o.vertices_[i];
    if (!(edge.norm() > 0))
      throw InputError("outline polygon: vertices " + std::to_string(i) + " and the next coincide");
    o.normals_[i] = Eigen::Vector2d(edge.y(), -edge.x()).normalized();  // outward for counter-clockwise
  }
  o.description_ = std::move(description);
  o.size_ = polygon_size(o.vertices_);
  ShapeInfo shape;
  shape.name = "polygon";
  shape.geometry = Geometry::Polygon;
  shape.vertices_m = o.vertices_;
  o.footprint_ = std::make_shared<const Footprint>(make_footprint(Outline(shape)));
  return o;
}

ForecastOutline ForecastOutline::ellipse(double a, double b) {
  require_positive_finite(a, "outline ellipse: semi-axis a");
  require_positive_finite(b, "outline ellipse: semi-axis b");
  ForecastOutline o;
  o.ellipse_ = true;
  o.a_ = a;
  o.b_ = b;
  o.size_ = ellipse_size(a, b);
  ShapeInfo shape;
  shape.name = "ellipse";
  shape.geometry = Geometry::Ellipse;
  shape.dim1_m = a;
  shape.dim2_m = b;
  o.exact_ = std::make_shared<Outline>(shape);
  o.footprint_ = std::make_shared<const Footprint>(make_footprint(*o.exact_));
  o.description_ = a == b ? "circle" : "ellipse";
  return o;
}

ForecastOutline ForecastOutline::of_shape(const ShapeInfo& shape) {
  if (shape.geometry == Geometry::Ellipse) {
    ForecastOutline o = ellipse(shape.dim1_m, shape.dim2_m);
    o.description_ = "shape table: " + shape.name;
    return o;
  }
  return polygon(outline_polygon(shape), "shape table: " + shape.name);
}

Outline::Closest ForecastOutline::closest(const Eigen::Vector2d& p, int& hint) const {
  if (ellipse_) return exact_->closest(p);
  const int n = static_cast<int>(vertices_.size());
  constexpr int kWindow = 6;
  const bool full = hint < 0 || hint >= n || n <= 4 * kWindow;
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_point = Eigen::Vector2d::Zero(), point;
  auto visit = [&](int i) {
    const double d2 = segment_closest(vertices_[static_cast<std::size_t>(i)],
                                      vertices_[static_cast<std::size_t>((i + 1) % n)], p, point);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
      best_point = point;
    }
  };
  if (full) {
    for (int i = 0; i < n; ++i) visit(i);
  } else {
    for (int k = -kWindow; k <= kWindow; ++k) visit(((hint + k) % n + n) % n);
    const int offset = ((best - hint) % n + n) % n;
    if (offset == kWindow || offset == n - kWindow) {  // the nearest may lie beyond the window
      for (int i = 0; i < n; ++i) visit(i);
    }
  }
  hint = best;
  Outline::Closest c;
  c.point_m = best_point;
  const Eigen::Vector2d d = p - best_point;
  const double dist = std::sqrt(best_d2);
  // The normal: the edge's inside it, the direction to the point off a vertex (continuous around corners).
  const Eigen::Vector2d& a = vertices_[static_cast<std::size_t>(best)];
  const Eigen::Vector2d& b = vertices_[static_cast<std::size_t>((best + 1) % n)];
  const bool at_vertex = (best_point - a).squaredNorm() < 1e-24 || (best_point - b).squaredNorm() < 1e-24;
  const bool inside =
      d.dot(normals_[static_cast<std::size_t>(best)]) < 0 || (at_vertex && dist > 0 && polygon_contains(vertices_, p));
  if (at_vertex && dist > 1e-12)
    c.normal = inside ? Eigen::Vector2d(-d / dist) : Eigen::Vector2d(d / dist);
  else
    c.normal = normals_[static_cast<std::size_t>(best)];
  c.signed_distance_m = inside ? -dist : dist;
  return c;
}

Outline::Closest ForecastOutline::point_at_perimeter_fraction(double fraction) const {
  if (!(fraction >= 0 && fraction <= 1)) throw InputError("outline: perimeter fraction must lie in [0, 1]");
  const std::vector<Eigen::Vector2d> v = drawing_m();
  const std::size_t n = v.size();
  std::vector<double> arc(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) arc[i + 1] = arc[i] + (v[(i + 1) % n] - v[i]).norm();
  const double total = arc[n];
  auto at = [&](double s_m, Eigen::Vector2d* normal) {
    s_m = std::fmod(std::fmod(s_m, total) + total, total);
    const std::size_t i = static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), s_m) - arc.begin()) - 1;
    const std::size_t k = std::min(i, n - 1);
    const Eigen::Vector2d edge = v[(k + 1) % n] - v[k];
    if (normal) *normal = Eigen::Vector2d(edge.y(), -edge.x()).normalized();
    return Eigen::Vector2d(v[k] + (s_m - arc[k]) / edge.norm() * edge);
  };
  Outline::Closest c;
  c.point_m = at(fraction * total, &c.normal);
  return c;
}

std::vector<Eigen::Vector2d> ForecastOutline::drawing_m() const {
  if (!ellipse_) return vertices_;
  std::vector<Eigen::Vector2d> v;
  for (int k = 0; k < 96; ++k) {
    const double u = 2 * M_PI * k / 96;
    v.emplace_back(a_ * std::cos(u), b_ * std::sin(u));
  }
  return v;
}

namespace {

template <class Visit>
void for_each_area_sample(const ForecastOutline& o, Visit&& visit) {
  const std::vector<Eigen::Vector2d> v = o.drawing_m();
  Eigen::Vector2d lo = v.front(), hi = v.front();
  for (const auto& p : v) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  constexpr int kCells = 120;
  const Eigen::Vector2d step = (hi - lo) / kCells;
  for (int i = 0; i < kCells; ++i)
    for (int j = 0; j < kCells; ++j) {
      const Eigen::Vector2d p = lo + Eigen::Vector2d((i + 0.5) * step.x(), (j + 0.5) * step.y());
      const bool inside = o.is_polygon() ? polygon_contains(v, p)
                                         : (p.x() / o.semi_axis_a_m()) * (p.x() / o.semi_axis_a_m()) +
                                                   (p.y() / o.semi_axis_b_m()) * (p.y() / o.semi_axis_b_m()) <=
                                               1;
      if (inside) visit(p);
    }
}

}  // namespace

Eigen::Vector2d ForecastOutline::area_centroid_m() const {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  double count = 0;
  for_each_area_sample(*this, [&](const Eigen::Vector2d& p) {
    sum += p;
    count += 1;
  });
  return count > 0 ? Eigen::Vector2d(sum / count) : Eigen::Vector2d::Zero();
}

double ForecastOutline::uniform_pressure_torque_ratio_m(const Eigen::Vector2d& centre) const {
  double sum = 0, count = 0;
  for_each_area_sample(*this, [&](const Eigen::Vector2d& p) {
    sum += (p - centre).norm();
    count += 1;
  });
  return count > 0 ? sum / count : 0.0;
}

const char* limit_surface_name(LimitSurfaceKind kind) {
  return kind == LimitSurfaceKind::Outline ? "outline" : "ellipsoid";
}

LimitSurfaceKind limit_surface_named(const std::string& name) {
  if (name == "ellipsoid") return LimitSurfaceKind::Ellipsoid;
  if (name == "outline") return LimitSurfaceKind::Outline;
  throw InputError("limit surface '" + name + "' is not known: give ellipsoid or outline");
}

void use_limit_surface(ForecastObject& object, LimitSurfaceKind kind) {
  object.limit_surface = kind;
  object.pressure_surface.reset();
  if (kind != LimitSurfaceKind::Outline) return;
  if (!object.outline) throw InputError("forecast object '" + object.name + "': no outline for its limit surface");
  object.pressure_surface = std::make_shared<const PolynomialLimitSurface>(PolynomialLimitSurface::fit(
      planar_support_pressure(object.outline->footprint(), object.centre_of_friction_m, object.pressure_rim_weight)));
}

void set_centre_of_friction(ForecastObject& object, const Eigen::Vector2d& centre) {
  set_pressure_shape(object, centre, object.pressure_rim_weight);
}

void set_pressure_shape(ForecastObject& object, const Eigen::Vector2d& centre, double rim_weight) {
  if (centre == object.centre_of_friction_m && rim_weight == object.pressure_rim_weight &&
      (object.limit_surface != LimitSurfaceKind::Outline || object.pressure_surface))
    return;
  if (!std::isfinite(rim_weight))
    throw InputError("forecast object '" + object.name + "': the pressure's rim weight must be finite");
  object.centre_of_friction_m = centre;
  object.pressure_rim_weight = rim_weight;
  use_limit_surface(object, object.limit_surface);
}

void ForecastObject::validate() const {
  if (!outline) throw InputError("forecast object '" + name + "': no outline");
  if (limit_surface == LimitSurfaceKind::Outline &&
      (!pressure_surface || pressure_surface->centre_m() != centre_of_friction_m ||
       pressure_surface->rim_weight() != pressure_rim_weight))
    throw std::logic_error("forecast object '" + name +
                           "': its outline limit surface is not about its centre of friction or of its rim weight (use "
                           "set_centre_of_friction or set_pressure_shape)");
  if (!name.empty() && !is_shape_name(name))
    throw InputError("forecast object '" + plain_text(name) +
                     "': a name is letters and digits only, as a shape's name (the dataset's file names carry it as "
                     "shape=NAME)");
  // Labels short enough for the small-string buffer: validate runs in every forecast, which must not allocate.
  try {
    check_outline_size(outline->size(), "outline");
    check_mass_and_inertia(outline->size(), mass_kg, inertia_kgm2, "mass", "inertia");
  } catch (const InputError& e) {
    throw InputError("forecast object '" + name + "': " + e.what());
  }
  if (!centre_of_friction_m.allFinite())
    throw InputError("forecast object '" + name + "': centre of friction must be finite");
}

const char* ForecastParameters::name(int i) {
  static const char* names[kCount] = {"pusher_friction", "torque_ratio_m", "support_friction"};
  return i >= 0 && i < kCount ? names[i] : "?";
}

void ForecastParameters::validate() const {
  require_positive_finite(pusher_friction, "forecast parameters: pusher_friction");
  require_positive_finite(torque_ratio_m, "forecast parameters: torque_ratio_m");
  require_positive_finite(support_friction, "forecast parameters: support_friction");
  char text[160];
  const auto at_most = [&](double value, double bound, const char* what) {
    if (value <= bound) return;
    std::snprintf(text, sizeof text, "forecast parameters: %s of %.3g is above %.3g, more than a pushed object has",
                  what, value, bound);
    throw InputError(text);
  };
  at_most(pusher_friction, kMaxFrictionCoefficient, "pusher_friction");
  at_most(support_friction, kMaxFrictionCoefficient, "support_friction");
  at_most(torque_ratio_m, kMaxTorqueRatio_m, "torque_ratio_m");
}

namespace {

/// A plan no push of a recording could follow is refused before any work: longer than a recording's stream may last
/// (a 50 mm push at 1e-6 mm/s would be forecast for 1.6 years) or faster than an object can be pushed
/// (PlausibilityLimits: 600 s, 2 m/s).
void check_plan_bounds(double end_s, double peak_speed_m_s, const char* what) {
  const PlausibilityLimits limits;
  char text[160];
  if (!(end_s <= limits.max_span_s)) {
    std::snprintf(text, sizeof text, "%s lasts %.3g s, longer than the %.3g s a push may last", what, end_s,
                  limits.max_span_s);
    throw InputError(text);
  }
  if (!(peak_speed_m_s <= limits.max_speed_m_s)) {
    std::snprintf(text, sizeof text, "%s moves the tip at %.3g m/s, faster than the %.3g m/s a pushed object can move",
                  what, peak_speed_m_s, limits.max_speed_m_s);
    throw InputError(text);
  }
}

}  // namespace

void check_plausible_position(const Eigen::Vector2d& position_m, const std::string& label) {
  const PlausibilityLimits limits;
  char text[200];
  for (int i = 0; i < 2; ++i)
    if (!(std::abs(position_m(i)) <= limits.max_position_m)) {
      std::snprintf(text, sizeof text, "%s: %c of %.3g m is beyond the plausible %.3g m from the robot", label.c_str(),
                    i == 0 ? 'x' : 'y', position_m(i), limits.max_position_m);
      throw InputError(text);
    }
}

void check_plausible_pose(const Eigen::Vector3d& pose, const std::string& label) {
  check_plausible_position(pose.head<2>(), label);
  const PlausibilityLimits limits;
  if (!(std::abs(pose(2)) <= limits.max_yaw_rad)) {
    char text[200];
    std::snprintf(text, sizeof text, "%s: yaw of %.3g deg is beyond a turn (%.3g deg)", label.c_str(),
                  pose(2) * 180 / M_PI, limits.max_yaw_rad * 180 / M_PI);
    throw InputError(text);
  }
}

TipPlan TipPlan::straight(const Eigen::Vector2d& start, const Eigen::Vector2d& direction, double speed, double length,
                          double ramp) {
  if (!start.allFinite()) throw InputError("tip plan: start must be finite");
  check_plausible_position(start, "tip plan: start");
  if (!direction.allFinite() || !(direction.norm() > 0))
    throw InputError("tip plan: direction must be a non-zero vector");
  require_positive_finite(speed, "tip plan: speed");
  require_positive_finite(length, "tip plan: length");
  require_positive_finite(ramp, "tip plan: speed ramp");
  TipPlan p;
  p.straight_ = true;
  p.start_ = start;
  p.direction_ = direction.normalized();
  p.speed_ = speed;
  p.length_ = length;
  // A raised cosine covers speed * ramp / 2 in each ramp; a path too short for both gets shorter ramps.
  p.ramp_ = std::min(ramp, length / speed);
  p.rise_ = p.ramp_;
  p.hold_end_ = p.ramp_ + (length - speed * p.ramp_) / speed;
  p.end_s_ = p.hold_end_ + p.ramp_;
  p.peak_speed_ = speed;
  check_plan_bounds(p.end_s_, p.peak_speed_, "tip plan");
  return p;
}

TipPlan TipPlan::waypoints(const Eigen::VectorXd& times, const Eigen::MatrixX2d& positions) {
  if (times.size() < 2 || positions.rows() != times.size())
    throw InputError("tip path: needs at least two time-stamped points, one time per position");
  if (!times.allFinite() || !positions.allFinite()) throw InputError("tip path: times and positions must be finite");
  if (times(0) != 0) throw InputError("tip path: times must start at 0 (the plan's start)");
  TipPlan p;
  p.straight_ = false;
  p.times_ = times;
  p.points_ = positions;
  for (Eigen::Index k = 1; k < times.size(); ++k) {
    if (!(times(k) > times(k - 1)))
      throw InputError("tip path: times must increase strictly (row " + std::to_string(k + 1) + ")");
    p.peak_speed_ =
        std::max(p.peak_speed_, (positions.row(k) - positions.row(k - 1)).norm() / (times(k) - times(k - 1)));
  }
  p.end_s_ = times(times.size() - 1);
  p.start_ = positions.row(0).transpose();
  const Eigen::Vector2d total = positions.row(positions.rows() - 1).transpose() - p.start_;
  p.direction_ = total.norm() > 0 ? Eigen::Vector2d(total.normalized()) : Eigen::Vector2d::UnitX();
  p.length_ = 0;
  for (Eigen::Index k = 1; k < times.size(); ++k) p.length_ += (positions.row(k) - positions.row(k - 1)).norm();
  p.speed_ = p.length_ / p.end_s_;
  check_plan_bounds(p.end_s_, p.peak_speed_, "tip path");
  for (Eigen::Index k = 0; k < positions.rows(); ++k)
    check_plausible_position(positions.row(k).transpose(), "tip path: row " + std::to_string(k + 1));
  return p;
}

double TipPlan::rate(double t) const {
  if (t <= 0 || t >= end_s_) return 0;
  if (t < rise_) return 0.5 * speed_ * (1 - std::cos(M_PI * t / ramp_));
  if (t <= hold_end_) return speed_;
  return 0.5 * speed_ * (1 + std::cos(M_PI * (t - hold_end_) / ramp_));
}

double TipPlan::distance(double t) const {
  if (t <= 0) return 0;
  if (t >= end_s_) return length_;
  const double half = 0.5 * speed_;
  const double rise_length = half * ramp_;
  if (t < rise_) return half * (t - ramp_ / M_PI * std::sin(M_PI * t / ramp_));
  if (t <= hold_end_) return rise_length + speed_ * (t - rise_);
  const double u = t - hold_end_;
  return rise_length + speed_ * (hold_end_ - rise_) + half * (u + ramp_ / M_PI * std::sin(M_PI * u / ramp_));
}

void TipPlan::evaluate(double t, Eigen::Vector2d& position, Eigen::Vector2d& velocity) const {
  if (straight_) {
    position = start_ + distance(t) * direction_;
    velocity = rate(t) * direction_;
    return;
  }
  const Eigen::Index n = times_.size();
  if (t <= 0 || t >= end_s_) {
    position = t <= 0 ? points_.row(0).transpose() : points_.row(n - 1).transpose();
    velocity.setZero();
    return;
  }
  const Eigen::Index k =
      static_cast<Eigen::Index>(std::upper_bound(times_.data(), times_.data() + n, t) - times_.data()) - 1;
  const double span = times_(k + 1) - times_(k);
  velocity = (points_.row(k + 1) - points_.row(k)).transpose() / span;
  position = points_.row(k).transpose() + (t - times_(k)) * velocity;
}

Eigen::Vector2d TipPlan::start_m() const {
  Eigen::Vector2d p, v;
  evaluate(0, p, v);
  return p;
}

Eigen::Vector2d TipPlan::end_m() const {
  Eigen::Vector2d p, v;
  evaluate(end_s_, p, v);
  return p;
}

Eigen::Vector2d dataset_push_direction_body(const ShapeInfo& shape, int side, double position, double angle) {
  const Outline outline(shape);
  const Outline::Closest c = outline.point_on_side(side, position);
  return Eigen::Rotation2Dd(angle) * Eigen::Vector2d(-c.normal);
}

Eigen::Vector2d perimeter_push_direction_body(const ForecastOutline& outline, double position, double angle) {
  return Eigen::Rotation2Dd(angle) * Eigen::Vector2d(-outline.point_at_perimeter_fraction(position).normal);
}

Eigen::Vector2d closest_normal_push_direction_body(const ForecastOutline& outline, const Eigen::Vector2d& tip_body,
                                                   double angle) {
  int hint = -1;
  const Outline::Closest c = outline.closest(tip_body, hint);
  return Eigen::Rotation2Dd(angle) * Eigen::Vector2d(-c.normal);
}

ForecastRun forecast_into(const ForecastObject& object, const ForecastParameters& par, const TipPlan& plan,
                          const Eigen::Vector3d& pose0, const Eigen::VectorXd& out_t,
                          Eigen::Ref<Eigen::MatrixX3d> poses, const ForecastSettings& s) {
  ForecastRun run;
  const ForecastOutline& outline = *object.outline;
  const double push_step = std::min(s.max_step_s, s.max_tip_step_m / std::max(plan.peak_speed_m_s(), 1e-6));
  const double linear_decel = par.support_friction * s.gravity_m_s2;  // F / m
  const double c2 = par.torque_ratio_m * par.torque_ratio_m;
  const double angular_decel = par.support_friction * object.mass_kg * s.gravity_m_s2 * c2 / object.inertia_kgm2;
  const PolynomialLimitSurface* surface =
      object.limit_surface == LimitSurfaceKind::Outline ? object.pressure_surface.get() : nullptr;
  if (object.limit_surface == LimitSurfaceKind::Outline &&
      (!surface || surface->centre_m() != object.centre_of_friction_m))
    throw std::logic_error("forecast: the outline limit surface is not about the centre of friction");
  // Warm starts of the surface's Newton solutions from the previous step (body frame).
  Eigen::Vector2d push_force_hint = Eigen::Vector2d::Zero();
  Eigen::Vector3d slide_wrench_hint = Eigen::Vector3d::Zero();
  const double support_force_per_kg = par.support_friction * s.gravity_m_s2;  // F / m
  const Eigen::Index n_out = out_t.size();
  Eigen::Index k = 0;
  while (k < n_out && out_t(k) <= 0) poses.row(k++) = pose0.transpose();

  Eigen::Vector3d pose = pose0;
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  // CoF velocity, world
  double w = 0;
  int hint = -1;
  double t = 0, sliding_time = 0;
  const double end = plan.end_time_s();
  Eigen::Vector2d tip, tip_velocity;
  for (;;) {
    const bool moving_plan = t < end - 1e-12;
    const double dt = moving_plan ? std::min(push_step, end - t) : s.slide_step_s;
    plan.evaluate(moving_plan ? t : end, tip, tip_velocity);
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(pose(2)).toRotationMatrix();
    const Eigen::Vector2d origin = pose.head<2>();
    const Outline::Closest c = outline.closest(R.transpose() * (tip - origin), hint);
    const double penetration = s.rod_radius_m - c.signed_distance_m;

    // The free slide over this step: the limit surface's Coulomb friction, stopping exactly. On the outline's
    // surface it costs a Newton solution, so it is found only where it is needed (free_slide below).
    Eigen::Vector2d v_free = v;
    double w_free = w;
    bool free_known = false;
    auto free_slide = [&] {
      if (free_known) return;
      free_known = true;
      if (surface) {
        if (v.squaredNorm() > 0 || w != 0) {
          const Eigen::Vector3d W = surface->wrench_for_twist(R.transpose() * v, w, &slide_wrench_hint);
          const Eigen::Vector2d a = -support_force_per_kg * (R * W.head<2>());
          const double alpha = -support_force_per_kg * object.mass_kg * W(2) / object.inertia_kgm2;
          // Stop where the step would dissipate the kinetic energy (for a pure translation or rotation: where the
          // step's deceleration exceeds the speed, as the ellipsoid's exact stop).
          const double kinetic2 = v.squaredNorm() + object.inertia_kgm2 / object.mass_kg * w * w;
          const double dissipated = -dt * (a.dot(v) + object.inertia_kgm2 / object.mass_kg * alpha * w);
          if (dissipated >= kinetic2) {
            v_free.setZero();
            w_free = 0;
          } else {
            v_free = v + dt * a;
            w_free = w + dt * alpha;
          }
        }
      } else {
        const double speed = std::sqrt(v.squaredNorm() + c2 * w * w);
        if (speed > 0) {
          v_free =
              speed <= linear_decel * dt ? Eigen::Vector2d::Zero() : Eigen::Vector2d(v - dt * linear_decel * v / speed);
          w_free = speed <= angular_decel * dt ? 0.0 : w - dt * angular_decel * w / speed;
        }
      }
    };
    bool pushed = false;
    if (penetration > -s.contact_slack_m) {
      const Eigen::Vector2d n = -(R * c.normal);
      const Eigen::Vector2d rc = R * (c.point_m - object.centre_of_friction_m);
      const Eigen::Vector2d vp = tip_velocity + n * (std::max(penetration, 0.0) / (s.gap_steps * dt));
      const double normal_speed = n.dot(vp);
      if (normal_speed > 0) {
        QuasiStaticMotion m;
        bool outruns = false;  // the object sliding freely would leave the tip's normal speed behind
        if (surface) {
          m = quasi_static_motion_on(*surface, c.point_m - object.centre_of_friction_m, -c.normal, R.transpose() * vp,
                                     par.pusher_friction, &push_force_hint);
          m.velocity_m_s = R * m.velocity_m_s;
          // Friction cannot speed the contact up by more than its largest force and moment allow (|f| <= 1 and
          // |m| <= rho on the surface per unit F; the quartic's within a few per cent, so a margin of 1.5): below
          // that bound the free slide need not be found.
          const double bound = (v + w * perp(rc)).dot(n) +
                               1.5 * dt * support_force_per_kg *
                                   (1 + object.mass_kg * surface->torque_ratio_m() * rc.norm() / object.inertia_kgm2);
          if (bound > normal_speed) {
            free_slide();
            outruns = (v_free + w_free * perp(rc)).dot(n) > normal_speed;
          }
        } else {
          m = quasi_static_motion(rc, n, vp, par.pusher_friction, par.torque_ratio_m);
          free_slide();
          outruns = (v_free + w_free * perp(rc)).dot(n) > normal_speed;
        }
        if (m.mode != ContactMode::None && !outruns) {
          pushed = true;
          v = m.velocity_m_s;
          w = m.omega_rad_s;
          run.contact_time_s += dt;
          if (m.mode != ContactMode::Sticking) sliding_time += dt;
        }
      }
    }
    if (!pushed) {
      free_slide();
      v = v_free;
      w = w_free;
    }
    Eigen::Vector3d next = pose;
    const Eigen::Vector2d cof_arm = R * object.centre_of_friction_m;
    next.head<2>() += dt * (v - w * perp(cof_arm));
    next(2) += dt * w;
    const double t_next = t + dt;
    for (; k < n_out && out_t(k) < t_next; ++k) {
      const double u = (out_t(k) - t) / dt;
      poses.row(k) = ((1 - u) * pose + u * next).transpose();
    }
    pose = next;
    t = t_next;
    const bool at_rest = v.squaredNorm() == 0 && w == 0;
    if (t >= end - 1e-12 && at_rest) break;
    if (t > end + s.max_slide_s) {
      run.reached_rest = false;
      break;
    }
  }
  for (; k < n_out; ++k) poses.row(k) = pose.transpose();
  run.rest_time_s = t;
  run.sliding_fraction = run.contact_time_s > 0 ? sliding_time / run.contact_time_s : 0;
  return run;
}

void check_tip_starts_outside(const ForecastObject& object, const TipPlan& plan, const Eigen::Vector3d& pose0,
                              const char* label, long plan_index) {
  const Eigen::Vector2d tip_body = Eigen::Rotation2Dd(-pose0(2)) * (plan.start_m() - pose0.head<2>());
  int hint = -1;
  const Outline::Closest c = object.outline->closest(tip_body, hint);
  if (c.signed_distance_m < 0) {
    char plan_name[40] = "";
    if (plan_index >= 0) std::snprintf(plan_name, sizeof plan_name, ": plan %ld", plan_index);
    char text[240];
    std::snprintf(text, sizeof text,
                  "%s%s: the tip starts %.1f mm inside the object's outline; a push starts with the tip outside it",
                  label, plan_name, -1e3 * c.signed_distance_m);
    throw InputError(text);
  }
}

Eigen::MatrixX3d forecast_poses(const ForecastObject& object, const ForecastParameters& parameters, const TipPlan& plan,
                                const Eigen::Vector3d& pose0, const Eigen::VectorXd& output_times_s,
                                const ForecastSettings& settings, ForecastRun* run) {
  object.validate();
  parameters.validate();
  if (!pose0.allFinite()) throw InputError("forecast: start pose must be finite");
  check_plausible_pose(pose0, "forecast: start pose");
  for (Eigen::Index k = 1; k < output_times_s.size(); ++k)
    if (!(output_times_s(k) >= output_times_s(k - 1))) throw InputError("forecast: output times must not decrease");
  Eigen::MatrixX3d poses(output_times_s.size(), 3);
  const ForecastRun r = forecast_into(object, parameters, plan, pose0, output_times_s, poses, settings);
  if (run) *run = r;
  return poses;
}

double forecast_rest_time_s(const ForecastObject& object, const ForecastParameters& parameters, const TipPlan& plan,
                            const Eigen::Vector3d& pose0, const ForecastSettings& settings) {
  Eigen::MatrixX3d none(0, 3);
  return forecast_into(object, parameters, plan, pose0, Eigen::VectorXd(0), none, settings).rest_time_s;
}

}  // namespace pushpred
