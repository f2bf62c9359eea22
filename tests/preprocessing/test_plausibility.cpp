// check_plausible refuses recordings that are well-formed but are not pushes of the dataset, naming the stream and
// the problem, and accepts every real recording.
#include <boost/test/unit_test.hpp>

#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/plausibility.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "test_support.hpp"

using namespace pushpred;

namespace {

/// A plausible recording: three streams at 250 Hz for 2 s from Unix time 1.5e9, a push of 5 cm with 2 N.
Recording plausible_recording() {
  Recording r;
  r.source = "synthetic.h5";
  r.push = PushParameters{"abs", "rect1", 0, 0.025, 0, 0.5, 0};
  const auto stream = [](double x0, double force) {
    TimedStream s;
    s.t_s = Eigen::VectorXd::LinSpaced(500, 1.5e9, 1.5e9 + 499 / 250.0);
    s.values.resize(500, 3);
    for (Eigen::Index i = 0; i < 500; ++i) s.values.row(i) << x0 + 1e-4 * i + force, 0.02, 0.1;
    return s;
  };
  r.object_pose = stream(0.3, 0);
  r.tip_pose = stream(0.25, 0);
  r.ft_wrench = stream(0, -2.0);
  return r;
}

void expect_refused(const Recording& r, const std::string& problem) {
  try {
    check_plausible(r);
    BOOST_ERROR("accepted: " + problem);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    BOOST_TEST_INFO("message: " << msg);
    BOOST_TEST(msg.rfind(r.source + ": ", 0) == 0);
    BOOST_TEST(msg.find(problem) != std::string::npos);
  }
}

}  // namespace

BOOST_AUTO_TEST_SUITE(plausibility)

BOOST_AUTO_TEST_CASE(a_plausible_recording_passes) { BOOST_CHECK_NO_THROW(check_plausible(plausible_recording())); }

BOOST_AUTO_TEST_CASE(time_stamps_in_milliseconds_are_refused) {
  Recording r = plausible_recording();
  r.ft_wrench.t_s *= 1e3;
  expect_refused(r, "stream 'ft_wrench' has time stamps near 1.5e+12, which are not Unix seconds (milliseconds?)");
  r = plausible_recording();
  r.object_pose.t_s = (r.object_pose.t_s.array() - 1.5e9) * 1e3;  // relative milliseconds: 4 units per sample
  expect_refused(r, "stream 'object_pose' runs at 0.25 Hz (median step 4 s), outside 25 to 2.5e+03 Hz");
}

BOOST_AUTO_TEST_CASE(a_rate_far_from_the_datasets_is_refused) {
  Recording r = plausible_recording();
  r.tip_pose.t_s = Eigen::VectorXd::LinSpaced(500, 1.5e9, 1.5e9 + 499 * 0.1);  // 10 Hz
  expect_refused(r, "stream 'tip_pose' runs at 10 Hz");
  r = plausible_recording();
  r.tip_pose.t_s = Eigen::VectorXd::LinSpaced(500, 1.5e9, 1.5e9 + 499 * 1e-4);  // 10 kHz
  expect_refused(r, "stream 'tip_pose' runs at 1e+04 Hz");
}

BOOST_AUTO_TEST_CASE(a_gap_far_longer_than_the_push_is_refused) {
  Recording r = plausible_recording();
  r.object_pose.t_s(499) += 1e5;
  expect_refused(r, "stream 'object_pose' has a gap of 1e+05 s between rows 498 and 499");
}

BOOST_AUTO_TEST_CASE(a_stream_longer_than_ten_minutes_is_refused) {
  PlausibilityLimits slow;  // steps of 0.9 s pass the gap bound; a slow rate is allowed here to reach the span bound
  slow.min_rate_hz = 1.0;
  Recording r = plausible_recording();
  r.ft_wrench.t_s = Eigen::VectorXd::LinSpaced(500, 1.5e9, 1.5e9 + 499 * 0.9);  // 449 s
  BOOST_CHECK_NO_THROW(check_plausible(r, slow));
  r.ft_wrench.t_s = Eigen::VectorXd::LinSpaced(1000, 1.5e9, 1.5e9 + 999 * 0.9);  // 899 s
  r.ft_wrench.values = Eigen::MatrixX3d::Zero(1000, 3);
  BOOST_CHECK_EXCEPTION(check_plausible(r, slow), InputError, [](const InputError& e) {
    return std::string(e.what()).find("stream 'ft_wrench' spans 899 s, longer than the 600 s") != std::string::npos;
  });
}

BOOST_AUTO_TEST_CASE(values_outside_physical_ranges_are_refused) {
  Recording r = plausible_recording();
  r.ft_wrench.values(7, 1) = 1e300;
  expect_refused(r, "stream 'ft_wrench' has fy 1e+300 N at row 7, beyond the plausible 1e+03 N");
  r = plausible_recording();
  r.ft_wrench.values(3, 2) = -500;
  expect_refused(r, "stream 'ft_wrench' has tz -500 N m at row 3");
  r = plausible_recording();
  r.object_pose.values(0, 0) = 1e3;
  expect_refused(r, "stream 'object_pose' has x 1e+03 m at row 0, beyond the plausible 10 m");
  r = plausible_recording();
  r.tip_pose.values(9, 2) = 40.0;
  expect_refused(r, "stream 'tip_pose' has yaw 40 rad at row 9");
}

BOOST_AUTO_TEST_CASE(synchronise_checks_before_any_work) {
  Recording r = plausible_recording();
  r.object_pose.t_s(499) += 1e5;  // would make a grid of 25 million samples
  BOOST_CHECK_THROW(synchronise(r, ShapeTable::published().find("rect1")), InputError);
}

BOOST_AUTO_TEST_CASE(every_real_recording_is_plausible) {
  int checked = 0;
  for (const auto& path : list_recordings(resolve_data_folder())) {
    BOOST_TEST_CONTEXT(path.filename().string()) { BOOST_CHECK_NO_THROW(check_plausible(read_recording(path))); }
    ++checked;
  }
  BOOST_TEST(checked == 91);
}

BOOST_AUTO_TEST_SUITE_END()
