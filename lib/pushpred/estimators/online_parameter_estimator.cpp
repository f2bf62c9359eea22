#include "pushpred/estimators/online_parameter_estimator.hpp"

#include <algorithm>
#include <cmath>

#include "pushpred/core/error.hpp"

namespace pushpred {

Eigen::VectorXd ParameterEstimate::standard_errors() const { return covariance.diagonal().cwiseMax(0.0).cwiseSqrt(); }

Eigen::Index ParameterEstimate::index_of(const std::string& name) const {
  std::string known;
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (names[k] == name) return static_cast<Eigen::Index>(k);
    known += (known.empty() ? "" : ", ") + names[k];
  }
  throw InputError(estimator + ": no parameter '" + name + "' (known: " + known + ")");
}

double ParameterEstimate::standard_error_of(const std::string& name) const {
  const Eigen::Index k = index_of(name);
  return std::sqrt(std::max(0.0, covariance(k, k)));
}

ParameterEstimate OnlineParameterEstimator::estimate() const {
  const std::string reason = not_ready_reason();
  if (!reason.empty()) throw InputError(name() + ": not ready: " + reason);
  return current_estimate();
}

}  // namespace pushpred
