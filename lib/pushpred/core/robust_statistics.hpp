#pragma once
// Robust location and scale of a small sample (per-push estimates, per-window means): the median and the median
// absolute deviation resist the one wild value that a short or barely moving push gives. Beside them, the plain
// standard deviation they stand in for, where every value is trusted.

#include <vector>

namespace pushpred {

/// The middle value; the mean of the two middle values for an even count. NaN for an empty sample.
double median(std::vector<double> values);

/// The value at position n / 2 of the sorted sample: for an even count the upper of the two middle values, so
/// always one of the values. NaN for an empty sample.
double upper_median(std::vector<double> values);

/// 1.4826 x the median absolute deviation from the median: a normal distribution's standard deviation, estimated
/// so that fewer than half the values can move it far. NaN for an empty sample.
double robust_spread(const std::vector<double>& values);

/// The sample standard deviation (divided by n - 1). NaN for fewer than two values.
double standard_deviation(const std::vector<double>& values);

}  // namespace pushpred
