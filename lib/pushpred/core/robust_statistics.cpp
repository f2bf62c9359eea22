#include "pushpred/core/robust_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pushpred {

double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  const double upper = *middle;
  if (values.size() % 2 != 0) return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), middle));
}

double upper_median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

double robust_spread(const std::vector<double>& values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const double centre = median(values);
  std::vector<double> deviation;
  deviation.reserve(values.size());
  for (double x : values) deviation.push_back(std::abs(x - centre));
  return 1.4826 * median(std::move(deviation));
}

double standard_deviation(const std::vector<double>& values) {
  const std::size_t n = values.size();
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  double mean = 0;
  for (double x : values) mean += x;
  mean /= static_cast<double>(n);
  double sum = 0;
  for (double x : values) sum += (x - mean) * (x - mean);
  return std::sqrt(sum / static_cast<double>(n - 1));
}

}  // namespace pushpred
