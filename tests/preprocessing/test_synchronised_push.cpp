#define BOOST_TEST_MODULE preprocessing
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::real_file;
namespace tt = boost::test_tools;

namespace {

/// A synthetic recording: object moving along x at `speed` with yaw turning through +-pi, tip behind it, the
/// sensor reading `reading_N` (reaction on the pusher), each stream on its own clock.
Recording synthetic_recording(double speed_m_s, Eigen::Vector2d reading_N) {
  Recording r;
  r.source = "synthetic";
  r.push = PushParameters{"abs", "rect1", 0, speed_m_s, 0, 0.5, 0};
  auto stream = [](double t0, double rate, int n) {
    TimedStream s;
    s.t_s = Eigen::VectorXd::LinSpaced(n, t0, t0 + (n - 1) / rate);
    s.values.setZero(n, 3);
    return s;
  };
  r.object_pose = stream(1000.0, 250.0, 500);
  r.tip_pose = stream(1000.01, 228.0, 450);
  r.ft_wrench = stream(999.99, 251.0, 510);
  for (Eigen::Index i = 0; i < r.object_pose.size(); ++i) {
    const double t = r.object_pose.t_s(i) - 1000.0;
    const double yaw = 3.0 + 0.5 * t;  // passes pi: stored wrapped
    r.object_pose.values.row(i) << 0.3 + speed_m_s * t, 0.02, std::remainder(yaw, 2 * M_PI);
  }
  for (Eigen::Index i = 0; i < r.tip_pose.size(); ++i) {
    const double t = r.tip_pose.t_s(i) - 1000.0;
    r.tip_pose.values.row(i) << 0.3 - 0.05 + speed_m_s * t, 0.03, 0.0;
  }
  for (Eigen::Index i = 0; i < r.ft_wrench.size(); ++i) r.ft_wrench.values.row(i) << reading_N.x(), reading_N.y(), 0.01;
  return r;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(resampling)

BOOST_AUTO_TEST_CASE(linear_interpolation_reproduces_a_linear_signal_exactly) {
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(40, 0.0, 1.0).array().pow(1.5);  // uneven stamps
  Eigen::MatrixXd v(40, 2);
  v.col(0) = 3.0 * t.array() + 1.0;
  v.col(1) = -2.0 * t;
  const Eigen::VectorXd grid = Eigen::VectorXd::LinSpaced(101, 0.0, 1.0);
  const Eigen::MatrixXd g = interpolate_linear(t, v, grid);
  BOOST_TEST((g.col(0).array() - (3.0 * grid.array() + 1.0)).abs().maxCoeff() < 1e-12);
  BOOST_TEST((g.col(1) + 2.0 * grid).cwiseAbs().maxCoeff() < 1e-12);
}

BOOST_AUTO_TEST_CASE(a_sinusoid_resampled_from_a_jittered_250_hz_clock_stays_within_the_interpolation_bound) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.4e-3, 0.4e-3);
  const int n = 500;
  Eigen::VectorXd t(n);
  for (int i = 0; i < n; ++i) t(i) = i * 0.004 + (i > 0 && i < n - 1 ? jitter(rng) : 0.0);
  const double w = 2 * M_PI * 2.0;  // 2 Hz, a push's fastest motion
  Eigen::MatrixXd v = t.array().unaryExpr([&](double s) { return std::sin(w * s); }).matrix();
  const Eigen::VectorXd grid = Eigen::VectorXd::LinSpaced(400, 0.0, 1.596);
  const Eigen::MatrixXd g = interpolate_linear(t, v, grid);
  // Linear interpolation error is at most h^2/8 max|f''| with h the longest step (4.8 ms).
  const double bound = std::pow(4.8e-3, 2) / 8 * w * w;
  const double err = (g.col(0).array() - grid.array().unaryExpr([&](double s) { return std::sin(w * s); })).abs().maxCoeff();
  BOOST_TEST(err <= bound);
  BOOST_TEST(err > 0.0);
}

BOOST_AUTO_TEST_CASE(the_grid_covers_the_common_span_at_the_requested_rate) {
  const Recording r = synthetic_recording(0.05, {-1.0, 0.0});
  PreprocessOptions o;
  o.rate_hz = 100.0;
  const SynchronisedPush p = synchronise(r, ShapeTable::published().find("rect1"), o);
  BOOST_TEST(p.t0_unix_s == 1000.01);  // latest start: the tip
  const double common_end = std::min({r.object_pose.end_s(), r.tip_pose.end_s(), r.ft_wrench.end_s()});
  BOOST_TEST(p.t0_unix_s + p.duration_s() <= common_end + 1e-9);
  BOOST_TEST(p.t0_unix_s + p.duration_s() > common_end - 0.01);
  BOOST_TEST(p.t_s(1) - p.t_s(0) == 0.01, tt::tolerance(1e-12));
  PreprocessOptions negative_rate;
  negative_rate.rate_hz = -5.0;
  BOOST_CHECK_THROW(synchronise(r, p.shape, negative_rate), InputError);
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_SUITE(pose_cleaning)

BOOST_AUTO_TEST_CASE(yaw_is_unwrapped_across_pi) {
  const Recording r = synthetic_recording(0.05, {-1.0, 0.0});
  const SynchronisedPush p = synchronise(r, ShapeTable::published().find("rect1"));
  for (Eigen::Index k = 1; k < p.size(); ++k) BOOST_TEST_REQUIRE(std::abs(p.pose(k, 2) - p.pose(k - 1, 2)) < 0.01);
  BOOST_TEST(p.pose(p.size() - 1, 2) > M_PI);
}

BOOST_AUTO_TEST_CASE(a_single_sample_glitch_is_removed_and_counted_while_fast_motion_is_kept) {
  Eigen::MatrixX3d pose(100, 3);
  for (int i = 0; i < 100; ++i) pose.row(i) << 0.6e-3 * i, 0.0, 0.002 * i;  // 150 mm/s at 250 Hz
  Eigen::MatrixX3d clean = pose;
  pose(40, 1) += 0.01;  // a 10 mm jump for one sample
  pose(70, 2) += 0.3;   // a 17 degree yaw spike
  BOOST_TEST(remove_single_sample_glitches(pose, 2e-3, 0.035) == 2);
  BOOST_TEST((pose - clean).cwiseAbs().maxCoeff() < 1e-12);
  BOOST_TEST(remove_single_sample_glitches(clean, 2e-3, 0.035) == 0);
}

BOOST_AUTO_TEST_CASE(no_real_file_loses_samples_to_glitch_rejection) {
  // The real recordings are clean; glitch rejection must not mistake their motion for glitches.
  const SynchronisedPush p = load_push(real_file("shape=butter_a=0_v=150"));
  BOOST_TEST(p.object_glitches == 0);
  BOOST_TEST(p.tip_glitches == 0);
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_SUITE(conventions)

BOOST_AUTO_TEST_CASE(the_force_on_the_object_is_the_negative_of_the_sensor_reading) {
  const Recording r = synthetic_recording(0.05, {-2.0, 0.5});
  const SynchronisedPush p = synchronise(r, ShapeTable::published().find("rect1"));
  BOOST_TEST(p.force_N(10, 0) == 2.0, tt::tolerance(1e-12));
  BOOST_TEST(p.force_N(10, 1) == -0.5, tt::tolerance(1e-12));
  BOOST_TEST(p.tip_torque_Nm(10) == -0.01, tt::tolerance(1e-12));
  // r_m = r_C - r_O = (-0.05, 0.01); T = T_C + r_m x f_C = -0.01 + (-0.05 * -0.5 - 0.01 * 2.0)
  BOOST_TEST(p.lever_m(10, 0) == -0.05, tt::tolerance(1e-9));
  BOOST_TEST(p.lever_m(10, 1) == 0.01, tt::tolerance(1e-9));
  BOOST_TEST(p.torque_about_centre_Nm(10) == -0.01 + 0.025 - 0.02, tt::tolerance(1e-9));
  BOOST_TEST(p.has_contact);
}

BOOST_AUTO_TEST_CASE(on_a_real_push_the_pusher_force_points_along_the_object_motion) {
  const SynchronisedPush p = load_push(real_file("shape=ellip3_a=0_v=10_"));
  BOOST_REQUIRE(p.has_contact);
  BOOST_TEST(!p.flags.frozen_force_sensor);
  // Over the contact interval, the object moves where the pusher pushes it: f_C . v > 0 on average.
  const Eigen::Index a = p.index_at(p.contact_start_s), b = p.index_at(p.contact_end_s);
  double work = 0;
  for (Eigen::Index k = a + 1; k <= b; ++k) work += p.force_N.row(k).dot(p.pose.row(k).head<2>() - p.pose.row(k - 1).head<2>());
  BOOST_TEST(work > 0.0);
  // The pusher (tip) sits outside the object: |r_m| exceeds the smallest semi-axis plus the rod radius.
  for (Eigen::Index k = a; k <= b; ++k) BOOST_TEST_REQUIRE(p.lever_m.row(k).norm() > 0.0525 + kPusherRadius_m - 2e-3);
  // The torque about the centre is T_C plus the lever arm crossed with the force.
  const Eigen::Index k = (a + b) / 2;
  const double cross = p.lever_m(k, 0) * p.force_N(k, 1) - p.lever_m(k, 1) * p.force_N(k, 0);
  BOOST_TEST(p.torque_about_centre_Nm(k) == p.tip_torque_Nm(k) + cross, tt::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(real_pushes_with_a_frozen_force_sensor_are_flagged) {
  const SynchronisedPush frozen = load_push(real_file("shape=rect1_a=0_v=75"));
  BOOST_TEST(frozen.flags.frozen_force_sensor);
  BOOST_TEST(frozen.flags.contact_from_geometry);
  const SynchronisedPush live = load_push(real_file("shape=hex_a=0_v=50"));
  BOOST_TEST(!live.flags.frozen_force_sensor);
}

BOOST_AUTO_TEST_CASE(a_push_that_barely_moves_the_object_is_flagged) {
  int flagged = 0;
  for (const auto& path : list_recordings(resolve_data_folder(), "abs")) flagged += load_push(path).flags.barely_moves;
  // The data README: a few pushes barely move the object (under 2 mm).
  BOOST_TEST(flagged >= 3);
  BOOST_TEST(flagged <= 15);
}

BOOST_AUTO_TEST_SUITE_END()
