// The paper's recursive least squares (section III-B): equal to the batch fit, honest about its uncertainty,
// able to forget, and clear about input that cannot identify the relation.
#include <boost/test/unit_test.hpp>

#include "pushpred/core/error.hpp"
#include "pushpred/estimators/recursive_least_squares.hpp"
#include "relation_test_data.hpp"

using namespace pushpred;
using pushpred::test::Interval;

namespace {

/// How far the RLS result after all `intervals` is from the reference QR least squares over them stacked:
/// the fit difference (see fit_difference), and the relative differences of residual std and covariance.
struct Agreement {
  double fit = 0, residual_std = 0, covariance = 0;
};

Agreement rls_against_least_squares(const std::vector<Interval>& intervals) {
  RecursiveLeastSquares rls;
  for (const auto& [u, d] : intervals) rls.add_interval(u, d);
  const Interval all = test::stack(intervals);
  const RelationParameters ref = least_squares_relation(all.first, all.second);
  const RelationParameters got = rls.parameters();
  Agreement a;
  a.fit = test::fit_difference(got.beta, got.eps, ref.beta, ref.eps, all);
  for (int c = 0; c < 3; ++c) {
    a.residual_std = std::max(a.residual_std, std::abs(got.residual_std(c) / ref.residual_std(c) - 1.0));
    a.covariance = std::max(a.covariance, (got.covariance[c] - ref.covariance[c]).norm() / ref.covariance[c].norm());
  }
  return a;
}

bool message_contains(const std::exception& e, const std::string& part) {
  return std::string(e.what()).find(part) != std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(recursive_least_squares)

BOOST_AUTO_TEST_CASE(rls_equals_batch_least_squares_over_random_intervals) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    // Intervals of different lengths, as the schedule may cut them.
    std::vector<Interval> intervals;
    std::uniform_int_distribution<int> length(30, 400);
    for (int i = 0; i < 6; ++i) {
      Eigen::MatrixX3d u = test::synthetic_input(length(rng), 0.3 * i, rng);
      Eigen::MatrixX3d d = test::synthetic_disturbance(u, {}, rng);
      intervals.emplace_back(std::move(u), std::move(d));
    }
    const Agreement a = rls_against_least_squares(intervals);
    BOOST_TEST(a.fit < 1e-12);
    BOOST_TEST(a.residual_std < 1e-10);
    BOOST_TEST(a.covariance < 1e-10);
  }
}

BOOST_AUTO_TEST_CASE(rls_fed_one_sample_at_a_time_equals_batch_least_squares) {
  // The classic sample-by-sample RLS is the special case of one-row intervals: the first sample cannot
  // initialise (H^T H singular), the second can, the third makes it ready.
  std::mt19937 rng(12);
  const Eigen::MatrixX3d u = test::synthetic_input(300, 0.0, rng);
  const Eigen::MatrixX3d d = test::synthetic_disturbance(u, {}, rng);
  RecursiveLeastSquares rls;
  for (Eigen::Index k = 0; k < u.rows(); ++k) {
    rls.add_interval(u.middleRows(k, 1), d.middleRows(k, 1));
    BOOST_TEST(rls.ready() == (k >= 2));
  }
  const RelationParameters ref = least_squares_relation(u, d);
  const RelationParameters got = rls.parameters();
  BOOST_TEST(test::fit_difference(got.beta, got.eps, ref.beta, ref.eps, {u, d}) < 1e-12);
  BOOST_TEST((got.residual_std.array() / ref.residual_std.array() - 1.0).abs().maxCoeff() < 1e-10);
}

BOOST_AUTO_TEST_CASE(rls_equals_batch_least_squares_on_real_pushes) {
  // A clean push and one whose force sensor froze (nearly constant input in the first and last quarters:
  // the worst-conditioned Initialise the real data offers).
  for (const std::string name : {"hex_a=0_v=50_i=4.000_s=0.700_t=0.000", "ellip3_a=0_v=10_i=0.000_s=0.000_t=0.349",
                                 "rect1_a=0_v=75_i=2.000_s=0.800_t=0.000"}) {
    BOOST_TEST_CONTEXT(name) {
      const Agreement a = rls_against_least_squares(test::real_intervals(test::real_push(name), 4));
      BOOST_TEST(a.fit < 1e-10);
      BOOST_TEST(a.residual_std < 1e-10);
      BOOST_TEST(a.covariance < 1e-10);
    }
  }
}

BOOST_AUTO_TEST_CASE(a_frozen_force_sensor_leaves_beta_unidentified_and_the_covariance_says_so) {
  // The frozen sensor's interpolated force varies by about 1e-4 of its level: numerically enough to solve for
  // beta, statistically nothing. The estimate is not trusted silently: its standard deviation is huge.
  const auto intervals = test::real_intervals(test::real_push("rect1_a=0_v=75_i=2.000_s=0.800_t=0.000"), 4);
  RecursiveLeastSquares rls;
  rls.add_interval(intervals[0].first, intervals[0].second);
  BOOST_TEST_REQUIRE(rls.ready());
  BOOST_TEST(rls.parameters().beta_std()(0) > 100.0);
  BOOST_TEST(rls.parameters().beta_std()(1) > 100.0);
}

BOOST_AUTO_TEST_CASE(rls_recovers_a_known_relation_within_its_covariance) {
  std::mt19937 rng(13);
  const test::KnownRelation truth;
  RecursiveLeastSquares rls;
  for (const auto& [u, d] : test::synthetic_intervals(4, 200, truth, rng)) {
    rls.add_interval(u, d);
    const RelationParameters p = rls.parameters();
    for (int c = 0; c < 3; ++c) {
      BOOST_TEST(std::abs(p.beta(c) - truth.beta(c)) < 4.0 * p.beta_std()(c));
      BOOST_TEST(std::abs(p.eps(c) - truth.eps(c)) < 4.0 * p.eps_std()(c));
    }
  }
}

BOOST_AUTO_TEST_CASE(the_covariance_matches_the_monte_carlo_spread_with_and_without_forgetting) {
  // 400 repetitions of 4 intervals of fresh noise on the same inputs: the spread of (beta, eps) must match the
  // mean reported covariance. Eigenvalues of C_ref^-1/2 C_mc C_ref^-1/2 in [0.75, 1.33] is about +-4 standard
  // errors of a 400-sample covariance. With forgetting, the plain s^2 P would be too large; s^2 P M P is not.
  const test::KnownRelation truth;
  std::mt19937 rng(14);
  std::vector<Eigen::MatrixX3d> inputs;
  for (int i = 0; i < 4; ++i) inputs.push_back(test::synthetic_input(150, 0.6 * i, rng));
  for (const double lambda : {1.0, 0.3}) {
    BOOST_TEST_CONTEXT("forgetting " << lambda) {
      const int trials = 400;
      std::array<std::vector<Eigen::Vector2d>, 3> estimates;
      std::array<Eigen::Matrix2d, 3> reported{Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero(),
                                              Eigen::Matrix2d::Zero()};
      for (int t = 0; t < trials; ++t) {
        RecursiveLeastSquares rls(RlsOptions{lambda});
        for (const auto& u : inputs) rls.add_interval(u, test::synthetic_disturbance(u, truth, rng));
        const RelationParameters p = rls.parameters();
        for (int c = 0; c < 3; ++c) {
          estimates[c].emplace_back(p.beta(c), p.eps(c));
          reported[c] += p.covariance[c] / trials;
        }
      }
      for (int c = 0; c < 3; ++c) {
        Eigen::Vector2d mean = Eigen::Vector2d::Zero();
        for (const auto& e : estimates[c]) mean += e / trials;
        Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
        for (const auto& e : estimates[c]) spread += (e - mean) * (e - mean).transpose() / (trials - 1);
        const Eigen::Vector2d ratio = test::covariance_ratio(spread, reported[c]);
        BOOST_TEST_MESSAGE("forgetting " << lambda << ", channel " << relation_channel_name(c)
                                         << ": Monte-Carlo / reported covariance eigenvalue ratios "
                                         << ratio.transpose());
        BOOST_TEST_CONTEXT("channel " << relation_channel_name(c) << ", ratios " << ratio.transpose()) {
          BOOST_TEST(ratio.minCoeff() > 0.75);
          BOOST_TEST(ratio.maxCoeff() < 1.33);
        }
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(forgetting_tracks_a_change_of_beta_that_plain_rls_averages_away) {
  // Five intervals with the first relation, then five with beta changed by +0.3 in every channel.
  std::mt19937 rng(15);
  test::KnownRelation before, after;
  after.beta = before.beta.array() + 0.3;
  const double lambda = 0.5;
  RecursiveLeastSquares plain, forgetting(RlsOptions{lambda});
  for (int i = 0; i < 10; ++i) {
    const Eigen::MatrixX3d u = test::synthetic_input(200, 0.8 * i, rng);
    const Eigen::MatrixX3d d = test::synthetic_disturbance(u, i < 5 ? before : after, rng);
    plain.add_interval(u, d);
    forgetting.add_interval(u, d);
  }
  const RelationParameters p = plain.parameters(), f = forgetting.parameters();
  BOOST_TEST(f.effective_samples < 0.5 * p.effective_samples);
  for (int c = 0; c < 3; ++c) {
    BOOST_TEST_CONTEXT("channel " << relation_channel_name(c)) {
      // The old intervals keep at most lambda^5 of the weight, so at most that share of the change remains.
      BOOST_TEST(std::abs(f.beta(c) - after.beta(c)) < std::pow(lambda, 5) * 0.3 + 4.0 * f.beta_std()(c));
      // Plain RLS sits between the two relations, many of its own standard deviations from the new one.
      BOOST_TEST(std::abs(p.beta(c) - after.beta(c)) > 0.05);
      BOOST_TEST(std::abs(p.beta(c) - after.beta(c)) > 10.0 * p.beta_std()(c));
    }
  }
}

BOOST_AUTO_TEST_CASE(a_first_interval_with_constant_input_defers_initialise_and_says_why) {
  std::mt19937 rng(16);
  Eigen::MatrixX3d u0 = test::synthetic_input(100, 0.0, rng);
  u0.col(0).setConstant(-0.338929);  // a frozen force sensor's x reading
  u0.col(2).setZero();               // and no torque at all
  const Eigen::MatrixX3d d0 = test::synthetic_disturbance(u0, {}, rng);
  RecursiveLeastSquares rls;
  rls.add_interval(u0, d0);
  BOOST_TEST(!rls.ready());
  BOOST_TEST(rls.not_ready_reason().find("channel(s) x, rotation has not varied") != std::string::npos);
  BOOST_CHECK_EXCEPTION(rls.parameters(), InputError, [](const InputError& e) {
    return message_contains(e, "rls: not ready: the input of channel(s) x, rotation has not varied over the 1 "
                               "interval(s)");
  });
  // A second, varying interval initialises over both: the result is the batch fit of both.
  const Eigen::MatrixX3d u1 = test::synthetic_input(100, 0.4, rng);
  const Eigen::MatrixX3d d1 = test::synthetic_disturbance(u1, {}, rng);
  rls.add_interval(u1, d1);
  BOOST_TEST_REQUIRE(rls.ready());
  const Interval all = test::stack({{u0, d0}, {u1, d1}});
  const RelationParameters ref = least_squares_relation(all.first, all.second);
  const RelationParameters got = rls.parameters();
  BOOST_TEST(test::fit_difference(got.beta, got.eps, ref.beta, ref.eps, all) < 1e-12);
  BOOST_TEST((got.residual_std.array() / ref.residual_std.array() - 1.0).abs().maxCoeff() < 1e-10);
}

BOOST_AUTO_TEST_CASE(a_forgetting_factor_outside_zero_to_one_is_an_input_error) {
  for (const double lambda : {0.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()})
    BOOST_CHECK_EXCEPTION(RecursiveLeastSquares(RlsOptions{lambda}), InputError, [](const InputError& e) {
      return message_contains(e, "forgetting factor must lie in (0, 1]");
    });
  BOOST_TEST(RecursiveLeastSquares(RlsOptions{1.0}).name() == "rls");
  BOOST_TEST(RecursiveLeastSquares(RlsOptions{0.9}).name() == "rls_forget");
}

BOOST_AUTO_TEST_SUITE_END()
