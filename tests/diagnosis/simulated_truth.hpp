#pragma once
// Truths the simulator knows and a diagnosis has to find, computed from the simulator's own physics. (Kept out of
// the test file: simulation/pushed_object_system.hpp and prediction/prediction_study.hpp both declare
// kGravity_m_s2 and cannot share a translation unit.)
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/simulation/scenario.hpp"

namespace pushpred::testing {

/// Simulates `scenarios` (all with the same position_friction amount), appends their synchronised pushes to
/// `pushes`, and returns the truth for the position_friction gradient g [1/m]: the simulator's extra friction
/// force from the patch at the true states, projected on the effect's regressor (distance travelled times the
/// unit Coulomb law) over the samples where the object slides.
double position_friction_truth(const std::vector<PushScenario>& scenarios, std::vector<SynchronisedPush>& pushes);

}  // namespace pushpred::testing
