#define BOOST_TEST_MODULE estimators
#include <boost/test/unit_test.hpp>

#include <limits>

#include "pushpred/core/error.hpp"
#include "pushpred/estimators/relation_estimator.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/prediction/schedule.hpp"
#include "relation_test_data.hpp"

using namespace pushpred;
using pushpred::test::Interval;

namespace {

bool message_contains(const std::exception& e, const std::string& part) {
  return std::string(e.what()).find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(relation_estimator)

BOOST_AUTO_TEST_CASE(every_listed_name_makes_an_estimator_of_that_name) {
  const auto names = relation_estimator_names();
  BOOST_TEST(names.size() == 8u);
  for (const auto& name : names) BOOST_TEST(make_relation_estimator(name)->name() == name);
}

BOOST_AUTO_TEST_CASE(an_unknown_name_is_an_input_error_listing_the_known_ones) {
  BOOST_CHECK_EXCEPTION(make_relation_estimator("kalman"), InputError, [](const InputError& e) {
    return message_contains(e, "'kalman'") && message_contains(e, "rls") && message_contains(e, "batch_cauchy");
  });
}

BOOST_AUTO_TEST_CASE(malformed_intervals_are_input_errors_naming_the_problem) {
  std::mt19937 rng(1);
  const Eigen::MatrixX3d u = test::synthetic_input(20, 0.0, rng);
  const Eigen::MatrixX3d d = test::synthetic_disturbance(u, {}, rng);
  for (const auto& name : relation_estimator_names()) {
    BOOST_TEST_CONTEXT(name) {
      auto est = make_relation_estimator(name);
      BOOST_CHECK_EXCEPTION(est->add_interval(u, d.topRows(19)), InputError, [&](const InputError& e) {
        return message_contains(e, name) && message_contains(e, "20 rows of u but 19 of d_hat");
      });
      BOOST_CHECK_EXCEPTION(est->add_interval(u.topRows(0), d.topRows(0)), InputError,
                            [](const InputError& e) { return message_contains(e, "empty"); });
      Eigen::MatrixX3d bad = u;
      bad(7, 2) = std::numeric_limits<double>::quiet_NaN();
      BOOST_CHECK_EXCEPTION(est->add_interval(bad, d), InputError, [](const InputError& e) {
        return message_contains(e, "non-finite u at row 7, channel rotation");
      });
      // A rejected interval leaves the estimator as it was.
      BOOST_TEST(!est->ready());
    }
  }
}

BOOST_AUTO_TEST_CASE(asking_before_any_interval_is_an_input_error_saying_not_ready) {
  for (const auto& name : relation_estimator_names()) {
    const auto est = make_relation_estimator(name);
    BOOST_TEST(!est->ready());
    BOOST_CHECK_EXCEPTION(est->parameters(), InputError, [&](const InputError& e) {
      return message_contains(e, name + ": not ready: no identification interval fed yet");
    });
  }
}

BOOST_AUTO_TEST_CASE(a_clone_continues_on_its_own_and_reset_forgets_everything) {
  std::mt19937 rng(2);
  const auto intervals = test::synthetic_intervals(3, 120, {}, rng);
  for (const auto& name : relation_estimator_names()) {
    BOOST_TEST_CONTEXT(name) {
      auto est = make_relation_estimator(name);
      est->add_interval(intervals[0].first, intervals[0].second);
      est->add_interval(intervals[1].first, intervals[1].second);
      const RelationParameters two = est->parameters();
      auto copy = est->clone();
      est->add_interval(intervals[2].first, intervals[2].second);
      BOOST_TEST(copy->parameters().beta == two.beta);
      BOOST_TEST(copy->parameters().intervals == 2);
      copy->add_interval(intervals[2].first, intervals[2].second);
      BOOST_TEST(copy->parameters().beta == est->parameters().beta);

      est->reset();
      BOOST_TEST(!est->ready());
      est->add_interval(intervals[0].first, intervals[0].second);
      est->add_interval(intervals[1].first, intervals[1].second);
      BOOST_TEST(est->parameters().beta == two.beta);
      BOOST_TEST(est->parameters().samples == 240);
    }
  }
}

BOOST_AUTO_TEST_CASE(an_identification_interval_feeds_the_same_as_its_u_and_d_hat) {
  std::mt19937 rng(3);
  const auto intervals = test::synthetic_intervals(2, 100, {}, rng);
  auto by_matrices = make_relation_estimator("rls");
  auto by_interval = make_relation_estimator("rls");
  const SynchronisedPush push;  // the relation reads only the observer's output
  const TimeInterval span{0.0, 1.0};
  for (const auto& [u, d] : intervals) {
    by_matrices->add_interval(u, d);
    const Eigen::MatrixX3d u3 = u, d3 = d;
    static_cast<OnlineParameterEstimator&>(*by_interval).add_interval(IdentificationInterval{push, span, u3, d3});
  }
  BOOST_TEST(by_interval->parameters().beta == by_matrices->parameters().beta);
  BOOST_TEST(by_interval->parameters().eps == by_matrices->parameters().eps);
}

BOOST_AUTO_TEST_CASE(the_reference_least_squares_recovers_a_noise_free_relation) {
  std::mt19937 rng(4);
  test::KnownRelation truth;
  truth.noise_std.setZero();
  const Eigen::MatrixX3d u = test::synthetic_input(200, 0.0, rng);
  const RelationParameters p = least_squares_relation(u, test::synthetic_disturbance(u, truth, rng));
  for (int c = 0; c < 3; ++c) {
    BOOST_TEST(std::abs(p.beta(c) - truth.beta(c)) < 1e-12);
    BOOST_TEST(std::abs(p.eps(c) - truth.eps(c)) < 1e-12);
    BOOST_TEST(p.residual_std(c) < 1e-12);
  }
}

BOOST_AUTO_TEST_CASE(every_estimator_recovers_a_known_relation_within_four_sigma) {
  std::mt19937 rng(5);
  const test::KnownRelation truth;
  const auto intervals = test::synthetic_intervals(4, 250, truth, rng);
  for (const auto& name : relation_estimator_names()) {
    BOOST_TEST_CONTEXT(name) {
      auto est = make_relation_estimator(name);
      for (const auto& [u, d] : intervals) est->add_interval(u, d);
      const RelationParameters p = est->parameters();
      BOOST_TEST(p.samples == 1000);
      BOOST_TEST(p.intervals == 4);
      for (int c = 0; c < 3; ++c) {
        BOOST_TEST_CONTEXT("channel " << relation_channel_name(c)) {
          BOOST_TEST(std::abs(p.beta(c) - truth.beta(c)) < 4.0 * p.beta_std()(c));
          BOOST_TEST(std::abs(p.eps(c) - truth.eps(c)) < 4.0 * p.eps_std()(c));
          // The residual std estimates the noise: within 10 % for at least 250 samples of Gaussian noise.
          BOOST_TEST(std::abs(p.residual_std(c) / truth.noise_std(c) - 1.0) < 0.1);
        }
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(an_input_that_has_not_varied_is_reported_per_channel) {
  // The building block behind every estimator's readiness: constant u (frozen sensor, no contact) leaves
  // H^T H singular, whatever the unit.
  for (const double level : {0.0, 1e-3, 0.34, 250.0}) {
    const Eigen::VectorXd u = Eigen::VectorXd::Constant(50, level);
    Eigen::Matrix2d a;
    a << u.squaredNorm(), u.sum(), u.sum(), 50.0;
    BOOST_TEST(!relation_identifiable(a));
  }
  std::mt19937 rng(6);
  const Eigen::MatrixX3d u = test::synthetic_input(50, 0.0, rng);
  for (int c = 0; c < 3; ++c) {
    Eigen::Matrix2d a;
    a << u.col(c).squaredNorm(), u.col(c).sum(), u.col(c).sum(), 50.0;
    BOOST_TEST(relation_identifiable(a));
  }
  Eigen::MatrixX3d frozen = u;
  frozen.col(1).setConstant(-0.2198);
  BOOST_CHECK_EXCEPTION(least_squares_relation(frozen, test::synthetic_disturbance(u, {}, rng)), InputError,
                        [](const InputError& e) { return message_contains(e, "channel y does not vary"); });
}

BOOST_AUTO_TEST_SUITE_END()
