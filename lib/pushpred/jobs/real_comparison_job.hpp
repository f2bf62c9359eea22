#pragma once
// `pushpred simulate --compare-real` as a job: each real recording beside a clean simulated copy of it
// (simulation/simulator.hpp's scenario_like_recording), both inspected as `pushpred inspect` does;
// reports/simulation_comparison.hpp renders the table and summary of the differences. Frictions are coefficients.
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/reports/simulation_comparison.hpp"
#include "pushpred/simulation/simulator.hpp"

namespace pushpred {

/// Simulates a clean copy of each real recording (see scenario_like_recording) and inspects both the same way
/// `pushpred inspect` does. InputError before any file is read for a friction coefficient out of range
/// (check_friction_coefficient).
Batch<RealComparison> compare_with_real(const std::vector<std::string>& inputs, double surface_friction,
                                        double contact_friction = RodContact().friction);

}  // namespace pushpred
