#pragma once
// Measuring the FloorContext (candidate_effect.hpp) of a diagnosis on its fit data: the object's nominal mass and
// inertia, the support friction fitted there and its push-to-push spread, the force stream's sample period, and
// the typical (RMS) sliding speed and acceleration and the travel of the fit pushes.
#include <vector>

#include "pushpred/diagnosis/diagnosis_data.hpp"

namespace pushpred {

/// `friction_coefficient` and `friction_spread` as fitted (builtin coulomb_friction); the motion statistics from
/// the zero-phase smoothed state of `data` (diagnosis_data.hpp), on the samples where the object slides. Throws
/// InputError for no data.
FloorContext measure_floor_context(const std::vector<DiagnosisPush>& data, double friction_coefficient,
                                   double friction_spread, double relevance_fraction);

}  // namespace pushpred
