// The pusher_stop refinement of the quasi-static push law: the push needs the pusher to move as well as to press.
// A pusher that stops but keeps pressing above the law's stop force no longer drives the object, while a moving
// one does; the planned tip velocity is the mean velocity of each plan step of the phase's tip path.
#include <boost/test/unit_test.hpp>
#include <algorithm>
#include <cmath>
#include <optional>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/corrected_prediction.hpp"
#include "pushpred/prediction/schedule.hpp"
#include "test_support.hpp"

using namespace pushpred;

namespace {

/// A held signal with one value on [0, t_switch) and another from t_switch on, over [0, t1].
template <int Channels>
SampledSignal two_step(double t_switch_s, const Eigen::Matrix<double, 1, Channels>& first,
                       const Eigen::Matrix<double, 1, Channels>& second) {
  Eigen::VectorXd t(2);
  t << 0.0, t_switch_s;
  Eigen::MatrixXd values(2, Channels);
  values.row(0) = first;
  values.row(1) = second;
  return SampledSignal(t, values, Hold::Zero);
}

struct Scenario {
  const ShapeInfo& shape = ShapeTable::published().find("rect2");
  double stop_force_N = 1.5;   // the law's F_stop
  double pressing_N = 3.0;     // the planned force: twice F_stop throughout
  double speed_m_s = 0.05;     // the object's and the pusher's speed while pushing
  double tip_stops_s = 0.3;    // when the planned tip stops (never, when beyond t1)
  double t1_s = 0.6;

  /// Predicted x [m] at 0.2, 0.45 and 0.6 s, starting at the pusher's speed, with the pusher_stop criterion at
  /// 2 mm/s when `with_pusher_stop`.
  Eigen::Vector3d predict(bool with_pusher_stop) const {
    PlannedForce plan;
    plan.signal = two_step<3>(tip_stops_s, Eigen::RowVector3d(pressing_N, 0, 0), Eigen::RowVector3d(pressing_N, 0, 0));
    plan.t0_s = 0;
    plan.t1_s = t1_s;
    plan.rate_hz = 1 / tip_stops_s;
    std::optional<PusherStopCriterion> pusher_stop;
    if (with_pusher_stop) {
      PlannedTipVelocity tip;
      tip.signal = two_step<2>(tip_stops_s, Eigen::RowVector2d(speed_m_s, 0), Eigen::RowVector2d(0, 0));
      tip.t0_s = 0;
      tip.t1_s = t1_s;
      tip.rate_hz = plan.rate_hz;
      pusher_stop = PusherStopCriterion{tip, 0.002};
    }
    PredictionModel model;
    model.mass_kg = shape.mass_kg;
    model.inertia_kgm2 = shape.inertia_kgm2;
    model.extra_terms.push_back(std::make_shared<QuasiStaticPushTerm>(
        stop_force_N, std::vector<FittedForceLaw>{}, shape, Eigen::Vector3d::Zero(), pusher_stop));
    Eigen::VectorXd times(3);
    times << 0.2, 0.45, 0.6;
    return predict_poses(model, plan, Eigen::Vector3d::Zero(), Eigen::Vector3d(speed_m_s, 0, 0), times).col(0);
  }
};

}  // namespace

BOOST_AUTO_TEST_SUITE(pusher_stop)

BOOST_AUTO_TEST_CASE(the_law_stops_the_object_when_the_planned_tip_stops_though_the_force_stays_above_the_stop_force) {
  const Scenario s;
  const Eigen::Vector3d x = s.predict(true);
  // While the tip moves the push is on: the object keeps the pusher's pace.
  BOOST_TEST(x(0) == s.speed_m_s * 0.2, boost::test_tools::tolerance(0.02));
  // Once the tip stops, kinetic friction of F_stop (no friction law given) stops it within v^2 / (2 a), a = F_stop
  // / m, although the planned force (2 F_stop) would keep it going under the force criterion alone.
  const double slide = s.speed_m_s * s.speed_m_s / (2 * s.stop_force_N / s.shape.mass_kg);
  BOOST_TEST(x(1) > s.speed_m_s * s.tip_stops_s);
  BOOST_TEST(x(1) < s.speed_m_s * s.tip_stops_s + 1.5 * slide);
  BOOST_TEST(std::abs(x(2) - x(1)) < 1e-4);  // at rest, static friction holds it against the pressing pusher
  // The force criterion alone keeps it moving at the pusher's pace to the end.
  const Eigen::Vector3d force_only = s.predict(false);
  BOOST_TEST(force_only(2) == s.speed_m_s * s.t1_s, boost::test_tools::tolerance(0.02));
}

BOOST_AUTO_TEST_CASE(the_law_keeps_the_object_moving_while_the_planned_tip_moves) {
  Scenario s;
  s.tip_stops_s = 10.0;  // the tip moves over the whole phase
  const Eigen::Vector3d x = s.predict(true);
  BOOST_TEST(x(0) == s.speed_m_s * 0.2, boost::test_tools::tolerance(0.02));
  BOOST_TEST(x(1) == s.speed_m_s * 0.45, boost::test_tools::tolerance(0.02));
  BOOST_TEST(x(2) == s.speed_m_s * 0.6, boost::test_tools::tolerance(0.02));
}

BOOST_AUTO_TEST_CASE(the_push_weight_needs_force_and_motion) {
  const Scenario s;
  PlannedTipVelocity tip;
  tip.signal = two_step<2>(0.3, Eigen::RowVector2d(0.0, 0.01), Eigen::RowVector2d(0.001, 0));
  tip.t0_s = 0;
  tip.t1_s = 0.6;
  tip.rate_hz = 1 / 0.3;
  const QuasiStaticPushTerm term(s.stop_force_N, {}, s.shape, Eigen::Vector3d::Zero(), PusherStopCriterion{tip, 0.002});
  const IntegrationInterval first{0.0, 0.3}, second{0.3, 0.6};
  BOOST_TEST(term.push_weight(first, 0.1, 3.0) > 0.99);   // pressing, tip at 10 mm/s
  BOOST_TEST(term.push_weight(first, 0.1, 1.0) < 0.01);   // tip moving, force below F_stop
  BOOST_TEST(term.push_weight(first, 0.3, 3.0) > 0.99);   // the interval's end reads the value held inside it
  BOOST_TEST(term.push_weight(second, 0.3, 3.0) < 0.01);  // tip at 1 mm/s, below 2 mm/s: no push however hard it presses
  BOOST_CHECK_THROW(QuasiStaticPushTerm(s.stop_force_N, {}, s.shape, Eigen::Vector3d::Zero(),
                                        PusherStopCriterion{tip, 0.0}),
                    InputError);
  BOOST_TEST(make_pusher_stop_effect()->refines() == "quasi_static");
  BOOST_TEST(EffectLibrary::standard().find("pusher_stop") != nullptr);
}

BOOST_AUTO_TEST_CASE(the_planned_tip_velocity_is_the_mean_velocity_of_each_plan_step_of_the_phase) {
  const SynchronisedPush push = load_push(pushpred::testing::real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000"));
  const double t0 = 0.25 * push.duration_s(), t1 = 0.5 * push.duration_s();
  const PlannedTipVelocity tip = plan_tip_velocity_from_measurement(push, t0, t1, 10.0);
  const PlannedForce force = plan_from_measurement(push, t0, t1, 10.0);
  BOOST_TEST_REQUIRE(tip.signal.samples() == force.signal.samples());
  BOOST_TEST((tip.signal.times() - force.signal.times()).cwiseAbs().maxCoeff() == 0.0);
  for (Eigen::Index k = 0; k < tip.signal.samples(); ++k) {
    const double a = tip.signal.times()(k), b = std::min(a + 0.1, t1);
    const Eigen::Index ia = push.index_at(a);
    Eigen::Index ib = push.index_at(b);
    if (push.t_s(ib) > t1 + 1e-9) --ib;
    BOOST_TEST(push.t_s(ib) <= t1 + 1e-9);  // never beyond the phase's path
    const Eigen::Vector2d expected = (push.tip_m.row(ib) - push.tip_m.row(ia)).transpose() / (push.t_s(ib) - push.t_s(ia));
    BOOST_TEST((tip.signal.values().row(k).transpose() - expected).norm() < 1e-12);
  }
  // This is a 50 mm/s push: in its second quarter the pusher moves at about that speed.
  BOOST_TEST(tip.signal.values().row(0).norm() > 0.03);
  BOOST_TEST(tip.signal.values().row(0).norm() < 0.07);
}

BOOST_AUTO_TEST_CASE(on_the_traced_ellip3_push_the_pusher_stops_while_it_keeps_pressing) {
  // The real case pusher_stop is for (docs/diagnosis.md, the base model): in the last phase of this 75 mm/s push the
  // pusher stops, yet presses on with more than half the push's force, so the force criterion alone reads a push.
  const SynchronisedPush push = load_push(pushpred::testing::real_file("ellip3_a=0_v=75_i=0.000_s=0.775_t=-0.698"));
  const std::vector<TimeInterval> intervals = split_into_intervals(push, {});
  BOOST_TEST_REQUIRE(intervals.size() == 4u);
  const auto planned = [&](std::size_t k) {
    return std::make_pair(plan_tip_velocity_from_measurement(push, intervals[k].t0_s, intervals[k].t1_s, 10.0),
                          plan_from_measurement(push, intervals[k].t0_s, intervals[k].t1_s, 10.0));
  };
  // While pushing (the second interval), the tip moves at the push's speed.
  const auto [pushing_tip, pushing_force] = planned(1);
  for (Eigen::Index k = 0; k < pushing_tip.signal.samples(); ++k) {
    BOOST_TEST(pushing_tip.signal.values().row(k).norm() > 0.07);
    BOOST_TEST(pushing_tip.signal.values().row(k).norm() < 0.08);
  }
  // In the last phase, after its first plan step (in which the tip creeps the last half millimetre), the tip rests,
  // its planned speed at the level of the tip's noise, while the planned force stays above 3 N.
  const auto [stopped_tip, stopped_force] = planned(3);
  BOOST_TEST_REQUIRE(stopped_tip.signal.samples() >= 2);
  BOOST_TEST(stopped_tip.signal.values().row(0).norm() < 0.005);
  for (Eigen::Index k = 1; k < stopped_tip.signal.samples(); ++k) {
    BOOST_TEST(stopped_tip.signal.values().row(k).norm() < 5e-4);
    BOOST_TEST(stopped_force.signal.values().row(k).head<2>().norm() > 3.0);
  }
}

BOOST_AUTO_TEST_SUITE_END()
