// A simulated push is a recording like the real ones: same layout and naming, same clocks and noise, and it
// moves the object the way the real pushes moved theirs.
#include <hdf5.h>

#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <limits>

#include "pushpred/core/error.hpp"
#include "pushpred/jobs/inspection_job.hpp"
#include "pushpred/jobs/real_comparison_job.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/simulation/simulator.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::TempFolder;

namespace {

/// A short push (50 mm/s, 3 cm) of rect2, for tests that need a realistic file quickly.
PushScenario short_push(std::uint64_t seed = 1) {
  PushScenario s;
  s.name = "test push";
  s.shape = "rect2";
  s.motion.speed_m_s = 0.05;
  s.motion.length_m = 0.03;
  s.contact_side = 0;
  s.contact_position = 0.6;
  s.push_angle_rad = 0.2;
  s.initial_yaw_rad = 0.7;
  s.seed = seed;
  return s;
}

hsize_t root_links(const std::filesystem::path& path) {
  const hid_t file = H5Fopen(path.string().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  H5G_info_t info;
  H5Gget_info(file, &info);
  H5Fclose(file);
  return info.nlinks;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(simulate)

BOOST_AUTO_TEST_CASE(a_simulated_file_loads_and_inspects_like_a_real_one) {
  TempFolder tmp;
  const PushScenario s = short_push();
  const SimulatedPush sim = simulate_push(s);
  const auto path = simulated_output_path(s, tmp.path().string() + "/");
  write_recording_hdf5(sim.recording, path);

  BOOST_TEST(path.filename().string() == "motion_surface=abs_shape=rect2_a=0_v=50_i=0.000_s=0.600_t=0.200.h5");
  BOOST_TEST(root_links(path) == 3u);  // tip_pose, object_pose, ft_wrench and nothing else

  const SynchronisedPush p = load_push(path);
  BOOST_TEST(p.push.shape == "rect2");
  BOOST_TEST(p.push.speed_m_s == 0.05, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(p.has_contact);
  BOOST_TEST(p.flags.names().empty());
  BOOST_TEST(p.t0_unix_s > 1.5e9);
  BOOST_TEST(p.stream_rate_hz[0] == 250.0, boost::test_tools::tolerance(0.01));
  BOOST_TEST(p.stream_rate_hz[1] == 250.0, boost::test_tools::tolerance(0.01));
  BOOST_TEST(p.stream_rate_hz[2] == 248.0, boost::test_tools::tolerance(0.01));
  const Inspection i = inspect(p);
  BOOST_TEST(i.travel_mm > 20.0);
  BOOST_TEST(i.travel_mm < 31.0);
  BOOST_TEST(i.mean_contact_force_N > 3.0);  // about mu m g = 0.47 x 1.045 x 9.81 = 4.8 N while pushing
  BOOST_TEST(i.max_tip_yaw_deg < 0.01);
  // The rod, 1 mm away at first, reaches the object soon after it starts (the detected contact may start
  // earlier: at a 0.25 N threshold the force noise can trip it, as in real files).
  const auto first_touch = std::find(sim.touching.begin(), sim.touching.end(), 1) - sim.touching.begin();
  BOOST_TEST(sim.t_s(first_touch) > s.rest_before_s);
  BOOST_TEST(sim.t_s(first_touch) < s.rest_before_s + 0.1);
  BOOST_TEST(p.contact_end_s > sim.push_end_s - 0.1);
  // Yaw as stored lies in (-pi, pi].
  for (Eigen::Index k = 0; k < sim.recording.object_pose.size(); ++k)
    BOOST_TEST_REQUIRE(std::abs(sim.recording.object_pose.values(k, 2)) <= M_PI);
}

BOOST_AUTO_TEST_CASE(the_same_seed_gives_the_same_file_and_another_seed_other_noise) {
  TempFolder tmp;
  write_recording_hdf5(simulate_push(short_push(7)).recording, tmp / "a.h5");
  write_recording_hdf5(simulate_push(short_push(7)).recording, tmp / "b.h5");
  write_recording_hdf5(simulate_push(short_push(8)).recording, tmp / "c.h5");
  const Recording a = read_recording(tmp / "a.h5"), b = read_recording(tmp / "b.h5"), c = read_recording(tmp / "c.h5");
  BOOST_TEST((a.object_pose.t_s == b.object_pose.t_s));
  BOOST_TEST((a.object_pose.values == b.object_pose.values));
  BOOST_TEST((a.ft_wrench.t_s == b.ft_wrench.t_s));
  BOOST_TEST((a.ft_wrench.values == b.ft_wrench.values));
  BOOST_TEST((a.tip_pose.t_s == b.tip_pose.t_s));
  BOOST_TEST((a.tip_pose.values == b.tip_pose.values));
  BOOST_TEST(!(a.ft_wrench.values.rows() == c.ft_wrench.values.rows() && a.ft_wrench.values == c.ft_wrench.values));
}

BOOST_AUTO_TEST_CASE(simulated_clocks_and_noise_measure_like_the_real_ones) {
  // The measurement that set SensorModel::mcube() from the real files gives about the same from simulated ones.
  TempFolder tmp;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    PushScenario s = short_push(seed);
    s.motion.length_m = 0.05;
    s.motion.speed_m_s = 0.05;
    write_recording_hdf5(simulate_push(s).recording, simulated_output_path(s, tmp / std::to_string(seed) / ""));
  }
  const RecordingStatistics sim = measure_recordings({tmp.path().string()});
  const RecordingStatistics real = measure_recordings({(resolve_data_folder() / "abs").string()});
  BOOST_TEST(sim.files == 8);
  for (int k = 0; k < 3; ++k) {
    BOOST_TEST(sim.rate_hz[k] == real.rate_hz[k], boost::test_tools::tolerance(0.002));
    BOOST_TEST(sim.median_interval_s[k] == real.median_interval_s[k], boost::test_tools::tolerance(0.03));
  }
  BOOST_TEST(sim.interval_core_std_s[0] == real.interval_core_std_s[0], boost::test_tools::tolerance(0.2));
  BOOST_TEST(sim.late_share[0] == real.late_share[0], boost::test_tools::tolerance(0.4));
  BOOST_TEST(sim.tip_short_share == real.tip_short_share, boost::test_tools::tolerance(0.1));
  BOOST_TEST(sim.tip_short_s == real.tip_short_s, boost::test_tools::tolerance(0.03));
  BOOST_TEST(sim.tip_long_s == real.tip_long_s, boost::test_tools::tolerance(0.03));
  BOOST_TEST(sim.tip_interval_lag1 == real.tip_interval_lag1, boost::test_tools::tolerance(0.25));
  BOOST_TEST(sim.tip_rate_spread_hz[0] > 247.5);
  BOOST_TEST(sim.tip_rate_spread_hz[1] < 248.5);
  for (int stream : {0, 1})
    for (int c = 0; c < 3; ++c) {
      BOOST_TEST(sim.noise_white[stream][c] == real.noise_white[stream][c], boost::test_tools::tolerance(0.25));
      BOOST_TEST(sim.noise_total[stream][c] == real.noise_total[stream][c], boost::test_tools::tolerance(0.35));
    }
  BOOST_TEST(sim.rest_before_s == real.rest_before_s, boost::test_tools::tolerance(0.1));
  BOOST_TEST(sim.rest_after_s == real.rest_after_s, boost::test_tools::tolerance(0.1));
  BOOST_TEST(sim.ramp_5_95_s == real.ramp_5_95_s, boost::test_tools::tolerance(0.1));
  BOOST_TEST(sim.push_length_m == real.push_length_m, boost::test_tools::tolerance(0.01));
}

BOOST_AUTO_TEST_CASE(clean_simulations_of_the_real_pushes_move_the_objects_as_the_real_ones_did) {
  // Every real push of an object with a listed outline, simulated with the same parameters, pose and timing:
  // docs/simulator.md gives the table. rect1's force sensor is frozen, but travel and rotation come from the
  // object tracker.
  const auto data = resolve_data_folder() / "abs";
  std::vector<std::string> rect1, others;
  for (const auto& p : list_recordings(data)) {
    const std::string name = p.filename().string();
    if (name.find("rect1") != std::string::npos)
      rect1.push_back(p.string());
    else if (name.find("butter") == std::string::npos)
      others.push_back(p.string());
  }
  const double mu = PushScenario().surface_friction;
  const auto r = compare_with_real(rect1, mu);
  const auto o = compare_with_real(others, mu);
  BOOST_TEST(r.failures.empty());
  BOOST_TEST(o.failures.empty());
  const ComparisonSummary sr = summarise_comparison(r, mu), so = summarise_comparison(o, mu);
  BOOST_TEST(sr.pushes == 13);
  BOOST_TEST(sr.mean_abs_travel_mm < 1.5);
  BOOST_TEST(sr.mean_abs_rotation_deg < 3.5);
  BOOST_TEST(so.pushes == 37);
  BOOST_TEST(so.mean_abs_travel_mm < 3.0);
  BOOST_TEST(so.mean_abs_rotation_deg < 7.0);
  BOOST_TEST(so.mean_abs_duration_s < 0.02);
  // The force level: the default surface friction is the one that matches it (docs/simulator.md).
  BOOST_TEST(so.matching_surface_friction == mu, boost::test_tools::tolerance(0.05));
}

BOOST_AUTO_TEST_CASE(the_paper_cases_are_rect2_on_abs_at_the_table_speeds) {
  const double speed[6] = {0.01, 0.01, 0.01, 0.05, 0, 0};
  const double accel[6] = {0, 0, 0, 0, 0.2, 2.5};
  for (int n = 1; n <= 6; ++n) {
    const PushScenario s = paper_case_scenario(n);
    BOOST_TEST(s.shape == "rect2");
    BOOST_TEST(s.surface == "abs");
    if (accel[n - 1] > 0) {
      BOOST_TEST((s.motion.profile == PusherMotion::Profile::ConstantAcceleration));
      BOOST_TEST(s.motion.acceleration_m_s2 == accel[n - 1]);
      BOOST_TEST(s.push_parameters().speed_m_s == -0.001);  // the dataset's marker, as in the paper's table
    } else {
      BOOST_TEST((s.motion.profile == PusherMotion::Profile::ConstantSpeed));
      BOOST_TEST(s.motion.speed_m_s == speed[n - 1]);
    }
    BOOST_TEST(s.effects.active().empty());
  }
  // The three 10 mm/s cases differ in where and how the rod pushes.
  const PushScenario a = paper_case_scenario(1), b = paper_case_scenario(2), c = paper_case_scenario(3);
  BOOST_TEST((a.contact_position != b.contact_position || a.push_angle_rad != b.push_angle_rad));
  BOOST_TEST((b.contact_side != c.contact_side || b.push_angle_rad != c.push_angle_rad));
  BOOST_CHECK_THROW(paper_case_scenario(0), InputError);
  BOOST_CHECK_THROW(paper_case_scenario(7), InputError);
}

BOOST_AUTO_TEST_CASE(a_scenario_survives_a_json_round_trip) {
  PushScenario s = paper_case_scenario(5);
  s.effects.set("com_offset", 0.01);
  s.effects.set("time_offset", -0.02);
  s.sensors.noise_scale = 0.5;
  s.friction_patch_radius_m = 0.05;
  const PushScenario t = scenario_from_json(scenario_to_json(s), "round trip");
  BOOST_TEST(scenario_to_json(t).dump() == scenario_to_json(s).dump());
  BOOST_TEST(t.friction_patch_radius_m == 0.05);
  BOOST_TEST(t.effects.com_offset_m == 0.01);
  BOOST_TEST(t.effects.time_offset_s == -0.02);
}

BOOST_AUTO_TEST_CASE(bad_scenarios_are_input_errors_that_name_the_problem) {
  auto error_of = [](const nlohmann::json& j) {
    try {
      scenario_from_json(j, "bad.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BOOST_TEST(error_of({{"shap", "rect2"}}).find("unknown field 'shap'") != std::string::npos);
  BOOST_TEST(error_of({{"shape", "rect9"}}).find("unknown shape 'rect9'") != std::string::npos);
  BOOST_TEST(error_of({{"shape", "butter"}}).find("no outline") != std::string::npos);
  BOOST_TEST(error_of({{"effects", {{"wind", 1.0}}}}).find("unknown effect 'wind'") != std::string::npos);
  BOOST_TEST(error_of({{"effects", {{"inertia_mismatch", -1.0}}}}).find("must be in [0.1, 10]") != std::string::npos);
  BOOST_TEST(error_of({{"contact_side", 5}}).find("contact_side: contact side 5") != std::string::npos);
  BOOST_TEST(error_of({{"friction_patch_radius_m", -0.01}})
                 .find("bad.json: friction_patch_radius_m: must be in (0, 1] m, got -0.01") != std::string::npos);
  // Each field is named by its key in the file, and a friction coefficient or an effect is bounded (1e300 made CVODE
  // give up, exit 1).
  BOOST_TEST(error_of({{"contact_friction", -1.0}})
                 .find("bad.json: contact_friction: must be a finite number in [0, 10], got -1") != std::string::npos);
  BOOST_TEST(error_of({{"surface_friction", 1e300}})
                 .find("surface_friction: must be a finite number in (0, 10], got 1e+300") != std::string::npos);
  BOOST_TEST(error_of({{"sensors", {{"noise_scale", 1e300}}}}).find("sensors.noise_scale: must be in [0, 100]") !=
             std::string::npos);
  for (const char* effect :
       {"force_offset", "viscous_friction", "stribeck_friction", "position_friction", "inertia_mismatch"})
    BOOST_TEST(error_of({{"effects", {{effect, 1e300}}}}).find(std::string("effect ") + effect + "=1e+300: ") !=
               std::string::npos);
  BOOST_TEST(error_of({{"speed_m_s", "fast"}}).find("must be a number") != std::string::npos);
  BOOST_TEST(error_of({{"speed_m_s", 0.01}, {"acceleration_m_s2", 1.0}}).find("not both") != std::string::npos);
  BOOST_TEST(error_of({{"push_angle_rad", 2.0}}).find("push_angle_rad: must be within (-pi/2, pi/2) rad") !=
             std::string::npos);
  BOOST_TEST(error_of({{"shape", "rect2"}}).find("bad.json") == std::string::npos);  // a good one passes
  // Names given by the caller (simulate's flags) replace the keys.
  PushScenario flagged;
  flagged.contact_friction = std::numeric_limits<double>::infinity();
  try {
    flagged.validate({{"contact_friction", "--contact-mu"}});
    BOOST_FAIL("an infinite contact friction passed");
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()) == "--contact-mu: must be a finite number in [0, 10], got inf");
  }
  // A seed is a whole number from 0 to 2^64 - 1: no sign (a negative seed wrapped around), no overflow, no exponent.
  BOOST_TEST(parse_seed("0") == 0u);
  BOOST_TEST(parse_seed("18446744073709551615") == std::numeric_limits<std::uint64_t>::max());
  for (const char* bad : {"-1", "18446744073709551616", "1e3", "", " 1", "+1", "0x10"})
    BOOST_CHECK_THROW(parse_seed(bad), InputError);
  BOOST_CHECK_THROW(parse_effect_assignment("time_offset"), InputError);
  BOOST_CHECK_THROW(parse_effect_assignment("time_offset=soon"), InputError);
  BOOST_CHECK_THROW(parse_effect_assignment("gravity=2"), InputError);
  BOOST_TEST(parse_effect_assignment("force_offset=0.5").second == 0.5);
  TempFolder tmp;
  pushpred::testing::write_text(tmp / "broken.json", "{\"shape\": ");
  BOOST_CHECK_THROW(read_scenario_file(tmp / "broken.json"), InputError);
  BOOST_CHECK_THROW(read_scenario_file(tmp / "missing.json"), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
