// Robust location and scale: the median and the median absolute deviation, against values worked out by hand,
// and the property they are used for, that one wild value among several does not move them far.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <vector>

#include "pushpred/core/robust_statistics.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(robust_statistics)

BOOST_AUTO_TEST_CASE(the_median_is_the_middle_value_or_the_mean_of_the_two_middle_ones) {
  BOOST_TEST(median({3.0, 1.0, 2.0}) == 2.0);
  BOOST_TEST(median({4.0, 1.0, 3.0, 2.0}) == 2.5);
  BOOST_TEST(median({7.0}) == 7.0);
  BOOST_TEST(std::isnan(median({})));
}

BOOST_AUTO_TEST_CASE(the_upper_median_is_always_one_of_the_values) {
  BOOST_TEST(upper_median({4.0, 1.0, 3.0, 2.0}) == 3.0);
  BOOST_TEST(upper_median({3.0, 1.0, 2.0}) == 2.0);
  BOOST_TEST(std::isnan(upper_median({})));
}

BOOST_AUTO_TEST_CASE(the_robust_spread_is_a_normal_standard_deviation_from_the_median_absolute_deviation) {
  // The median is (25.1 + 25.3) / 2 = 25.2; the deviations 0.1, 0.3, 0.1, 51.8 have the median (0.1 + 0.3) / 2.
  BOOST_TEST(robust_spread({25.3, 24.9, 25.1, 77.0}) == 1.4826 * 0.2, boost::test_tools::tolerance(1e-9));
  // Four values 20 apart from their median 40: the spread is 1.4826 x 20, as for the plain case.
  BOOST_TEST(robust_spread({10.0, 30.0, 50.0, 70.0}) == 1.4826 * 20.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(robust_spread({5.0}) == 0.0);
  BOOST_TEST(std::isnan(robust_spread({})));
}

BOOST_AUTO_TEST_CASE(the_standard_deviation_divides_by_n_minus_one_and_trusts_every_value) {
  // Mean 40, squared deviations 900 + 100 + 100 + 900 = 2000 over n - 1 = 3.
  BOOST_TEST(standard_deviation({10.0, 30.0, 50.0, 70.0}) == std::sqrt(2000.0 / 3.0), boost::test_tools::tolerance(1e-12));
  // The wild value the robust spread resists moves it far: 25.95 against 0.30.
  BOOST_TEST(standard_deviation({25.3, 24.9, 25.1, 77.0}) > 80 * robust_spread({25.3, 24.9, 25.1, 77.0}));
  BOOST_TEST(std::isnan(standard_deviation({5.0})));
  BOOST_TEST(std::isnan(standard_deviation({})));
}

BOOST_AUTO_TEST_SUITE_END()
