// The data a diagnosis fits is the observer's view of a push: the filtered input agrees with the observer's own,
// smoothing adds no lag, data corrections do what they say, and the rest window is found.
#define BOOST_TEST_MODULE diagnosis
#include <boost/test/unit_test.hpp>
#include <algorithm>
#include <cmath>

#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::real_file;

BOOST_AUTO_TEST_SUITE(diagnosis_data)

BOOST_AUTO_TEST_CASE(the_q_filtered_input_is_the_observers_own) {
  const SynchronisedPush push = load_push(real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000"));
  const DiagnosisPush d = prepare_diagnosis_push(push, 0.0, push.duration_s());
  // The observer's total is Q u + d_hat, both as interval means (q_filter_observer.hpp): its Q u and ours must
  // agree once the different starts (the observer's follows the input's initial ramp) have died out, 0.1 s =
  // twenty time constants 1 / (zeta wn) later.
  const Eigen::MatrixX3d observer_filtered = d.estimate.total - d.estimate.d_hat;
  const Eigen::Vector3d scale = d.estimate.u.cwiseAbs().colwise().maxCoeff().transpose();
  const Eigen::Index start = push.index_at(0.1);
  const Eigen::Index n = d.rows() - start;
  for (int c = 0; c < 3; ++c)
    BOOST_TEST((observer_filtered.col(c) - d.filtered_input.col(c)).tail(n).cwiseAbs().maxCoeff() <= 1e-6 * scale(c));
  BOOST_TEST(d.rows() == push.size());
}

BOOST_AUTO_TEST_CASE(zero_phase_smoothing_keeps_a_slow_wave_in_place) {
  const int n = 1000;
  Eigen::VectorXd t(n);
  Eigen::MatrixXd y(n, 1);
  const double w = 2 * M_PI * 1.0;  // 1 Hz, far below the 16 Hz smoothing
  for (int k = 0; k < n; ++k) {
    t(k) = k / 250.0;
    y(k, 0) = std::sin(w * t(k));
  }
  Eigen::MatrixXd rate;
  const Eigen::MatrixXd s = zero_phase_smooth(t, y, kSmoothingBandwidth_rad_s, &rate);
  // Away from the ends, no lag: the smoothed wave and its derivative sit on the true ones.
  for (int k = 250; k < 750; ++k) {
    BOOST_TEST(std::abs(s(k, 0) - y(k, 0)) < 2e-3);
    BOOST_TEST(std::abs(rate(k, 0) - w * std::cos(w * t(k))) < 2e-2 * w);
  }
}

BOOST_AUTO_TEST_CASE(a_force_delay_is_read_back_where_it_happened) {
  SynchronisedPush push = load_push(real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000"));
  const SynchronisedPush original = push;
  // Make a push whose force stream lags by 5 grid steps, then undo it.
  const Eigen::Index shift = 5;
  const double delay = shift / push.rate_hz;
  for (Eigen::Index k = push.size() - 1; k >= shift; --k) {
    push.force_N.row(k) = original.force_N.row(k - shift);
    push.tip_torque_Nm(k) = original.tip_torque_Nm(k - shift);
  }
  ModelCorrection c;
  c.force_delay_s = delay;
  const SynchronisedPush back = apply_data_correction(push, c);
  for (Eigen::Index k = shift; k + shift < push.size(); ++k) {
    BOOST_TEST((back.force_N.row(k) - original.force_N.row(k)).norm() < 1e-9);
    BOOST_TEST(std::abs(back.torque_about_centre_Nm(k) - original.torque_about_centre_Nm(k)) < 1e-9);
  }
  BOOST_TEST((back.pose - original.pose).norm() == 0.0);
}

BOOST_AUTO_TEST_CASE(a_sensor_bias_is_removed_and_the_torque_follows) {
  const SynchronisedPush push = load_push(real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000"));
  ModelCorrection c;
  c.sensor_bias_N = Eigen::Vector2d(0.3, -0.2);
  c.inertia_factor = 1.2;
  const SynchronisedPush p = apply_data_correction(push, c);
  for (Eigen::Index k = 0; k < push.size(); k += 37) {
    BOOST_TEST((p.force_N.row(k) - push.force_N.row(k) - c.sensor_bias_N.transpose()).norm() < 1e-12);
    const double expected = push.torque_about_centre_Nm(k) + push.lever_m(k, 0) * 0.2 * -1 - push.lever_m(k, 1) * 0.3;
    BOOST_TEST(std::abs(p.torque_about_centre_Nm(k) - expected) < 1e-12);
  }
  BOOST_TEST(p.shape.mass_kg == 1.2 * push.shape.mass_kg, boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(the_rest_window_ends_when_the_tip_starts_to_move) {
  const SynchronisedPush push = load_push(real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000"));
  const auto idx = samples_before_tip_moves(push);
  BOOST_TEST_REQUIRE(idx.size() > 10u);
  const Eigen::Vector2d rest = push.tip_m.row(0).transpose();
  BOOST_TEST((push.tip_m.row(idx.back()).transpose() - rest).norm() < 1e-3);
  // The tip does move afterwards: the whole push is not a rest window.
  BOOST_TEST(static_cast<Eigen::Index>(idx.size()) < push.size() / 2);
}

BOOST_AUTO_TEST_CASE(a_pushed_object_is_sliding_and_a_resting_one_is_stuck) {
  const SynchronisedPush push = load_push(real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000"));
  const DiagnosisPush d = prepare_diagnosis_push(push, 0.0, push.duration_s());
  BOOST_TEST(d.stuck.front() == 1);
  BOOST_TEST(d.stuck.back() == 1);
  long sliding = 0;
  for (char s : d.stuck) sliding += s ? 0 : 1;
  BOOST_TEST(sliding > d.rows() / 2);
}

BOOST_AUTO_TEST_CASE(the_blurred_tail_of_a_sudden_stop_is_not_slow_sliding) {
  // The object rests, slides at 50 mm/s along x from 0.2 s and stops at 0.7 s, each within one sample: its true
  // speed is 50 mm/s or zero, never a few mm/s. Every smoothed speed between is blur: no row may count as resolved
  // slow sliding.
  constexpr double kRate_hz = 250, kSpeed_m_s = 0.05;
  const Eigen::Index n = 250;  // 1 s
  SynchronisedPush push = pushpred::testing::synthetic_push_shell("rect1", kRate_hz, n);
  push.force_N.setZero();
  push.torque_about_centre_Nm.setZero();
  for (Eigen::Index k = 0; k < n; ++k) push.pose.row(k) << kSpeed_m_s * std::clamp(push.t_s(k) - 0.2, 0.0, 0.5), 0.0, 0.0;
  const DiagnosisPush d = prepare_diagnosis_push(push, 0.0, push.duration_s());
  long resolved_slow = 0, slow_by_own_rate = 0, sliding = 0;
  for (Eigen::Index k = 0; k < d.rows(); ++k) {
    const auto r = static_cast<std::size_t>(k);
    if (d.unresolved[r]) BOOST_TEST(d.blurred[r] == 1);  // blurred is the wider of the two
    if (d.stuck[r]) continue;
    ++sliding;
    const bool slow = sliding_speed(d.smooth_velocity.row(k).transpose(), push.shape) < 0.5 * kSpeed_m_s;
    if (slow && !d.blurred[r]) ++resolved_slow;
    if (slow && !d.unresolved[r]) ++slow_by_own_rate;
  }
  BOOST_TEST(sliding > 100);
  // The row's own acceleration is not enough: where it passes through zero in the tail, a blurred speed would pass.
  BOOST_TEST(slow_by_own_rate > 0);
  BOOST_TEST(resolved_slow == 0);
}

BOOST_AUTO_TEST_SUITE_END()
