#define BOOST_TEST_MODULE systems
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>

#include "pushpred/core/error.hpp"
#include "pushpred/systems/sampled_signal.hpp"

using namespace pushpred;

namespace {

SampledSignal ramp_samples(Hold hold) {
  Eigen::VectorXd t(4);
  t << 0.0, 0.1, 0.2, 0.4;
  Eigen::MatrixXd v(4, 2);
  v << 0, 10, 1, 20, 4, 30, 5, 40;
  return SampledSignal(t, v, hold);
}

}  // namespace

BOOST_AUTO_TEST_SUITE(sampled_signal)

BOOST_AUTO_TEST_CASE(zero_order_hold_keeps_each_sample_until_the_next) {
  const SampledSignal s = ramp_samples(Hold::Zero);
  BOOST_TEST(s(0.05)(0) == 0.0);
  BOOST_TEST(s(0.1)(0) == 1.0);  // right-continuous: the new sample holds from its own time
  BOOST_TEST(s(0.1999)(1) == 20.0);
  BOOST_TEST(s(0.3)(0) == 4.0);
  BOOST_TEST(s(-1.0)(1) == 10.0);  // end values held outside the samples
  BOOST_TEST(s(7.0)(1) == 40.0);
}

BOOST_AUTO_TEST_CASE(first_order_hold_interpolates_linearly) {
  const SampledSignal s = ramp_samples(Hold::First);
  BOOST_TEST(s(0.05)(0) == 0.5, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(s(0.3)(1) == 35.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(s(0.2)(0) == 4.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(s(-1.0)(0) == 0.0);
  BOOST_TEST(s(1.0)(0) == 5.0);
}

BOOST_AUTO_TEST_CASE(inside_an_interval_the_zero_order_value_holds_at_both_ends) {
  const SampledSignal s = ramp_samples(Hold::Zero);
  Eigen::VectorXd out(2);
  s.evaluate_within(0.2, 0.1, 0.2, out);  // the end of [0.1, 0.2] still sees the sample of 0.1
  BOOST_TEST(out(0) == 1.0);
  s.evaluate_within(0.2, 0.2, 0.4, out);
  BOOST_TEST(out(0) == 4.0);
  const SampledSignal f = ramp_samples(Hold::First);
  f.evaluate_within(0.15, 0.1, 0.2, out);
  BOOST_TEST(out(0) == 2.5, boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(only_zero_order_hold_jumps) {
  const auto z = ramp_samples(Hold::Zero).jumps(0.0, 0.4);
  BOOST_TEST(z.size() == 2u);  // 0.1 and 0.2: strictly inside (0, 0.4)
  BOOST_TEST(z.front() == 0.1);
  BOOST_TEST(ramp_samples(Hold::First).jumps(0.0, 0.4).empty());
}

BOOST_AUTO_TEST_CASE(resampling_holds_the_signal_at_the_new_rate) {
  const SampledSignal s = ramp_samples(Hold::First);
  const SampledSignal plan = resample_and_hold(s, 0.0, 0.4, 0.1);
  BOOST_TEST(plan.samples() == 5);
  BOOST_TEST((plan.hold() == Hold::Zero));
  BOOST_TEST(plan(0.35)(1) == 35.0, boost::test_tools::tolerance(1e-12));  // sample of 0.3, held
  BOOST_CHECK_THROW(resample_and_hold(s, 0.0, 0.4, 0.0), InputError);
}

BOOST_AUTO_TEST_CASE(bad_samples_are_clear_errors) {
  BOOST_CHECK_THROW(SampledSignal(Eigen::VectorXd(), Eigen::MatrixXd(), Hold::Zero), InputError);
  Eigen::VectorXd t(3);
  t << 0, 0.2, 0.1;
  BOOST_CHECK_THROW(SampledSignal(t, Eigen::MatrixXd::Zero(3, 1), Hold::Zero), InputError);
  t << 0, 0.1, 0.2;
  BOOST_CHECK_THROW(SampledSignal(t, Eigen::MatrixXd::Zero(2, 1), Hold::Zero), InputError);
  Eigen::MatrixXd v = Eigen::MatrixXd::Zero(3, 1);
  v(1, 0) = std::numeric_limits<double>::quiet_NaN();
  BOOST_CHECK_THROW(SampledSignal(t, v, Hold::First), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
