#include "pushpred/diagnosis/sensor_zero.hpp"

#include <algorithm>
#include <cmath>

#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "pushpred/diagnosis/residual_regression.hpp"

namespace pushpred {

SensorZeros equalise_sensor_zeros(const std::vector<SynchronisedPush>& pushes) {
  SensorZeros out;
  out.pushes = pushes;
  // The reading is -f_C + b; at rest clear of the object f_C = 0, so a push's zero is -mean(f_C recorded).
  std::vector<std::pair<std::size_t, Eigen::Index>> measured;  // push, first sample after its rest window
  std::vector<Eigen::Vector2d> zeros;
  Eigen::Vector2d noise2 = Eigen::Vector2d::Zero();  // mean over the pushes of their zero's squared standard error
  for (std::size_t p = 0; p < pushes.size(); ++p) {
    const auto rest = samples_without_contact(pushes[p]);
    if (rest.size() < 5) continue;
    Eigen::MatrixX2d f(static_cast<Eigen::Index>(rest.size()), 2);
    for (std::size_t k = 0; k < rest.size(); ++k) f.row(static_cast<Eigen::Index>(k)) = pushes[p].force_N.row(rest[k]);
    zeros.push_back(-f.colwise().mean().transpose());
    for (int c = 0; c < 2; ++c) noise2(c) += long_run_variance(f.col(c), f.rows() - 1) / static_cast<double>(f.rows());
    measured.emplace_back(p, rest.back() + 1);
  }
  out.measured = static_cast<int>(zeros.size());
  if (zeros.empty()) return out;
  for (const auto& z : zeros) out.mean_N += z / static_cast<double>(zeros.size());
  if (zeros.size() >= 2) {
    for (const auto& z : zeros) out.spread_N += (z - out.mean_N).cwiseAbs2() / static_cast<double>(zeros.size() - 1);
    out.spread_N = out.spread_N.cwiseSqrt();
  }
  // Only where the zeros disagree beyond their own noise: their spread over twice the larger of their standard
  // error (long-run variance over each rest window) and the rig's whole force noise at rest. A zeroed sensor's slow
  // noise (0.1 s) moves a rest's mean by about its standard deviation, which a rest window's own samples do not
  // show, and that mean does not hold through the push.
  noise2 /= static_cast<double>(zeros.size());
  Eigen::Vector2d gate = Eigen::Vector2d::Zero();
  for (int c = 0; c < 2; ++c)
    gate(c) = out.spread_N(c) > 2 * std::max(std::sqrt(noise2(c)), kRestForceNoise_N[c]) ? 1.0 : 0.0;
  for (std::size_t j = 0; j < measured.size(); ++j) {
    SynchronisedPush& push = out.pushes[measured[j].first];
    // f_C recorded = -(reading - b): removing the deviation d = b - mean from the reading adds d to f_C.
    const Eigen::Vector2d deviation = gate.cwiseProduct(zeros[j] - out.mean_N);
    if (deviation.isZero()) continue;
    for (Eigen::Index k = measured[j].second; k < push.size(); ++k) {
      push.force_N.row(k) += deviation.transpose();
      push.torque_about_centre_Nm(k) =
          push.tip_torque_Nm(k) + push.lever_m(k, 0) * push.force_N(k, 1) - push.lever_m(k, 1) * push.force_N(k, 0);
    }
  }
  out.removed = gate.cast<bool>();
  return out;
}

}  // namespace pushpred
