#include "pushpred/observers/disturbance_estimator.hpp"

#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/observers/pid_force_reconstruction.hpp"
#include "pushpred/observers/q_filter_observer.hpp"

namespace pushpred {

void require_nominal_inertia_choice(double mass_kg, double inertia_kgm2, const std::string& who) {
  if (!(mass_kg >= 0) || !std::isfinite(mass_kg))
    throw InputError(who + ": nominal mass must be positive (or 0 for the shape's), got " + std::to_string(mass_kg) +
                     " kg");
  if (!(inertia_kgm2 >= 0) || !std::isfinite(inertia_kgm2))
    throw InputError(who + ": nominal moment of inertia must be positive (or 0 for the shape's), got " +
                     std::to_string(inertia_kgm2) + " kg m^2");
}

std::vector<std::string> disturbance_estimator_names() { return {"dob", "pid"}; }

std::unique_ptr<DisturbanceEstimator> make_disturbance_estimator(const std::string& name) {
  if (name == "dob") return std::make_unique<QFilterObserver>();
  if (name == "pid") return std::make_unique<PidForceReconstruction>();
  std::string known;
  for (const auto& n : disturbance_estimator_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown disturbance estimator '" + name + "' (known: " + known + ")");
}

}  // namespace pushpred
