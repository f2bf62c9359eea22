#include <boost/test/unit_test.hpp>

#include "pushpred/core/error.hpp"
#include "pushpred/prediction/planned_force.hpp"
#include "pushpred/prediction/schedule.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::real_file;

BOOST_AUTO_TEST_SUITE(schedule)

BOOST_AUTO_TEST_CASE(four_equal_intervals_cover_the_whole_recording) {
  const SynchronisedPush push = load_push(real_file("shape=ellip3_a=0_v=10_"));
  const auto iv = split_into_intervals(push, ScheduleOptions{});
  BOOST_REQUIRE_EQUAL(iv.size(), 4u);
  BOOST_TEST(iv.front().t0_s == 0.0);
  BOOST_TEST(iv.back().t1_s == push.duration_s());
  for (size_t k = 0; k < iv.size(); ++k) {
    BOOST_TEST(iv[k].duration_s() == push.duration_s() / 4, boost::test_tools::tolerance(1e-12));
    if (k > 0) BOOST_TEST(iv[k].t0_s == iv[k - 1].t1_s);
  }
}

BOOST_AUTO_TEST_CASE(the_contact_span_option_splits_only_the_span_in_contact) {
  const SynchronisedPush push = load_push(real_file("shape=ellip3_a=0_v=10_"));
  ScheduleOptions o;
  o.span = ScheduleSpan::ContactOnly;
  o.intervals = 5;
  const auto iv = split_into_intervals(push, o);
  BOOST_REQUIRE_EQUAL(iv.size(), 5u);
  BOOST_TEST(iv.front().t0_s == push.contact_start_s);
  BOOST_TEST(iv.back().t1_s == push.contact_end_s);
  BOOST_TEST(push.contact_start_s > 0.1);  // this push starts out of contact
}

BOOST_AUTO_TEST_CASE(a_push_too_short_for_four_intervals_is_a_clear_error) {
  SynchronisedPush push = load_push(real_file("shape=hex_a=0_v=50"));
  const Eigen::Index n = 30;  // 0.116 s: 7 samples per interval
  push.t_s.conservativeResize(n);
  try {
    split_into_intervals(push, ScheduleOptions{});
    BOOST_ERROR("no error");
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()).find("push too short for 4 intervals") != std::string::npos);
  }
  BOOST_CHECK_THROW(split_into_intervals(push, ScheduleOptions{1}), InputError);
  BOOST_CHECK_THROW(parse_schedule_span("halfway"), InputError);
}

BOOST_AUTO_TEST_CASE(the_held_planned_force_is_exact_at_the_10_hz_points) {
  const SynchronisedPush push = load_push(real_file("shape=ellip3_a=0_v=10_"));
  const PlannedForce plan = plan_from_measurement(push, 1.0, 2.0, 10.0);
  const Eigen::MatrixX3d u = push.applied_input();
  BOOST_REQUIRE_EQUAL(plan.signal.samples(), 10);
  for (int k = 0; k < 10; ++k) {
    const double t = 1.0 + 0.1 * k;
    const Eigen::RowVector3d measured = u.row(push.index_at(t));
    BOOST_TEST_REQUIRE((plan.signal(t).transpose() - measured).norm() == 0.0);
    // Held until the next 10 Hz point.
    BOOST_TEST_REQUIRE((plan.signal(t + 0.0999).transpose() - measured).norm() == 0.0);
  }
  BOOST_TEST(plan.signal.jumps(1.0, 2.0).size() == 9u);
  BOOST_CHECK_THROW(plan_from_measurement(push, 1.0, 0.5), InputError);
  BOOST_CHECK_THROW(plan_from_measurement(push, 1.0, 2.0, 0.0), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
