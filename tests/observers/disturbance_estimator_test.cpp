// The common interface: estimators chosen by name, the same shape of output, the re-simulation check.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <string>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/observers/observation.hpp"
#include "pushpred/observers/resimulation.hpp"
#include "synthetic_push.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(disturbance_estimator)

BOOST_AUTO_TEST_CASE(estimators_are_chosen_by_name) {
  for (const std::string& name : disturbance_estimator_names()) BOOST_TEST(make_disturbance_estimator(name)->name() == name);
  try {
    make_disturbance_estimator("kalman");
    BOOST_FAIL("an unknown estimator was made");
  } catch (const InputError& e) {
    const std::string what = e.what();
    BOOST_TEST(what.find("kalman") != std::string::npos);
    BOOST_TEST(what.find("dob") != std::string::npos);
    BOOST_TEST(what.find("pid") != std::string::npos);
  }
}

BOOST_AUTO_TEST_CASE(every_estimator_answers_on_the_push_grid_in_the_same_form) {
  pushpred::testing::SyntheticPushSpec spec;
  spec.disturbance = [](int c, double) { return c == 2 ? 0.0 : -1.0; };
  const SynchronisedPush push = pushpred::testing::synthetic_push(spec);
  for (const std::string& name : disturbance_estimator_names()) {
    const DisturbanceEstimate e = make_disturbance_estimator(name)->estimate(push, 0.2, 0.6);
    BOOST_TEST_INFO(name);
    BOOST_TEST(e.estimator == name);
    const Eigen::Index first = push.index_at(0.2), n = e.t_s.size();
    BOOST_TEST(n == 101);  // 0.2 to 0.6 s at 250 Hz, both ends included
    BOOST_TEST(e.t_s(0) == push.t_s(first));
    BOOST_TEST((e.u - push.applied_input().middleRows(first, n)).cwiseAbs().maxCoeff() == 0.0);
    BOOST_TEST(e.d_hat.rows() == n);
    BOOST_TEST(e.total.rows() == n);
    BOOST_TEST(e.velocity.rows() == n);
    BOOST_TEST(e.nominal_inertia(0) == push.shape.mass_kg);
    BOOST_TEST(e.nominal_inertia(2) == push.shape.inertia_kgm2);
    BOOST_TEST(e.d_hat.allFinite());
  }
}

BOOST_AUTO_TEST_CASE(re_simulation_needs_an_estimate_of_the_same_push) {
  pushpred::testing::SyntheticPushSpec spec;
  spec.disturbance = [](int, double) { return 0.0; };
  const SynchronisedPush push = pushpred::testing::synthetic_push(spec);
  DisturbanceEstimate e = make_disturbance_estimator("dob")->estimate(push, 0.2, 0.6);
  e.t_s.array() += 0.001;  // off the grid
  BOOST_CHECK_THROW(resimulate_pose(push, e), InputError);
  BOOST_CHECK_THROW(resimulate_pose(push, DisturbanceEstimate{}), InputError);
}

BOOST_AUTO_TEST_CASE(an_observation_writes_both_estimates_side_by_side) {
  pushpred::testing::SyntheticPushSpec spec;
  spec.disturbance = [](int c, double t) { return c == 2 ? 0.0 : -1.0 - (t > 0.5); };
  const SynchronisedPush push = pushpred::testing::synthetic_push(spec);
  const Observation o = observe_push(push);
  const auto files = observation_files(o);
  BOOST_TEST_REQUIRE(files.size() >= 3u);
  BOOST_TEST(files[0].name == "observer.csv");
  const std::string& csv = files[0].text;
  BOOST_TEST(csv.substr(0, csv.find('\n')) ==
             "t_s,u_x_N,u_y_N,u_theta_Nm,dob_d_x_N,dob_d_y_N,dob_d_theta_Nm,pid_d_x_N,pid_d_y_N,pid_d_theta_Nm,"
             "dob_v_x_m_s,dob_v_y_m_s,dob_v_theta_rad_s,pid_v_x_m_s,pid_v_y_m_s,pid_v_theta_rad_s");
  BOOST_TEST(std::count(csv.begin(), csv.end(), '\n') == push.size() + 1);
  // The numbers are those of the parts.
  BOOST_TEST((o.rms_dob_minus_pid - rms_difference(o.dob.d_hat, o.pid.d_hat)).norm() == 0.0);
  BOOST_TEST((o.rms_resimulation_pid - rms_difference(resimulate_pose(push, o.pid), push.pose)).norm() == 0.0);
  BOOST_TEST(o.rms_resimulation_dob.allFinite());
}

BOOST_AUTO_TEST_SUITE_END()
