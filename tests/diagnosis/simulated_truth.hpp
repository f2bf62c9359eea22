#pragma once
// Truths the simulator knows and a diagnosis has to find, computed from the simulator's own physics.
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/simulation/scenario.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred::testing {

/// Simulates `scenarios`, appends their synchronised pushes to `pushes`, and returns the simulations (their true
/// states).
std::vector<SimulatedPush> simulate_with_states(const std::vector<PushScenario>& scenarios,
                                                std::vector<SynchronisedPush>& pushes);

/// The position_friction gradient g [1/m] (mu's unit per metre) that a friction patch of relative excess 1 gives on
/// the simulated pushes `sims`: the patch as scenario.hpp defines it (a 2 cm radius disk on the push line, centred
/// 2.5 cm beyond the object's leading point at the start), its extra support force per unit excess at the true
/// states computed here from a support with and one without the patch, fitted by least squares on the Coulomb law
/// (which takes the mean, as mu does) and on the candidate's regressor (the travel beyond `onset_m` times the unit
/// Coulomb law's force, less its mean over each push's sliding samples), over the samples where the object slides. A
/// patch of excess e gives the gradient e times this, so a fitted gradient over this is the excess the diagnosis saw.
double patch_gradient_per_unit_excess(const std::vector<SimulatedPush>& sims, double onset_m);

}  // namespace pushpred::testing
