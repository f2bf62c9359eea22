#include "pushpred/systems/sampled_signal.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "pushpred/core/error.hpp"

namespace pushpred {

const char* hold_name(Hold hold) { return hold == Hold::Zero ? "zero" : "first"; }

SampledSignal::SampledSignal(Eigen::VectorXd t_s, Eigen::MatrixXd values, Hold hold)
    : t_(std::move(t_s)), values_(std::move(values)), hold_(hold) {
  if (t_.size() == 0) throw InputError("sampled signal: no samples");
  if (values_.rows() != t_.size())
    throw InputError("sampled signal: " + std::to_string(t_.size()) + " sample times but " +
                     std::to_string(values_.rows()) + " rows of values");
  if (values_.cols() == 0) throw InputError("sampled signal: no channels");
  for (Eigen::Index k = 0; k < t_.size(); ++k) {
    if (!std::isfinite(t_(k))) throw InputError("sampled signal: time " + std::to_string(k) + " is not finite");
    if (k > 0 && !(t_(k) > t_(k - 1)))
      throw InputError("sampled signal: times not strictly increasing at sample " + std::to_string(k));
  }
  if (!values_.allFinite()) throw InputError("sampled signal: values hold NaN or infinity");
}

Eigen::Index SampledSignal::segment(double t) const {
  const double* begin = t_.data();
  const double* end = begin + t_.size();
  const double* it = std::upper_bound(begin, end, t);  // first sample strictly after t
  return it == begin ? 0 : static_cast<Eigen::Index>(it - begin) - 1;
}

void SampledSignal::evaluate(double t, Eigen::Ref<Eigen::VectorXd> out) const {
  const Eigen::Index n = t_.size();
  if (t <= t_(0)) {
    out = values_.row(0).transpose();
    return;
  }
  if (t >= t_(n - 1)) {
    out = values_.row(n - 1).transpose();
    return;
  }
  const Eigen::Index k = segment(t);
  if (hold_ == Hold::Zero) {
    out = values_.row(k).transpose();
  } else {
    const double w = (t - t_(k)) / (t_(k + 1) - t_(k));
    out = (1 - w) * values_.row(k).transpose() + w * values_.row(k + 1).transpose();
  }
}

Eigen::VectorXd SampledSignal::operator()(double t) const {
  Eigen::VectorXd out(channels());
  evaluate(t, out);
  return out;
}

void SampledSignal::evaluate_within(double t, double t_lo, double t_hi, Eigen::Ref<Eigen::VectorXd> out) const {
  // Under zero-order hold the signal is constant inside a jump-free interval, so its midpoint carries the value
  // that holds at both ends; a first-order-held signal is continuous and needs no care.
  if (hold_ == Hold::Zero && t_hi > t_lo) evaluate(0.5 * (t_lo + t_hi), out);
  else evaluate(t, out);
}

std::vector<double> SampledSignal::jumps(double t0, double t1) const {
  std::vector<double> out;
  if (hold_ != Hold::Zero) return out;
  for (Eigen::Index k = 0; k < t_.size(); ++k)
    if (t_(k) > t0 && t_(k) < t1) out.push_back(t_(k));
  return out;
}

SampledSignal resample_and_hold(const SampledSignal& signal, double t0, double t1, double period) {
  if (!(period > 0) || !std::isfinite(period)) throw InputError("resample: period must be positive and finite");
  if (!std::isfinite(t0) || !std::isfinite(t1) || t1 < t0)
    throw InputError("resample: end time must not precede start time");
  const auto n = static_cast<Eigen::Index>(std::floor((t1 - t0) / period + 1e-9)) + 1;
  Eigen::VectorXd t(n);
  Eigen::MatrixXd v(n, signal.channels());
  Eigen::VectorXd row(signal.channels());
  for (Eigen::Index k = 0; k < n; ++k) {
    t(k) = t0 + static_cast<double>(k) * period;
    signal.evaluate(t(k), row);
    v.row(k) = row.transpose();
  }
  return SampledSignal(std::move(t), std::move(v), Hold::Zero);
}

}  // namespace pushpred
