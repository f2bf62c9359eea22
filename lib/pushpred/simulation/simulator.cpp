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

// Where the position-friction patch sits, from the effect's definition (scenario.hpp).
constexpr double kPatchRadius_m = kFrictionPatchRadius_m;
constexpr double kPatchAlongPath_m = kFrictionPatchAhead_m;

}  // namespace

SimulatedPush simulate_push(const PushScenario& scenario, const SensorModel& sensors) {
  scenario.validate();
  const ShapeInfo& shape = ShapeTable::published().find(scenario.shape);
  const Effects& fx = scenario.effects;

  ObjectProperties object = ObjectProperties::nominal(shape);
  object.mass_kg *= fx.inertia_factor;
  object.inertia_kgm2 *= fx.inertia_factor;
  object.mass_centre_m.x() += fx.com_offset_m;

  // Where the rod starts and where it goes, from the contact side, position and push angle.
  const Outline outline(shape);
  const Outline::Closest side = outline.point_on_side(scenario.contact_side, scenario.contact_position);
  RodContact contact;
  contact.friction = scenario.contact_friction;
  contact.stiffness_N_m = scenario.contact_stiffness_N_m;
  const Eigen::Vector2d start_body = side.point_m + (contact.rod_radius_m + scenario.approach_gap_m) * side.normal;
  const Eigen::Vector2d direction_body = rotation(scenario.push_angle_rad) * (-side.normal);
  const Eigen::Vector3d pose0(scenario.initial_x_m, scenario.initial_y_m, scenario.initial_yaw_rad);
  const Eigen::Matrix2d R0 = rotation(pose0(2));
  const Eigen::Vector2d start_world = pose0.head<2>() + R0 * start_body;
  const Eigen::Vector2d direction_world = R0 * direction_body;
  const PusherPath path(start_world, direction_world, scenario.rest_before_s, scenario.motion);

  SupportFriction support;
  support.coefficient = scenario.surface_friction;
  support.viscous_per_kg = fx.viscous_per_kg;
  support.pressure_rim_weight = scenario.pressure_rim_weight;
  support.stribeck_excess = fx.stribeck_excess;
  support.patch_excess = fx.position_friction_excess;
  // The patch lies on the push line, kPatchAlongPath_m beyond the object's leading point at the start: the object
  // runs onto it during the push.
  support.patch_centre_m =
      pose0.head<2>() + (outline.extent_along(direction_body) + kPatchAlongPath_m) * direction_world;
  support.patch_radius_m = kPatchRadius_m;

  const PushedObjectSystem system = [&] {
    try {
      return PushedObjectSystem(shape, object, support, contact, path);
    } catch (const InputError& e) {
      if (fx.com_offset_m == 0) throw;
      throw InputError("com_offset=" + std::to_string(fx.com_offset_m) + " is too large for " + scenario.shape + ": " +
                       e.what());
    }
  }();
  const double duration = path.end_time_s() + scenario.rest_after_s;

  // Clocks and noise, drawn in a fixed order from one generator: the same seed gives the same recording.
  std::mt19937_64 rng(scenario.seed);
  const double js = scenario.sensors.jitter_scale, ns = scenario.sensors.noise_scale;
  const StreamSchedule object_clock = draw_schedule(sensors.object_pose.clock, duration, js, rng);
  const StreamSchedule force_clock = draw_schedule(sensors.ft_wrench.clock, duration, js, rng);
  const StreamSchedule tip_clock = draw_schedule(sensors.tip_pose.clock, duration, js, rng);
  for (const auto* c : {&object_clock, &force_clock, &tip_clock})
    if (c->stamp_s.size() < 2) throw InputError("the recording is too short for two sensor samples");
  const Eigen::MatrixX3d object_noise =
      draw_noise(sensors.object_pose, sensors.slow_time_constant_s, object_clock.stamp_s, ns, rng);
  const Eigen::MatrixX3d force_noise =
      draw_noise(sensors.ft_wrench, sensors.slow_time_constant_s, force_clock.stamp_s, ns, rng);
  const Eigen::MatrixX3d tip_noise =
      draw_noise(sensors.tip_pose, sensors.slow_time_constant_s, tip_clock.stamp_s, ns, rng);

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
  const Eigen::VectorXd object_instants = snapped(object_clock.sample_s);
  const Eigen::VectorXd force_instants = snapped(force_clock.sample_s.array() - fx.time_offset_s);
  std::vector<double> instants(object_instants.data(), object_instants.data() + object_instants.size());
  instants.insert(instants.end(), force_instants.data(), force_instants.data() + force_instants.size());
  std::sort(instants.begin(), instants.end());
  instants.erase(std::unique(instants.begin(), instants.end()), instants.end());
  const double t0 = std::min(0.0, instants.front());

  IntegratorOptions options;
  options.method = IntegratorOptions::Method::Bdf;
  options.relative_tolerance = 1e-6;
  options.absolute_tolerance = 1e-9;
  const Eigen::VectorXd out_times = Eigen::Map<const Eigen::VectorXd>(instants.data(), instants.size());
  CvodeIntegrator::Stats stats;
  const Eigen::MatrixXd states = integrate(system, options, t0, system.state_at_rest(pose0), out_times, &stats);

  SimulatedPush sim;
  sim.scenario = scenario;
  sim.solver = stats;
  sim.push_start_s = path.start_time_s();
  sim.push_end_s = path.end_time_s();
  sim.rod_peak_speed_m_s = path.peak_speed_m_s();
  const Eigen::Index n = out_times.size();
  sim.t_s = out_times;
  sim.tracked_pose.resize(n, 3);
  sim.mass_centre_velocity.resize(n, 3);
  sim.force_on_object_N.resize(n, 2);
  sim.touching.assign(n, 0);
  Eigen::VectorXd rod_torque(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::VectorXd x = states.row(k).transpose();
    sim.tracked_pose.row(k) = system.tracked_pose(x).transpose();
    sim.mass_centre_velocity.row(k) = x.tail<3>().transpose();
    const RodWrench w = system.rod_wrench(out_times(k), x);
    sim.force_on_object_N.row(k) = w.force_on_object_N.transpose();
    sim.touching[k] = w.touching;
    rod_torque(k) = w.torque_about_rod_Nm;
  }
  auto row_at = [&](double t) {
    const auto it = std::lower_bound(instants.begin(), instants.end(), t);
    return static_cast<Eigen::Index>(it - instants.begin());
  };

  Recording& rec = sim.recording;
  rec.source = scenario.name.empty() ? "simulated push" : scenario.name;
  rec.push = scenario.push_parameters();
  const double unix0 = scenario.start_unix_s;
  {
    const Eigen::Index m = object_instants.size();
    Eigen::MatrixX3d v(m, 3);
    for (Eigen::Index i = 0; i < m; ++i) {
      const Eigen::Index k = row_at(object_instants(i));
      v.row(i) = sim.tracked_pose.row(k) + object_noise.row(i);
      v(i, 2) = wrap_angle(v(i, 2));
    }
    rec.object_pose = make_stream(object_clock.stamp_s.array() + unix0, v);
  }
  {
    const Eigen::Index m = force_instants.size();
    Eigen::MatrixX3d v(m, 3);
    for (Eigen::Index i = 0; i < m; ++i) {
      const Eigen::Index k = row_at(force_instants(i));
      // The sensor reads the reaction on the pusher, plus any bias.
      v(i, 0) = -sim.force_on_object_N(k, 0) + fx.force_offset_N;
      v(i, 1) = -sim.force_on_object_N(k, 1) + fx.force_offset_N;
      v(i, 2) = -rod_torque(k);
    }
    rec.ft_wrench = make_stream(force_clock.stamp_s.array() + unix0, v + force_noise);
  }
  {
    const Eigen::Index m = tip_clock.sample_s.size();
    Eigen::MatrixX3d v(m, 3);
    for (Eigen::Index i = 0; i < m; ++i) {
      v.row(i).head<2>() = path.position_m(tip_clock.sample_s(i)).transpose();
      v(i, 2) = 0.0;
    }
    v += tip_noise;
    rec.tip_pose = make_stream(tip_clock.stamp_s.array() + unix0, v);
  }
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
