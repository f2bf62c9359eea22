// The common interface of the online parameter estimators (online_parameter_estimator.hpp): the relation estimators
// and the quasi-static pushing model's identification, fed the same intervals of a simulated push and read through
// the interface alone.
#include <Eigen/Eigenvalues>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <memory>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/estimators/online_parameter_estimator.hpp"
#include "pushpred/estimators/relation_estimator.hpp"
#include "pushpred/observers/disturbance_estimator.hpp"
#include "pushpred/prediction/quasi_static_identification.hpp"
#include "pushpred/prediction/schedule.hpp"
#include "pushpred/simulation/simulator.hpp"

using namespace pushpred;

namespace {

/// rect2 pushed 60 degrees off the normal, off the side's centre, at 50 mm/s over 50 mm: the rod slides and the
/// object turns, so the data determine mu_p (the cone's edge) and c (the turn); the rig's noise and jitter.
SynchronisedPush sliding_push(double contact_friction, double surface_friction) {
  PushScenario s;
  s.name = "online estimator";
  s.shape = "rect2";
  s.contact_side = 2;
  s.contact_position = 0.35;
  s.push_angle_rad = 1.047;
  s.contact_friction = contact_friction;
  s.surface_friction = surface_friction;
  s.motion.speed_m_s = 0.05;
  s.motion.length_m = 0.05;
  s.seed = 7;
  return synchronise(as_read(simulate_push(s).recording), ShapeTable::published().find("rect2"));
}

/// The push's intervals (the paper's schedule) with the paper's observer output on each.
struct Fed {
  std::vector<TimeInterval> intervals;
  std::vector<DisturbanceEstimate> observer_output;
};
Fed schedule_of(const SynchronisedPush& push) {
  Fed f;
  f.intervals = split_into_intervals(push, ScheduleOptions{});
  const auto observer = make_disturbance_estimator("dob");
  for (const auto& iv : f.intervals) f.observer_output.push_back(observer->estimate(push, iv.t0_s, iv.t1_s));
  return f;
}

/// Feeds every interval of `fed` to `estimator`, through the interface only.
void feed(OnlineParameterEstimator& estimator, const SynchronisedPush& push, const Fed& fed) {
  for (std::size_t k = 0; k < fed.intervals.size(); ++k)
    estimator.add_interval(IdentificationInterval{push, fed.intervals[k], fed.observer_output[k].u, fed.observer_output[k].d_hat});
}

bool message_contains(const std::exception& e, const std::string& part) {
  return std::string(e.what()).find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(online_parameter_estimator)

BOOST_AUTO_TEST_CASE(the_quasi_static_identification_recovers_mu_p_and_c_through_the_interface) {
  const double mu_p = 0.3, mu_s = 0.4;
  const SynchronisedPush push = sliding_push(mu_p, mu_s);
  const Fed fed = schedule_of(push);
  std::unique_ptr<OnlineParameterEstimator> estimator = std::make_unique<QuasiStaticEstimator>();
  BOOST_TEST(estimator->name() == "quasi_static");
  feed(*estimator, push, fed);
  BOOST_TEST_REQUIRE(estimator->ready(), estimator->not_ready_reason());
  const ParameterEstimate e = estimator->estimate();
  const double c_true = uniform_pressure_torque_ratio(make_footprint(Outline(ShapeTable::published().find("rect2"))),
                                                      Eigen::Vector2d::Zero());
  BOOST_TEST_MESSAGE("through the interface: mu_p "
                     << e.value_of("pusher_friction") << " +- " << e.standard_error_of("pusher_friction") << ", c "
                     << e.value_of("torque_ratio_m") << " +- " << e.standard_error_of("torque_ratio_m") << " m (true "
                     << c_true << "), mu_s " << e.value_of("support_friction") << " +- "
                     << e.standard_error_of("support_friction") << "; " << e.samples << " samples, " << e.intervals
                     << " intervals");
  BOOST_TEST(e.estimator == "quasi_static");
  BOOST_TEST(e.intervals == static_cast<long>(fed.intervals.size()));
  BOOST_TEST(e.units[static_cast<std::size_t>(e.index_of("torque_ratio_m"))] == "m");
  BOOST_TEST_REQUIRE(e.identified("pusher_friction"));
  BOOST_TEST_REQUIRE(e.identified("torque_ratio_m"));
  // The accuracy stated by test_quasi_static_identification.cpp for this push: the model's own error against the
  // simulator (25 % for mu_p, 10 % for c), a fixed share of the truth; the standard errors are bounded below.
  BOOST_TEST(std::abs(e.value_of("pusher_friction") - mu_p) < 0.25 * mu_p);
  BOOST_TEST(std::abs(e.value_of("torque_ratio_m") - c_true) < 0.10 * c_true);
  BOOST_TEST(e.standard_error_of("pusher_friction") < 0.1 * mu_p);
  BOOST_TEST(e.standard_error_of("torque_ratio_m") < 0.1 * c_true);
  // A covariance: symmetric, positive semi-definite, with the correlation of mu_p and c that the cone's edge
  // couples (|rho| < 1, not assumed zero).
  BOOST_TEST((e.covariance - e.covariance.transpose()).cwiseAbs().maxCoeff() < 1e-15);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(e.covariance);
  BOOST_TEST(eig.eigenvalues().minCoeff() > -1e-12 * eig.eigenvalues().maxCoeff());
  const double rho = e.covariance(0, 1) / std::sqrt(e.covariance(0, 0) * e.covariance(1, 1));
  BOOST_TEST_MESSAGE("correlation of mu_p and c: " << rho);
  BOOST_TEST(std::abs(rho) < 1.0);
  BOOST_TEST(rho != 0.0);
}

BOOST_AUTO_TEST_CASE(the_interface_reports_exactly_what_each_estimator_reports_itself) {
  const SynchronisedPush push = sliding_push(0.3, 0.4);
  const Fed fed = schedule_of(push);

  QuasiStaticEstimator quasi_static;
  feed(quasi_static, push, fed);
  QuasiStaticEstimator fed_directly;
  fed_directly.reset(push);
  for (const auto& iv : fed.intervals) fed_directly.add_interval(iv);
  const QuasiStaticIdentification id = fed_directly.identify();
  const ParameterEstimate q = quasi_static.estimate();
  BOOST_TEST_REQUIRE(q.names.size() == 4u);
  BOOST_TEST(q.value_of("pusher_friction") == id.parameters.pusher_friction);
  BOOST_TEST(q.value_of("torque_ratio_m") == id.parameters.torque_ratio_m);
  BOOST_TEST(q.value_of("support_friction") == id.parameters.support_friction);
  BOOST_TEST(q.value_of("contact_offset_m") == id.parameters.contact_offset_m);
  for (Eigen::Index k = 0; k < 4; ++k) {
    BOOST_TEST(q.standard_errors()(k) == id.std(k), boost::test_tools::tolerance(1e-12));
    BOOST_TEST(q.sources[static_cast<std::size_t>(k)] == id.sources[static_cast<std::size_t>(k)]);
  }

  for (const std::string name : {"rls", "batch_huber"}) {
    const std::unique_ptr<RelationEstimator> relation = make_relation_estimator(name);
    feed(*relation, push, fed);
    const std::unique_ptr<RelationEstimator> direct = make_relation_estimator(name);
    for (const auto& out : fed.observer_output) direct->add_interval(out.u, out.d_hat);
    const RelationParameters p = direct->parameters();
    const ParameterEstimate r = static_cast<const OnlineParameterEstimator&>(*relation).estimate();
    BOOST_TEST(r.estimator == name);
    BOOST_TEST_REQUIRE(r.names.size() == 6u);
    for (int c = 0; c < 3; ++c) {
      const std::string channel = relation_channel_name(c);
      BOOST_TEST(r.value_of("beta_" + channel) == p.beta(c));
      BOOST_TEST(r.value_of("eps_" + channel) == p.eps(c));
      const Eigen::Index b = r.index_of("beta_" + channel), e = r.index_of("eps_" + channel);
      BOOST_TEST(r.covariance(b, b) == p.covariance[static_cast<std::size_t>(c)](0, 0));
      BOOST_TEST(r.covariance(b, e) == p.covariance[static_cast<std::size_t>(c)](0, 1));
      BOOST_TEST(r.covariance(e, e) == p.covariance[static_cast<std::size_t>(c)](1, 1));
    }
    BOOST_TEST(r.units[static_cast<std::size_t>(r.index_of("eps_rotation"))] == "N m");
    BOOST_TEST(r.samples == p.samples);
    BOOST_TEST(r.intervals == p.intervals);
  }
}

BOOST_AUTO_TEST_CASE(an_estimator_not_ready_says_why_and_reset_forgets) {
  const SynchronisedPush push = sliding_push(0.3, 0.4);
  const Fed fed = schedule_of(push);
  std::vector<std::unique_ptr<OnlineParameterEstimator>> estimators;
  estimators.push_back(make_relation_estimator("rls"));
  estimators.push_back(std::make_unique<QuasiStaticEstimator>());
  for (auto& e : estimators) {
    BOOST_TEST(!e->ready(), e->name());
    BOOST_CHECK_EXCEPTION(e->estimate(), InputError,
                          [&](const InputError& x) { return message_contains(x, e->name() + ": not ready: "); });
    feed(*e, push, fed);
    BOOST_TEST(e->ready(), e->name() << ": " << e->not_ready_reason());
    BOOST_TEST(e->estimate().intervals == 4);
    e->reset();
    BOOST_TEST(!e->ready(), e->name() << " after reset");
  }
}

BOOST_AUTO_TEST_CASE(the_quasi_static_identification_refuses_an_interval_of_another_push_until_reset) {
  const SynchronisedPush first = sliding_push(0.3, 0.4), second = sliding_push(0.15, 0.4);
  const Fed a = schedule_of(first), b = schedule_of(second);
  QuasiStaticEstimator estimator;
  OnlineParameterEstimator& common = estimator;
  common.add_interval({first, a.intervals[0], a.observer_output[0].u, a.observer_output[0].d_hat});
  BOOST_CHECK_EXCEPTION(common.add_interval({second, b.intervals[1], b.observer_output[1].u, b.observer_output[1].d_hat}), InputError,
                        [](const InputError& x) { return message_contains(x, "another push"); });
  common.reset();
  common.add_interval({second, b.intervals[0], b.observer_output[0].u, b.observer_output[0].d_hat});
  BOOST_TEST(common.estimate().intervals == 1);
}

BOOST_AUTO_TEST_SUITE_END()
