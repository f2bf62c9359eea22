// The residual regression finds a term hidden in the observer's disturbance, with an uncertainty that covers the
// truth, and finds nothing where nothing was hidden; its effective sample count follows the autocorrelation.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "pushpred/diagnosis/residual_regression.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::real_file;

namespace {

std::vector<DiagnosisPush> real_pushes() {
  std::vector<DiagnosisPush> out;
  for (const char* f : {"shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000", "shape=ellip1_a=0_v=50_i=0.000_s=0.175_t=-0.349"}) {
    const SynchronisedPush p = load_push(real_file(f));
    out.push_back(prepare_diagnosis_push(p, 0.0, p.duration_s()));
  }
  return out;
}

/// A smooth made-up disturbance pattern (not a physical effect): what the regression should find when added.
EffectColumns pattern(const std::vector<DiagnosisPush>& pushes) {
  EffectColumns cols(1);
  for (const auto& d : pushes) {
    Eigen::MatrixX3d raw(d.rows(), 3);
    for (Eigen::Index k = 0; k < d.rows(); ++k) {
      const double t = d.estimate.t_s(k);
      raw.row(k) << std::sin(7 * t), std::cos(5 * t), 0.01 * std::sin(3 * t + 1);
    }
    cols[0].push_back(d.as_observed(raw));
  }
  return cols;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(residual_regression)

BOOST_AUTO_TEST_CASE(a_term_hidden_in_d_hat_is_found_with_a_covering_interval) {
  std::vector<DiagnosisPush> pushes = real_pushes();
  const EffectColumns cols = pattern(pushes);
  const double truth = 0.4;
  for (std::size_t p = 0; p < pushes.size(); ++p) pushes[p].estimate.d_hat += truth * cols[0][p];
  {
    const Relation base = Relation::Linear;
    const ResidualRegression regression(pushes, base);
    const RegressionFit fit = regression.fit({&cols});
    BOOST_TEST_REQUIRE(fit.identifiable);
    BOOST_TEST(std::abs(fit.theta(0) - truth) <= 3 * fit.standard_error()(0));
    BOOST_TEST(fit.standard_error()(0) < 0.1 * truth);
    BOOST_TEST(fit.wald(0, 1) - std::log(regression.effective_samples()) > 10.0);
  }
}

BOOST_AUTO_TEST_CASE(where_nothing_was_hidden_nothing_is_found) {
  const std::vector<DiagnosisPush> pushes = real_pushes();
  const EffectColumns cols = pattern(pushes);
  const ResidualRegression regression(pushes, Relation::Linear);
  const RegressionFit fit = regression.fit({&cols});
  BOOST_TEST_MESSAGE("theta " << fit.theta(0) << " +- " << fit.standard_error()(0));
  BOOST_TEST(fit.wald(0, 1) - std::log(regression.effective_samples()) < 10.0);
}

BOOST_AUTO_TEST_CASE(dependent_columns_are_not_identifiable) {
  const std::vector<DiagnosisPush> pushes = real_pushes();
  const EffectColumns cols = pattern(pushes);
  const EffectColumns twice = cols;
  const RegressionFit fit = ResidualRegression(pushes).fit({&cols, &twice});
  BOOST_TEST(!fit.identifiable);
  BOOST_TEST(std::isinf(fit.bic));
}

BOOST_AUTO_TEST_CASE(the_effective_sample_count_follows_the_autocorrelation) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01;
  const int n = 20000;
  const double rho = 0.9;
  Eigen::VectorXd x(n);
  x(0) = n01(rng);
  for (int k = 1; k < n; ++k) x(k) = rho * x(k - 1) + std::sqrt(1 - rho * rho) * n01(rng);
  BOOST_TEST(lag1_autocorrelation(x) == rho, boost::test_tools::tolerance(0.02));
  BOOST_TEST(effective_sample_count(x) == n * (1 - rho) / (1 + rho), boost::test_tools::tolerance(0.15));
  // The long-run variance of an AR(1) of unit variance is (1 + rho) / (1 - rho).
  BOOST_TEST(long_run_variance(x, 200) == (1 + rho) / (1 - rho), boost::test_tools::tolerance(0.25));
  Eigen::VectorXd white(n);
  for (int k = 0; k < n; ++k) white(k) = n01(rng);
  BOOST_TEST(long_run_variance(white, 50) == 1.0, boost::test_tools::tolerance(0.1));
}

BOOST_AUTO_TEST_SUITE_END()
