// The Ceres batch fit: equal to least squares with the plain loss (per channel and jointly), resistant to
// outliers with Huber and Cauchy losses, and with a covariance that matches the spread it claims.
#include <boost/test/unit_test.hpp>

#include "pushpred/core/error.hpp"
#include "pushpred/estimators/batch_least_squares_fit.hpp"
#include "relation_test_data.hpp"

using namespace pushpred;
using pushpred::test::Interval;

namespace {

bool message_contains(const std::exception& e, const std::string& part) {
  return std::string(e.what()).find(part) != std::string::npos;
}

BatchFitOptions options(RobustLoss loss, bool joint = false) {
  BatchFitOptions o;
  o.loss = loss;
  o.joint = joint;
  return o;
}

RelationParameters fit(const BatchFitOptions& o, const std::vector<Interval>& intervals) {
  BatchLeastSquaresFit est(o);
  for (const auto& [u, d] : intervals) est.add_interval(u, d);
  return est.parameters();
}

/// Adds +size_c to d at the given share of samples, chosen among those whose input is in the channel's top
/// 40 %: one-sided glitches that pull both beta and eps.
void add_outliers(std::vector<Interval>& intervals, double share, const Eigen::Vector3d& size, std::mt19937& rng) {
  std::uniform_real_distribution<double> pick(0.0, 1.0);
  for (auto& [u, d] : intervals)
    for (int c = 0; c < 3; ++c) {
      std::vector<double> sorted(u.col(c).data(), u.col(c).data() + u.rows());
      std::sort(sorted.begin(), sorted.end());
      const double threshold = sorted[static_cast<std::size_t>(0.6 * static_cast<double>(sorted.size()))];
      for (Eigen::Index k = 0; k < u.rows(); ++k)
        if (u(k, c) >= threshold && pick(rng) < share / 0.4) d(k, c) += size(c);
    }
}

}  // namespace

BOOST_AUTO_TEST_SUITE(batch_least_squares_fit)

BOOST_AUTO_TEST_CASE(the_plain_ceres_fit_equals_least_squares_per_channel_and_jointly) {
  std::mt19937 rng(21);
  std::vector<std::pair<std::string, std::vector<Interval>>> cases;
  cases.emplace_back("synthetic", test::synthetic_intervals(4, 250, {}, rng));
  for (const std::string name : {"hex_a=0_v=50_i=4.000_s=0.700_t=0.000", "ellip3_a=0_v=10_i=0.000_s=0.000_t=0.349",
                                 "rect1_a=0_v=75_i=2.000_s=0.800_t=0.000"})
    cases.emplace_back(name, test::real_intervals(test::real_push(name), 4));
  for (const auto& [label, intervals] : cases) {
    const Interval all = test::stack(intervals);
    const RelationParameters ref = least_squares_relation(all.first, all.second);
    for (const bool joint : {false, true}) {
      BOOST_TEST_CONTEXT(label << (joint ? ", joint" : ", per channel")) {
        const RelationParameters got = fit(options(RobustLoss::None, joint), intervals);
        BOOST_TEST(test::fit_difference(got.beta, got.eps, ref.beta, ref.eps, all) < 1e-10);
        for (int c = 0; c < 3; ++c) {
          BOOST_TEST(std::abs(got.residual_std(c) / ref.residual_std(c) - 1.0) < 1e-10);
          BOOST_TEST((got.covariance[c] - ref.covariance[c]).norm() / ref.covariance[c].norm() < 1e-10);
        }
        BOOST_TEST(got.loss_scale.isZero());
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(huber_and_cauchy_resist_outliers_where_least_squares_does_not) {
  std::mt19937 rng(22);
  const test::KnownRelation truth;
  auto intervals = test::synthetic_intervals(4, 250, truth, rng);
  // Gross glitches, 30 noise std (the frozen force sensor's spikes are larger still).
  add_outliers(intervals, 0.1, 30.0 * truth.noise_std, rng);
  const RelationParameters plain = fit(options(RobustLoss::None), intervals);
  const RelationParameters huber = fit(options(RobustLoss::Huber), intervals);
  const RelationParameters cauchy = fit(options(RobustLoss::Cauchy), intervals);
  for (int c = 0; c < 3; ++c) {
    const double plain_error = std::abs(plain.beta(c) - truth.beta(c));
    const double huber_error = std::abs(huber.beta(c) - truth.beta(c));
    const double cauchy_error = std::abs(cauchy.beta(c) - truth.beta(c));
    BOOST_TEST_MESSAGE("channel " << relation_channel_name(c) << ": beta errors plain " << plain_error << " huber "
                                  << huber_error << " cauchy " << cauchy_error);
    BOOST_TEST_CONTEXT("channel " << relation_channel_name(c) << ": beta errors plain " << plain_error << " huber "
                                  << huber_error << " cauchy " << cauchy_error) {
      // Least squares is pulled outside what its own (outlier-inflated) covariance allows.
      BOOST_TEST(plain_error > 4.0 * plain.beta_std()(c));
      // Huber bounds each outlier's pull at 1.345 noise std (a bias remains for one-sided outliers); Cauchy's
      // pull falls with the outlier's size (0.19 noise std at 30) and stays within its covariance.
      BOOST_TEST(huber_error < 0.25 * plain_error);
      BOOST_TEST(cauchy_error < 0.1 * plain_error);
      BOOST_TEST(cauchy_error < 4.0 * cauchy.beta_std()(c));
      BOOST_TEST(std::abs(cauchy.eps(c) - truth.eps(c)) < 4.0 * cauchy.eps_std()(c));
      // The automatic loss scale (k = 1.345 and 2.385 times a MAD-based std) follows the inliers' noise, not
      // the residual std, which the outliers make about 9 times larger. The MAD itself reads 1.14 noise std
      // with 10 % one-sided contamination, and the fit's remaining bias spreads the residuals further.
      BOOST_TEST(plain.residual_std(c) > 5.0 * truth.noise_std(c));
      for (const double s : {huber.loss_scale(c) / 1.345, cauchy.loss_scale(c) / 2.385}) {
        BOOST_TEST(s > 0.9 * truth.noise_std(c));
        BOOST_TEST(s < 1.5 * truth.noise_std(c));
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(the_joint_robust_fit_discounts_a_sample_spoiled_in_every_channel_at_once) {
  // A pose glitch spoils all three channels of a sample at once: far out in x, only 2 noise std in y and
  // rotation, where a per-channel loss takes it for an inlier. Judged as a whole the sample is an outlier.
  std::mt19937 rng(23);
  const test::KnownRelation truth;
  auto intervals = std::vector<Interval>{test::stack(test::synthetic_intervals(8, 500, truth, rng))};
  std::uniform_real_distribution<double> pick(0.0, 1.0);
  auto& [u, d] = intervals.front();
  for (Eigen::Index k = 0; k < u.rows(); ++k)
    if (pick(rng) < 0.15) d.row(k) += Eigen::RowVector3d(20.0, 2.0, 2.0).cwiseProduct(truth.noise_std.transpose());
  for (const RobustLoss loss : {RobustLoss::Huber, RobustLoss::Cauchy}) {
    const RelationParameters per_channel = fit(options(loss, false), intervals);
    const RelationParameters joint = fit(options(loss, true), intervals);
    for (const int c : {1, 2}) {
      const double per_channel_error = std::abs(per_channel.eps(c) - truth.eps(c));
      const double joint_error = std::abs(joint.eps(c) - truth.eps(c));
      BOOST_TEST_MESSAGE((loss == RobustLoss::Huber ? "huber" : "cauchy")
                         << ", channel " << relation_channel_name(c) << ": eps errors per channel "
                         << per_channel_error << " joint " << joint_error);
      BOOST_TEST_CONTEXT((loss == RobustLoss::Huber ? "huber" : "cauchy")
                         << ", channel " << relation_channel_name(c) << ": eps errors per channel "
                         << per_channel_error << " joint " << joint_error) {
        BOOST_TEST(per_channel_error > 4.0 * per_channel.eps_std()(c));
        BOOST_TEST(joint_error < 0.3 * per_channel_error);
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(the_robust_covariance_matches_the_monte_carlo_spread_under_contaminated_noise) {
  // Gaussian noise with 5 % symmetric gross errors (+-8 std, uncorrelated with u): the M-estimators are
  // unbiased there and Huber's asymptotic covariance must match their spread. 300 repetitions: eigenvalues of
  // C_ref^-1/2 C_mc C_ref^-1/2 in [0.7, 1.4] is about +-4 standard errors.
  const test::KnownRelation truth;
  std::mt19937 rng(24);
  // One interval per repetition: the refit after each interval is what is being checked, not the feeding.
  const Eigen::MatrixX3d u = test::synthetic_input(300, 0.0, rng);
  std::uniform_real_distribution<double> pick(0.0, 1.0);
  for (const auto& [label, o] : {std::pair{"huber", options(RobustLoss::Huber)},
                                 std::pair{"cauchy", options(RobustLoss::Cauchy)},
                                 std::pair{"huber joint", options(RobustLoss::Huber, true)}}) {
    const int trials = 300;
    std::array<std::vector<Eigen::Vector2d>, 3> estimates;
    std::array<Eigen::Matrix2d, 3> reported{Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero(),
                                            Eigen::Matrix2d::Zero()};
    for (int t = 0; t < trials; ++t) {
      BatchLeastSquaresFit est(o);
      Eigen::MatrixX3d d = test::synthetic_disturbance(u, truth, rng);
      for (Eigen::Index k = 0; k < d.rows(); ++k)
        for (int c = 0; c < 3; ++c)
          if (pick(rng) < 0.05) d(k, c) += (pick(rng) < 0.5 ? -8.0 : 8.0) * truth.noise_std(c);
      est.add_interval(u, d);
      const RelationParameters p = est.parameters();
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
      BOOST_TEST_MESSAGE(label << ", channel " << relation_channel_name(c) << ": Monte-Carlo / reported covariance "
                               "eigenvalue ratios " << ratio.transpose());
      BOOST_TEST_CONTEXT(label << ", channel " << relation_channel_name(c) << ", ratios " << ratio.transpose()) {
        BOOST_TEST(ratio.minCoeff() > 0.7);
        BOOST_TEST(ratio.maxCoeff() < 1.4);
        BOOST_TEST(std::abs(mean(0) - truth.beta(c)) < 4.0 * std::sqrt(reported[c](0, 0) / trials));
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(a_given_loss_scale_is_used_and_a_bad_one_is_an_input_error) {
  std::mt19937 rng(25);
  const auto intervals = test::synthetic_intervals(2, 200, {}, rng);
  BatchFitOptions o = options(RobustLoss::Huber);
  o.loss_scale = Eigen::Vector3d(0.5, 0.0, 0.01);  // y automatic
  const RelationParameters p = fit(o, intervals);
  BOOST_TEST(p.loss_scale(0) == 0.5);
  BOOST_TEST(p.loss_scale(2) == 0.01);
  BOOST_TEST(std::abs(p.loss_scale(1) / (1.345 * test::KnownRelation().noise_std(1)) - 1.0) < 0.2);
  for (const double bad : {-1.0, std::numeric_limits<double>::infinity()}) {
    o.loss_scale(2) = bad;
    BOOST_CHECK_EXCEPTION(BatchLeastSquaresFit{o}, InputError, [](const InputError& e) {
      return message_contains(e, "batch_huber: loss scale of channel rotation must be finite and not negative");
    });
  }
  BatchFitOptions broken;
  broken.solver.max_num_iterations = -1;
  BOOST_CHECK_EXCEPTION(BatchLeastSquaresFit{broken}, InputError,
                        [](const InputError& e) { return message_contains(e, "invalid Ceres solver options"); });
}

BOOST_AUTO_TEST_CASE(constant_input_leaves_the_batch_fit_not_ready_with_the_reason) {
  std::mt19937 rng(26);
  Eigen::MatrixX3d u = test::synthetic_input(80, 0.0, rng);
  u.col(1).setConstant(0.25);
  const Eigen::MatrixX3d d = test::synthetic_disturbance(u, {}, rng);
  for (const bool joint : {false, true}) {
    BatchLeastSquaresFit est(options(RobustLoss::Cauchy, joint));
    est.add_interval(u, d);
    BOOST_TEST(!est.ready());
    BOOST_CHECK_EXCEPTION(est.parameters(), InputError, [](const InputError& e) {
      return message_contains(e, "not ready: the input of channel(s) y has not varied over the 1 interval(s)");
    });
    est.add_interval(test::synthetic_input(80, 0.5, rng), d);
    BOOST_TEST(est.ready());
  }
}

BOOST_AUTO_TEST_SUITE_END()
