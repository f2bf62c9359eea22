#include "pushpred/observers/disturbance_estimator.hpp"

#include "pushpred/core/error.hpp"
#include "pushpred/observers/pid_force_reconstruction.hpp"
#include "pushpred/observers/q_filter_observer.hpp"

namespace pushpred {

std::vector<std::string> disturbance_estimator_names() { return {"dob", "pid"}; }

std::unique_ptr<DisturbanceEstimator> make_disturbance_estimator(const std::string& name) {
  if (name == "dob") return std::make_unique<QFilterObserver>();
  if (name == "pid") return std::make_unique<PidForceReconstruction>();
  std::string known;
  for (const auto& n : disturbance_estimator_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown disturbance estimator '" + name + "' (known: " + known + ")");
}

}  // namespace pushpred
