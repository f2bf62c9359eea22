// The common interface: estimators chosen by name, the same shape of output, the re-simulation check.
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/observers/observation.hpp"
#include "pushpred/observers/resimulation.hpp"
#include "synthetic_push.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(disturbance_estimator)

BOOST_AUTO_TEST_CASE(every_estimator_checks_its_nominal_inertia_alike) {
  // 0 picks the shape's; a negative or non-finite value is an error naming the estimator and the value.
  BOOST_CHECK_NO_THROW(require_nominal_inertia_choice(0.0, 0.0, "x"));
  BOOST_CHECK_NO_THROW(require_nominal_inertia_choice(1.045, 0.002, "x"));
  const auto message = [](double mass_kg, double inertia_kgm2) {
    try {
      require_nominal_inertia_choice(mass_kg, inertia_kgm2, "some estimator");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BOOST_TEST(message(-1.5, 0.0) ==
             "some estimator: nominal mass must be positive (or 0 for the shape's), got -1.500000 kg");
  BOOST_TEST(message(0.0, -0.25) ==
             "some estimator: nominal moment of inertia must be positive (or 0 for the shape's), got -0.250000 kg m^2");
  BOOST_TEST(message(std::nan(""), 0.0) != "no error");
  BOOST_TEST(message(0.0, HUGE_VAL) != "no error");
}

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

BOOST_AUTO_TEST_CASE(an_observation_holds_both_estimates_side_by_side) {
  pushpred::testing::SyntheticPushSpec spec;
  spec.disturbance = [](int c, double t) { return c == 2 ? 0.0 : -1.0 - (t > 0.5); };
  const SynchronisedPush push = pushpred::testing::synthetic_push(spec);
  const Observation o = observe_push(push);
  // The whole push, one row per sample in each part (its files: tests/reports/test_observation_report.cpp).
  BOOST_TEST(o.dob.t_s.size() == push.size());
  BOOST_TEST(o.pid.t_s.size() == push.size());
  BOOST_TEST(o.resimulated_dob.rows() == push.size());
  // The numbers are those of the parts, the RMS recomputed here by its definition rather than by rms_difference.
  const auto rms = [](const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b, int c) {
    double sum = 0;
    for (Eigen::Index k = 0; k < a.rows(); ++k) sum += (a(k, c) - b(k, c)) * (a(k, c) - b(k, c));
    return std::sqrt(sum / static_cast<double>(a.rows()));
  };
  const Eigen::MatrixX3d resimulated = resimulate_pose(push, o.pid);
  for (int c = 0; c < 3; ++c) {
    BOOST_TEST_INFO("channel " << c);
    BOOST_TEST(o.rms_dob_minus_pid(c) == rms(o.dob.d_hat, o.pid.d_hat, c), boost::test_tools::tolerance(1e-12));
    BOOST_TEST(o.rms_resimulation_pid(c) == rms(resimulated, push.pose, c), boost::test_tools::tolerance(1e-12));
  }
  BOOST_TEST(o.rms_dob_minus_pid.maxCoeff() > 0.0);  // the two estimates differ: the check above is not 0 == 0
  BOOST_TEST(o.rms_resimulation_dob.allFinite());
}

BOOST_AUTO_TEST_CASE(the_rms_difference_of_hand_made_columns) {
  Eigen::MatrixX3d a(2, 3), b = Eigen::MatrixX3d::Zero(2, 3);
  a << 1, 2, 3,  //
      3, -2, 1;
  // sqrt((1 + 9) / 2), sqrt((4 + 4) / 2), sqrt((9 + 1) / 2)
  const Eigen::RowVector3d r = rms_difference(a, b);
  BOOST_TEST(r(0) == std::sqrt(5.0), boost::test_tools::tolerance(1e-15));
  BOOST_TEST(r(1) == 2.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(r(2) == std::sqrt(5.0), boost::test_tools::tolerance(1e-15));
  BOOST_CHECK_THROW(rms_difference(a, Eigen::MatrixX3d::Zero(3, 3)), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
