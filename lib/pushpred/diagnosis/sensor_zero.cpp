#include "pushpred/diagnosis/sensor_zero.hpp"

#include <cmath>

#include "pushpred/diagnosis/diagnosis_data.hpp"

namespace pushpred {

SensorZeros equalise_sensor_zeros(const std::vector<SynchronisedPush>& pushes) {
  SensorZeros out;
  out.pushes = pushes;
  // The reading is -f_C + b; at rest clear of the object f_C = 0, so a push's zero is -mean(f_C recorded).
  std::vector<std::pair<std::size_t, Eigen::Index>> measured;  // push, first sample after its rest window
  std::vector<Eigen::Vector2d> zeros;
  for (std::size_t p = 0; p < pushes.size(); ++p) {
    const auto rest = samples_without_contact(pushes[p]);
    if (rest.size() < 5) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (Eigen::Index k : rest) mean += pushes[p].force_N.row(k).transpose();
    zeros.push_back(-mean / static_cast<double>(rest.size()));
    measured.emplace_back(p, rest.back() + 1);
  }
  out.measured = static_cast<int>(zeros.size());
  if (zeros.empty()) return out;
  for (const auto& z : zeros) out.mean_N += z / static_cast<double>(zeros.size());
  if (zeros.size() >= 2) {
    for (const auto& z : zeros) out.spread_N += (z - out.mean_N).cwiseAbs2() / static_cast<double>(zeros.size() - 1);
    out.spread_N = out.spread_N.cwiseSqrt();
  }
  for (std::size_t j = 0; j < measured.size(); ++j) {
    SynchronisedPush& push = out.pushes[measured[j].first];
    // f_C recorded = -(reading - b): removing the deviation d = b - mean from the reading adds d to f_C.
    const Eigen::Vector2d deviation = zeros[j] - out.mean_N;
    for (Eigen::Index k = measured[j].second; k < push.size(); ++k) {
      push.force_N.row(k) += deviation.transpose();
      push.torque_about_centre_Nm(k) =
          push.tip_torque_Nm(k) + push.lever_m(k, 0) * push.force_N(k, 1) - push.lever_m(k, 1) * push.force_N(k, 0);
    }
  }
  return out;
}

}  // namespace pushpred
