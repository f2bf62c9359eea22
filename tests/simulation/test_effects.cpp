// Each hidden effect changes the simulated recording the way its physics says, and only that way.
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "pushpred/simulation/pushed_object_system.hpp"
#include "pushpred/simulation/simulator.hpp"

using namespace pushpred;

namespace {
const double kG = SupportFriction().gravity_m_s2;  // 9.81 m/s^2
}  // namespace

namespace {

/// rect2 pushed through the middle of its +y side straight in (along its long axis), ideal sensors.
PushScenario central_push(double speed_m_s, double length_m = 0.04) {
  PushScenario s;
  s.shape = "rect2";
  s.motion.speed_m_s = speed_m_s;
  s.motion.length_m = length_m;
  s.contact_side = 0;
  s.contact_position = 0.5;
  s.push_angle_rad = 0;
  s.approach_gap_m = 0;
  s.initial_yaw_rad = 0.3;
  s.sensors.noise_scale = 0;
  s.sensors.jitter_scale = 0;
  return s;
}

SimulatedPush run(PushScenario s, const char* effect = nullptr, double amount = 0) {
  if (effect) s.effects.set(effect, amount);
  return simulate_push(s);
}

/// Mean |force on the object| over the truth samples whose time lies in [t0, t1].
double mean_force(const SimulatedPush& sim, double t0, double t1) {
  double sum = 0;
  int n = 0;
  for (Eigen::Index k = 0; k < sim.t_s.size(); ++k)
    if (sim.t_s(k) >= t0 && sim.t_s(k) <= t1) {
      sum += sim.force_on_object_N.row(k).norm();
      ++n;
    }
  BOOST_REQUIRE(n > 10);
  return sum / n;
}

/// The cruise of a constant-speed push, after the contact has settled and before the stop ramp.
double cruise_force(const SimulatedPush& sim) {
  const double ramp = sim.scenario.motion.ramp_s;
  return mean_force(sim, sim.push_start_s + ramp + 0.15, sim.push_end_s - ramp - 0.01);
}

/// Mean force while the object's tracked centre has moved between d0 and d1 metres.
double force_at_travel(const SimulatedPush& sim, double d0, double d1) {
  double sum = 0;
  int n = 0;
  for (Eigen::Index k = 0; k < sim.t_s.size(); ++k) {
    const double d = (sim.tracked_pose.row(k).head<2>() - sim.tracked_pose.row(0).head<2>()).norm();
    if (d >= d0 && d <= d1 && sim.t_s(k) < sim.push_end_s - sim.scenario.motion.ramp_s) {
      sum += sim.force_on_object_N.row(k).norm();
      ++n;
    }
  }
  BOOST_REQUIRE(n > 10);
  return sum / n;
}

double final_rotation_deg(const SimulatedPush& sim) {
  const Eigen::Index n = sim.t_s.size();
  return (sim.tracked_pose(n - 1, 2) - sim.tracked_pose(0, 2)) * 180 / M_PI;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(effects)

BOOST_AUTO_TEST_CASE(force_offset_shifts_every_force_reading_and_shows_while_not_touching) {
  PushScenario s = central_push(0.05, 0.02);
  s.approach_gap_m = 0.002;
  const SimulatedPush clean = run(s), biased = run(s, "force_offset", 0.4);
  BOOST_REQUIRE_EQUAL(clean.recording.ft_wrench.size(), biased.recording.ft_wrench.size());
  const Eigen::MatrixX3d d = biased.recording.ft_wrench.values - clean.recording.ft_wrench.values;
  BOOST_TEST((d.col(0).array() - 0.4).abs().maxCoeff() < 1e-9);
  BOOST_TEST((d.col(1).array() - 0.4).abs().maxCoeff() < 1e-9);
  BOOST_TEST(d.col(2).cwiseAbs().maxCoeff() < 1e-12);
  BOOST_TEST((biased.recording.object_pose.values == clean.recording.object_pose.values));

  // With the real sensor noise (slow drift up to 0.1 N) a 1 N bias stands out in the rest before the rod
  // arrives, where the clean reading averages near 0.
  s.sensors.noise_scale = 1;
  s.sensors.jitter_scale = 1;
  auto rest_mean = [&](const SimulatedPush& sim) {
    const TimedStream& ft = sim.recording.ft_wrench;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int n = 0;
    for (Eigen::Index k = 0; k < ft.size(); ++k)
      if (ft.t_s(k) - s.start_unix_s < s.rest_before_s) {
        sum += ft.values.row(k).head<2>().transpose();
        ++n;
      }
    BOOST_REQUIRE(n > 30);
    return Eigen::Vector2d(sum / n);
  };
  const Eigen::Vector2d without = rest_mean(run(s)), with = rest_mean(run(s, "force_offset", 1.0));
  BOOST_TEST(without.cwiseAbs().maxCoeff() < 0.3);
  BOOST_TEST(with.minCoeff() > 0.7);
  BOOST_TEST(with.maxCoeff() < 1.3);
}

BOOST_AUTO_TEST_CASE(time_offset_delays_the_force_stream_against_the_poses) {
  const PushScenario s = central_push(0.05, 0.02);
  const double lag = 8 * 0.004;  // eight force periods: the delayed stream repeats the clean one 8 samples later
  const SimulatedPush clean = run(s), late = run(s, "time_offset", lag);
  const TimedStream &a = clean.recording.ft_wrench, &b = late.recording.ft_wrench;
  BOOST_REQUIRE_EQUAL(a.size(), b.size());
  BOOST_TEST((a.t_s == b.t_s));  // stamps unchanged: the sensor does not know it lags
  double worst = 0, moved = 0;
  for (Eigen::Index k = 8; k < a.size(); ++k) {
    worst = std::max(worst, (b.values.row(k) - a.values.row(k - 8)).norm());
    moved = std::max(moved, (b.values.row(k) - a.values.row(k)).norm());
  }
  // Equal to solver accuracy: positions to about 1e-6 of 0.4 m on a 1e4 N/m contact, a few mN.
  BOOST_TEST(worst < 5e-3);
  BOOST_TEST(moved > 1.0);
  // The poses are those of the same motion (integrated to other output instants: equal to solver accuracy).
  BOOST_TEST((late.recording.object_pose.values - clean.recording.object_pose.values).cwiseAbs().maxCoeff() < 1e-7);
  BOOST_TEST((late.recording.tip_pose.values == clean.recording.tip_pose.values));
}

BOOST_AUTO_TEST_CASE(viscous_friction_adds_a_drag_proportional_to_speed) {
  const double c = 2.0;  // N s/m per kg
  const double mass = ShapeTable::published().find("rect2").mass_kg;
  for (double v : {0.02, 0.08}) {
    const PushScenario s = central_push(v);
    const double extra = cruise_force(run(s, "viscous_friction", c)) - cruise_force(run(s));
    BOOST_TEST(extra == c * mass * v, boost::test_tools::tolerance(0.05));
  }
}

BOOST_AUTO_TEST_CASE(stribeck_friction_raises_the_force_at_low_speed_only) {
  const double slow_rise =
      cruise_force(run(central_push(0.01), "stribeck_friction", 0.5)) / cruise_force(run(central_push(0.01))) - 1;
  const double fast_rise =
      cruise_force(run(central_push(0.08), "stribeck_friction", 0.5)) / cruise_force(run(central_push(0.08))) - 1;
  // Steady sliding at 10 mm/s would give 0.5 exp(-1) = 0.18; the falling friction makes the push stick and slip,
  // so the mean lies between the sliding and the static value.
  BOOST_TEST(slow_rise > 0.1);
  BOOST_TEST(slow_rise < 0.5);
  BOOST_TEST(std::abs(fast_rise) < 0.01);
}

BOOST_AUTO_TEST_CASE(position_friction_grows_as_the_object_runs_onto_the_patch) {
  const PushScenario s = central_push(0.05, 0.06);
  const SimulatedPush clean = run(s), patched = run(s, "position_friction", 1.0);
  const ShapeInfo& rect2 = ShapeTable::published().find("rect2");
  const double patch_share = M_PI * 0.02 * 0.02 / (rect2.dim1_m * rect2.dim2_m);  // of the uniform load
  auto rise = [&](double d0, double d1) {
    return force_at_travel(patched, d0, d1) / force_at_travel(clean, d0, d1) - 1;
  };
  // The patch's near rim is 5 mm ahead of the leading side, its far rim 45 mm.
  BOOST_TEST(std::abs(rise(0.001, 0.004)) < 0.003);
  BOOST_TEST(rise(0.023, 0.027) > 0.35 * patch_share);
  BOOST_TEST(rise(0.023, 0.027) < 0.65 * patch_share);
  BOOST_TEST(rise(0.048, 0.052) == patch_share, boost::test_tools::tolerance(0.05));
}

BOOST_AUTO_TEST_CASE(the_patch_has_the_size_and_place_the_scenario_gives) {
  PushScenario s = central_push(0.05, 0.03);
  const auto rise = [&](const PushScenario& u, double excess) {
    return force_at_travel(run(u, "position_friction", excess), 0.010, 0.020) / force_at_travel(run(u), 0.010, 0.020);
  };
  // A disk of 30 cm radius centred 2.5 cm ahead of rect2's leading side covers the whole footprint: the support's
  // friction is mu (1 + excess) everywhere.
  s.friction_patch_radius_m = 0.3;
  BOOST_TEST(rise(s, 0.5) == 1.5, boost::test_tools::tolerance(0.01));
  // A disk of 3 cm centred 4 cm behind the leading side lies under the object throughout: the rise is the excess
  // times the disk's share of the (uniform) load.
  const ShapeInfo& rect2 = ShapeTable::published().find("rect2");
  s.friction_patch_radius_m = 0.03;
  s.friction_patch_ahead_m = -0.04;
  BOOST_TEST(rise(s, 0.5) == 1 + 0.5 * M_PI * 0.03 * 0.03 / (rect2.dim1_m * rect2.dim2_m),
             boost::test_tools::tolerance(0.01));
  // A disk beyond the push's reach changes nothing.
  s.friction_patch_radius_m = 0.01;
  s.friction_patch_ahead_m = 0.3;
  BOOST_TEST(rise(s, 0.5) == 1.0, boost::test_tools::tolerance(1e-6));
}

BOOST_AUTO_TEST_CASE(com_offset_turns_a_push_through_the_tracked_centre) {
  const PushScenario s = central_push(0.05, 0.05);
  const SimulatedPush clean = run(s), right = run(s, "com_offset", 0.01), left = run(s, "com_offset", -0.01);
  BOOST_TEST(std::abs(final_rotation_deg(clean)) < 0.05);
  // The rod pushes along -y at x = 0; a mass centre at x = +1 cm takes the push's torque counter-clockwise.
  BOOST_TEST(final_rotation_deg(right) > 2.0);
  BOOST_TEST(final_rotation_deg(left) == -final_rotation_deg(right), boost::test_tools::tolerance(0.02));
  // The tracker still reports the tracked centre, not the mass centre.
  BOOST_TEST(right.recording.object_pose.values(0, 0) == s.initial_x_m, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(right.recording.object_pose.values(0, 1) == s.initial_y_m);
}

BOOST_AUTO_TEST_CASE(inertia_mismatch_scales_the_force_to_accelerate_but_not_the_free_slide) {
  PushScenario s = central_push(0.05, 0.05);
  s.motion.profile = PusherMotion::Profile::ConstantAcceleration;
  s.motion.acceleration_m_s2 = 0.5;
  const SimulatedPush nominal = run(s), heavy = run(s, "inertia_mismatch", 1.5);
  // While the rod accelerates the object, the force is m (mu g + a): everything scales with the mass.
  const double accel_end = nominal.push_end_s - s.motion.ramp_s;
  const double f_nominal = mean_force(nominal, nominal.push_start_s + 0.15, accel_end - 0.01);
  const double f_heavy = mean_force(heavy, heavy.push_start_s + 0.15, accel_end - 0.01);
  const double mass = ShapeTable::published().find("rect2").mass_kg;
  BOOST_TEST(f_nominal == mass * (s.surface_friction * kG + 0.5), boost::test_tools::tolerance(0.02));
  BOOST_TEST(f_heavy / f_nominal == 1.5, boost::test_tools::tolerance(0.02));

  // At 2.5 m/s^2 the rod stops hard and the object slides on alone, decelerated by mu g whatever its mass.
  s.motion.acceleration_m_s2 = 2.5;
  for (double factor : {1.0, 1.5}) {
    const SimulatedPush sim = run(s, "inertia_mismatch", factor);
    int free_samples = 0;
    for (Eigen::Index k = 1; k < sim.t_s.size(); ++k) {
      const double dt = sim.t_s(k) - sim.t_s(k - 1);
      if (sim.touching[k] || sim.touching[k - 1] || dt < 1e-3) continue;
      const double v0 = sim.mass_centre_velocity.row(k - 1).head<2>().norm();
      const double v1 = sim.mass_centre_velocity.row(k).head<2>().norm();
      if (v1 < 0.02) continue;
      BOOST_TEST((v0 - v1) / dt == s.surface_friction * kG, boost::test_tools::tolerance(0.01));
      ++free_samples;
    }
    BOOST_TEST(free_samples > 10);
  }
}

BOOST_AUTO_TEST_CASE(support_tilt_adds_m_g_sin_alpha_against_an_uphill_push_and_with_a_downhill_one) {
  // Pushed straight along the slope at constant speed: mu m g cos(alpha) +- m g sin(alpha).
  const double alpha_deg = 2, alpha = alpha_deg * M_PI / 180, mu = 0.47;
  const double mass = ShapeTable::published().find("rect2").mass_kg;
  PushScenario s = central_push(0.05);
  const double push_yaw = s.initial_yaw_rad - M_PI / 2;  // side 0 pushes along the body's -y
  for (const double sign : {1.0, -1.0}) {                // +1: the push goes uphill (downhill opposite to it)
    s.support_tilt_direction_rad = sign > 0 ? push_yaw + M_PI : push_yaw;
    const double expected = mass * kG * (mu * std::cos(alpha) + sign * std::sin(alpha));
    BOOST_TEST(cruise_force(run(s, "support_tilt", alpha_deg)) == expected, boost::test_tools::tolerance(0.01));
  }
}

BOOST_AUTO_TEST_CASE(anisotropic_friction_sets_each_body_axis_own_pushing_force_keeping_the_mean) {
  // mu_x / mu_y = 1.4, mean 0.47: pushed along the body's y axis (side 0) mu_y m g, along x (side 1) mu_x m g.
  const double r = 1.4, mu = 0.47;
  const double mass = ShapeTable::published().find("rect2").mass_kg;
  PushScenario s = central_push(0.05);
  const double along_y = cruise_force(run(s, "anisotropic_friction", r));
  s.contact_side = 1;
  const double along_x = cruise_force(run(s, "anisotropic_friction", r));
  BOOST_TEST(along_y == mu * 2 / (1 + r) * mass * kG, boost::test_tools::tolerance(0.01));
  BOOST_TEST(along_x == mu * 2 * r / (1 + r) * mass * kG, boost::test_tools::tolerance(0.01));
  BOOST_TEST(0.5 * (along_x + along_y) == mu * mass * kG, boost::test_tools::tolerance(0.01));
}

BOOST_AUTO_TEST_CASE(compliant_pusher_keeps_the_recorded_tip_on_its_path_while_the_object_lags_by_f_c) {
  const double compliance = 1e-3, mu = 0.47;  // 1000 N/m
  const double mass = ShapeTable::published().find("rect2").mass_kg;
  // The spring and the object ring at sqrt(k / m) (4.4 Hz; Coulomb friction does not damp it): a long cruise, so
  // that its means are over many periods.
  const PushScenario s = central_push(0.05, 0.15);
  const SimulatedPush clean = run(s), soft = run(s, "compliant_pusher", compliance);
  BOOST_TEST((soft.recording.tip_pose.values == clean.recording.tip_pose.values));  // the commanded path
  // In the cruise the object is f c further behind than on the rigid pusher, and the sensor reads the push.
  double lag = 0;
  int n = 0;
  const double ramp = s.motion.ramp_s;
  for (Eigen::Index k = 0; k < clean.t_s.size(); ++k)
    if (clean.t_s(k) > clean.push_start_s + ramp + 0.2 && clean.t_s(k) < clean.push_end_s - ramp - 0.01) {
      lag += (clean.tracked_pose.row(k).head<2>() - soft.tracked_pose.row(k).head<2>()).norm();
      ++n;
    }
  BOOST_REQUIRE(n > 10);
  BOOST_TEST(lag / n == mu * mass * kG * compliance, boost::test_tools::tolerance(0.03));
  BOOST_TEST(cruise_force(soft) == mu * mass * kG, boost::test_tools::tolerance(0.01));
}

BOOST_AUTO_TEST_CASE(a_push_offset_shifts_this_push_fx_and_fy_readings_by_exactly_its_amount) {
  PushScenario s = central_push(0.05, 0.02);
  const SimulatedPush clean = run(s);
  s.sensors.push_offset_N = Eigen::Vector2d(-1.2, 0.7);
  const SimulatedPush offset = run(s);
  const Eigen::MatrixX3d d = offset.recording.ft_wrench.values - clean.recording.ft_wrench.values;
  BOOST_TEST((d.col(0).array() + 1.2).abs().maxCoeff() < 1e-9);
  BOOST_TEST((d.col(1).array() - 0.7).abs().maxCoeff() < 1e-9);
  BOOST_TEST(d.col(2).cwiseAbs().maxCoeff() < 1e-12);
  BOOST_TEST((offset.recording.object_pose.values == clean.recording.object_pose.values));
}

BOOST_AUTO_TEST_CASE(a_preload_presses_with_stiffness_times_depth_before_the_tip_moves) {
  PushScenario s = central_push(0.05, 0.02);
  s.approach_gap_m = -2e-4;  // 1e4 N/m x 0.2 mm = 2 N, below rect2's friction mu m g: the object stays put
  const SimulatedPush pressed = run(s);
  BOOST_TEST(mean_force(pressed, 0.05, s.rest_before_s - 0.01) == 2.0, boost::test_tools::tolerance(0.01));
}

BOOST_AUTO_TEST_SUITE_END()
