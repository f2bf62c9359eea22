#include "pushpred/simulation/simulator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/simulation/pushed_object_system.hpp"

namespace pushpred {
namespace {

Eigen::Matrix2d rotation(double yaw) { return Eigen::Rotation2Dd(yaw).toRotationMatrix(); }

/// Yaw wrapped to (-pi, pi], as the dataset stores it.
double wrap_angle(double a) {
  double w = std::remainder(a, 2 * M_PI);
  if (w <= -M_PI) w += 2 * M_PI;
  return w;
}

TimedStream make_stream(const Eigen::VectorXd& t, const Eigen::MatrixX3d& values) {
  TimedStream s;
  s.t_s = t;
  s.values = values;
  return s;
}

/// The object as the scenario's effects change it from the published one.
ObjectProperties perturbed_object(const ShapeInfo& shape, const Effects& fx) {
  ObjectProperties object = ObjectProperties::nominal(shape);
  object.mass_kg *= fx.inertia_factor;
  object.inertia_kgm2 *= fx.inertia_factor;
  object.mass_centre_m.x() += fx.com_offset_m;
  return object;
}

RodContact rod_contact(const PushScenario& scenario) {
  RodContact contact;
  contact.friction = scenario.contact_friction;
  contact.stiffness_N_m = scenario.contact_stiffness_N_m;
  contact.pusher_compliance_m_N = scenario.effects.pusher_compliance_m_N;
  return contact;
}

/// Where the object starts, which way the rod pushes it (in the body and the world) and the rod's path.
struct PushLayout {
  Eigen::Vector3d pose0;
  Eigen::Vector2d direction_body, direction_world;
  PusherPath path;
};

/// The layout from the contact side, position and push angle.
PushLayout push_layout(const PushScenario& scenario, const Outline& outline, const RodContact& contact) {
  const Outline::Closest side = outline.point_on_side(scenario.contact_side, scenario.contact_position);
  PushLayout layout;
  const Eigen::Vector2d start_body = side.point_m + (contact.rod_radius_m + scenario.approach_gap_m) * side.normal;
  layout.direction_body = rotation(scenario.push_angle_rad) * (-side.normal);
  layout.pose0 = Eigen::Vector3d(scenario.initial_x_m, scenario.initial_y_m, scenario.initial_yaw_rad);
  const Eigen::Matrix2d R0 = rotation(layout.pose0(2));
  const Eigen::Vector2d start_world = layout.pose0.head<2>() + R0 * start_body;
  layout.direction_world = R0 * layout.direction_body;
  layout.path = PusherPath(start_world, layout.direction_world, scenario.rest_before_s, scenario.motion);
  return layout;
}

SupportFriction support_friction(const PushScenario& scenario, const Outline& outline, const PushLayout& layout) {
  const Effects& fx = scenario.effects;
  SupportFriction support;
  support.coefficient = scenario.surface_friction;
  support.viscous_per_kg = fx.viscous_per_kg;
  support.pressure_rim_weight = scenario.pressure_rim_weight;
  support.stribeck_excess = fx.stribeck_excess;
  support.patch_excess = fx.position_friction_excess;
  // The patch lies on the push line, friction_patch_ahead_m beyond the object's leading point at the start: the
  // object runs onto it during the push.
  support.patch_centre_m =
      layout.pose0.head<2>() +
      (outline.extent_along(layout.direction_body) + scenario.friction_patch_ahead_m) * layout.direction_world;
  support.patch_radius_m = scenario.friction_patch_radius_m;
  support.tilt_rad = fx.support_tilt_deg * M_PI / 180;
  support.downhill = rotation(scenario.support_tilt_direction_rad) * Eigen::Vector2d::UnitX();
  support.anisotropy = fx.friction_anisotropy;
  return support;
}

/// The system; a mass-centre offset that puts the centre outside the object is named in the error.
PushedObjectSystem pushed_object_system(const PushScenario& scenario, const ShapeInfo& shape,
                                        const ObjectProperties& object, const SupportFriction& support,
                                        const RodContact& contact, const PusherPath& path) {
  const double com_offset_m = scenario.effects.com_offset_m;
  try {
    return PushedObjectSystem(shape, object, support, contact, path);
  } catch (const InputError& e) {
    if (com_offset_m == 0) throw;
    throw InputError("com_offset=" + std::to_string(com_offset_m) + " is too large for " + scenario.shape + ": " +
                     e.what());
  }
}

/// Each sensor's clock and noise.
struct SensorDraws {
  StreamSchedule object_clock, force_clock, tip_clock;
  Eigen::MatrixX3d object_noise, force_noise, tip_noise;
};

/// Clocks and noise, drawn in a fixed order from one generator: the same seed gives the same recording.
SensorDraws draw_sensors(const PushScenario& scenario, const SensorModel& sensors, double duration) {
  std::mt19937_64 rng(scenario.seed);
  const double js = scenario.sensors.jitter_scale, ns = scenario.sensors.noise_scale;
  SensorDraws d;
  d.object_clock = draw_schedule(sensors.object_pose.clock, duration, js, rng);
  d.force_clock = draw_schedule(sensors.ft_wrench.clock, duration, js, rng);
  d.tip_clock = draw_schedule(sensors.tip_pose.clock, duration, js, rng);
  for (const auto* c : {&d.object_clock, &d.force_clock, &d.tip_clock})
    if (c->stamp_s.size() < 2) throw InputError("the recording is too short for two sensor samples");
  d.object_noise = draw_noise(sensors.object_pose, sensors.slow_time_constant_s, d.object_clock.stamp_s, ns, rng);
  d.force_noise = draw_noise(sensors.ft_wrench, sensors.slow_time_constant_s, d.force_clock.stamp_s, ns, rng);
  d.tip_noise = draw_noise(sensors.tip_pose, sensors.slow_time_constant_s, d.tip_clock.stamp_s, ns, rng);
  return d;
}

/// The instants at which the object and the force are sampled, and all of them sorted without repeats.
struct SampleInstants {
  Eigen::VectorXd object, force;
  std::vector<double> all;
};

SampleInstants sample_instants(const PusherPath& path, const SensorDraws& draws, double time_offset_s) {
  // The force sensor lags by time_offset: its sample stamped at grid time t holds the force at t - offset.
  // An instant a rounding error away from a phase boundary of the rod is taken as that boundary (the state is
  // continuous there): CVODE cannot step a few ulps past the point where it was re-initialised.
  const std::vector<double> boundaries = path.phase_boundaries();
  auto snapped = [&](Eigen::VectorXd t) {
    for (double& v : t)
      for (double b : boundaries)
        if (std::abs(v - b) < 1e-9) v = b;
    return t;
  };
  SampleInstants s;
  s.object = snapped(draws.object_clock.sample_s);
  s.force = snapped(draws.force_clock.sample_s.array() - time_offset_s);
  s.all.assign(s.object.data(), s.object.data() + s.object.size());
  s.all.insert(s.all.end(), s.force.data(), s.force.data() + s.force.size());
  std::sort(s.all.begin(), s.all.end());
  s.all.erase(std::unique(s.all.begin(), s.all.end()), s.all.end());
  return s;
}

/// The truth at every output instant, from the integrated states; returns the rod's torque about its axis.
Eigen::VectorXd record_truth(const PushedObjectSystem& system, const Eigen::MatrixXd& states,
                             const Eigen::VectorXd& out_times, SimulatedPush& sim) {
  const Eigen::Index n = out_times.size();
  sim.t_s = out_times;
  sim.tracked_pose.resize(n, 3);
  sim.mass_centre_velocity.resize(n, 3);
  sim.force_on_object_N.resize(n, 2);
  sim.sensed_force_N.resize(n, 2);
  sim.touching.assign(n, 0);
  Eigen::VectorXd rod_torque(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::VectorXd x = states.row(k).transpose();
    sim.tracked_pose.row(k) = system.tracked_pose(x).transpose();
    sim.mass_centre_velocity.row(k) = x.segment<3>(3).transpose();
    const RodWrench w = system.rod_wrench(out_times(k), x);
    sim.force_on_object_N.row(k) = w.force_on_object_N.transpose();
    // Behind a compliant pusher's spring the sensor reads the spring's force (the tip's inertia between).
    const Eigen::Vector2d sensed =
        system.compliant() ? system.pusher_spring_force_N(out_times(k), x) : w.force_on_object_N;
    sim.sensed_force_N.row(k) = sensed.transpose();
    sim.touching[k] = w.touching;
    rod_torque(k) = w.torque_about_rod_Nm;
  }
  return rod_torque;
}

/// The row of the truth at instant t (one of the sorted instants).
Eigen::Index row_at(const std::vector<double>& instants, double t) {
  const auto it = std::lower_bound(instants.begin(), instants.end(), t);
  return static_cast<Eigen::Index>(it - instants.begin());
}

TimedStream object_pose_stream(const SimulatedPush& sim, const SampleInstants& instants, const SensorDraws& draws,
                               double unix0) {
  const Eigen::Index m = instants.object.size();
  Eigen::MatrixX3d v(m, 3);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Index k = row_at(instants.all, instants.object(i));
    v.row(i) = sim.tracked_pose.row(k) + draws.object_noise.row(i);
    v(i, 2) = wrap_angle(v(i, 2));
  }
  return make_stream(draws.object_clock.stamp_s.array() + unix0, v);
}

TimedStream ft_wrench_stream(const SimulatedPush& sim, const Eigen::VectorXd& rod_torque,
                             const SampleInstants& instants, const SensorDraws& draws, double force_offset_N,
                             const Eigen::Vector2d& push_offset_N, double unix0) {
  const Eigen::Index m = instants.force.size();
  Eigen::MatrixX3d v(m, 3);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Index k = row_at(instants.all, instants.force(i));
    // The sensor reads the reaction on the pusher, plus any bias and this push's own zero error.
    v(i, 0) = -sim.sensed_force_N(k, 0) + force_offset_N + push_offset_N.x();
    v(i, 1) = -sim.sensed_force_N(k, 1) + force_offset_N + push_offset_N.y();
    v(i, 2) = -rod_torque(k);
  }
  return make_stream(draws.force_clock.stamp_s.array() + unix0, v + draws.force_noise);
}

TimedStream tip_pose_stream(const PusherPath& path, const SensorDraws& draws, double unix0) {
  const Eigen::Index m = draws.tip_clock.sample_s.size();
  Eigen::MatrixX3d v(m, 3);
  for (Eigen::Index i = 0; i < m; ++i) {
    v.row(i).head<2>() = path.position_m(draws.tip_clock.sample_s(i)).transpose();
    v(i, 2) = 0.0;
  }
  v += draws.tip_noise;
  return make_stream(draws.tip_clock.stamp_s.array() + unix0, v);
}

}  // namespace

Eigen::MatrixX3d patch_wrench_per_excess(const SimulatedPush& sim) {
  const PushScenario& scenario = sim.scenario;
  const ShapeInfo& shape = ShapeTable::published().find(scenario.shape);
  const ObjectProperties object = perturbed_object(shape, scenario.effects);
  const Outline outline(shape);
  const RodContact contact = rod_contact(scenario);
  const PushLayout layout = push_layout(scenario, outline, contact);
  SupportFriction with = support_friction(scenario, outline, layout), without = with;
  with.patch_excess = 1;
  without.patch_excess = 0;
  // Only the support's friction differs between the two systems; the rest of the wrench (drag, tilt) cancels.
  const PushedObjectSystem a = pushed_object_system(scenario, shape, object, with, contact, layout.path);
  const PushedObjectSystem b = pushed_object_system(scenario, shape, object, without, contact, layout.path);
  Eigen::MatrixX3d out(sim.t_s.size(), 3);
  for (Eigen::Index k = 0; k < sim.t_s.size(); ++k) {
    Eigen::VectorXd x = a.state_at_rest(sim.tracked_pose.row(k).transpose());
    x.segment<3>(3) = sim.mass_centre_velocity.row(k).transpose();
    const PlanarWrench wa = a.support_wrench(x), wb = b.support_wrench(x);
    out.row(k) << (wa.force_N - wb.force_N).transpose(), wa.torque_Nm - wb.torque_Nm;
  }
  return out;
}

SimulatedPush simulate_push(const PushScenario& scenario, const SensorModel& sensors) {
  scenario.validate();
  const ShapeInfo& shape = ShapeTable::known().find(scenario.shape);
  const Effects& fx = scenario.effects;
  const ObjectProperties object = perturbed_object(shape, fx);
  const Outline outline(shape);
  const RodContact contact = rod_contact(scenario);
  const PushLayout layout = push_layout(scenario, outline, contact);
  const PusherPath& path = layout.path;
  const SupportFriction support = support_friction(scenario, outline, layout);
  const PushedObjectSystem system = pushed_object_system(scenario, shape, object, support, contact, path);
  const double duration = path.end_time_s() + scenario.rest_after_s;

  const SensorDraws draws = draw_sensors(scenario, sensors, duration);
  const SampleInstants instants = sample_instants(path, draws, fx.time_offset_s);
  const double t0 = std::min(0.0, instants.all.front());
  IntegratorOptions options;
  options.method = IntegratorOptions::Method::Bdf;
  options.relative_tolerance = 1e-6;
  options.absolute_tolerance = 1e-9;
  const Eigen::VectorXd out_times = Eigen::Map<const Eigen::VectorXd>(instants.all.data(), instants.all.size());
  CvodeIntegrator::Stats stats;
  const Eigen::MatrixXd states = integrate(system, options, t0, system.state_at_rest(layout.pose0), out_times, &stats);

  SimulatedPush sim;
  sim.scenario = scenario;
  sim.solver = stats;
  sim.push_start_s = path.start_time_s();
  sim.push_end_s = path.end_time_s();
  sim.rod_peak_speed_m_s = path.peak_speed_m_s();
  const Eigen::VectorXd rod_torque = record_truth(system, states, out_times, sim);

  Recording& rec = sim.recording;
  rec.source = scenario.name.empty() ? "simulated push" : scenario.name;
  rec.push = scenario.push_parameters();
  const double unix0 = scenario.start_unix_s;
  rec.object_pose = object_pose_stream(sim, instants, draws, unix0);
  rec.ft_wrench =
      ft_wrench_stream(sim, rod_torque, instants, draws, fx.force_offset_N, scenario.sensors.push_offset_N, unix0);
  rec.tip_pose = tip_pose_stream(path, draws, unix0);
  return sim;
}

Recording as_read(const Recording& raw) {
  Recording r;
  r.source = raw.source;
  r.push = raw.push;
  auto condition = [&](const char* name, const TimedStream& s) {
    Eigen::MatrixXd rows(s.size(), 4);
    rows.col(0) = s.t_s;
    rows.rightCols<3>() = s.values;
    return condition_stream(raw.source, name, rows, ReadOptions{}, r.repairs);
  };
  r.tip_pose = condition("tip_pose", raw.tip_pose);
  r.object_pose = condition("object_pose", raw.object_pose);
  r.ft_wrench = condition("ft_wrench", raw.ft_wrench);
  return r;
}

std::filesystem::path simulated_output_path(const PushScenario& scenario, const std::filesystem::path& out) {
  const std::string text = out.string();
  if (text.empty()) throw InputError("no output path given");
  const bool folder = std::filesystem::is_directory(out) || text.back() == '/';
  return folder ? out / push_filename(scenario.push_parameters(), ".h5") : out;
}

PushScenario scenario_like_recording(const std::filesystem::path& real_path, double surface_friction,
                                     double contact_friction) {
  const Recording r = read_recording(real_path);
  const SynchronisedPush p = synchronise(r, shape_for(r, ""));
  const std::string source = real_path.string();
  if (!r.push) throw InputError(about(source, "file name does not carry the push parameters"));
  const PushParameters& q = *r.push;
  if (q.contact_side != std::round(q.contact_side))
    throw InputError(about(source, "contact side is not a whole number"));

  PushScenario s;
  s.name = "like " + real_path.filename().string();
  s.shape = q.shape;
  s.surface = q.surface;
  s.surface_friction = surface_friction;
  s.contact_friction = contact_friction;
  if (q.acceleration_m_s2 > 0) {
    s.motion.profile = PusherMotion::Profile::ConstantAcceleration;
    s.motion.acceleration_m_s2 = q.acceleration_m_s2;
  } else {
    if (!(q.speed_m_s > 0)) throw InputError(about(source, "push speed in the file name is not positive"));
    s.motion.speed_m_s = q.speed_m_s;
  }
  s.contact_side = static_cast<int>(std::round(q.contact_side));
  s.contact_position = q.contact_position;
  s.push_angle_rad = q.angle_rad;
  s.start_unix_s = p.t0_unix_s;
  s.seed = 1;

  // Initial pose and gap from the first samples, averaged over a few against the noise.
  const Eigen::Index n = p.size(), head = std::min<Eigen::Index>(5, n);
  const Eigen::Vector3d pose0 = p.pose.topRows(head).colwise().mean().transpose();
  const Eigen::Vector2d tip0 = p.tip_m.topRows(head).colwise().mean().transpose();
  s.initial_x_m = pose0(0);
  s.initial_y_m = pose0(1);
  s.initial_yaw_rad = wrap_angle(pose0(2));
  const Eigen::Vector2d tip_body = rotation(pose0(2)).transpose() * (tip0 - pose0.head<2>());
  s.approach_gap_m = std::clamp(Outline(p.shape).closest(tip_body).signed_distance_m - kPusherRadius_m, 0.0, 0.05);

  // Rest before and after and the push length, from the tip's motion; the raised-cosine ramp reaches 5 % of
  // its speed 0.1436 of a ramp after it starts, and the same before it stops.
  const Eigen::Vector2d travel = p.tip_m.row(n - 1).transpose() - tip0;
  s.motion.length_m = std::max(1e-3, travel.norm());
  const Eigen::Vector2d u = travel.normalized();
  const double v_ref = q.acceleration_m_s2 > 0 ? 0.0 : q.speed_m_s;
  double t_go = NAN, t_halt = NAN;
  for (Eigen::Index k = 2; k + 2 < n; ++k) {
    const double v = (p.tip_m.row(k + 2) - p.tip_m.row(k - 2)).dot(u.transpose()) / (p.t_s(k + 2) - p.t_s(k - 2));
    const double threshold = v_ref > 0 ? 0.05 * v_ref : 2e-3;
    if (v > threshold) {
      if (std::isnan(t_go)) t_go = p.t_s(k);
      t_halt = p.t_s(k);
    }
  }
  const double lead = 0.1436 * s.motion.ramp_s;
  if (!std::isnan(t_go)) s.rest_before_s = std::max(0.02, t_go - lead);
  if (!std::isnan(t_halt)) s.rest_after_s = std::max(0.02, p.duration_s() - t_halt - lead);

  // A rod already pressing before the push (a live sensor reading over 0.5 N at rest) starts that far inside.
  if (!p.flags.frozen_force_sensor && !std::isnan(t_go)) {
    std::vector<double> rest;
    for (Eigen::Index k = 0; k < n && p.t_s(k) < t_go - 0.02; ++k) rest.push_back(p.force_N.row(k).norm());
    if (rest.size() >= 5) {
      std::nth_element(rest.begin(), rest.begin() + rest.size() / 2, rest.end());
      const double preload = rest[rest.size() / 2];
      if (preload > 0.5) s.approach_gap_m = std::max(-0.001, -preload / RodContact().stiffness_N_m);
    }
  }
  s.validate();
  return s;
}

}  // namespace pushpred
