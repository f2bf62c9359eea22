#pragma once
// `pushpred simulate --compare-real`'s output: each real recording beside a clean simulated copy of it, both
// inspected as `pushpred inspect` does (jobs/real_comparison_job.hpp makes them), and the table and summary of the
// differences (docs/simulator.md). Lengths in mm, angles in degrees, forces in N.
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/reports/inspection.hpp"

namespace pushpred {

/// One real recording and its clean simulated copy.
struct RealComparison {
  std::string source;
  Inspection real, simulated;
  double real_force_per_weight = 0, simulated_force_per_weight = 0;  ///< median |f| / (m g), middle of push
  double real_force_spread_N = 0, simulated_force_spread_N = 0;      ///< std of |f| over the same span
  double real_final_force_N = 0, simulated_final_force_N = 0;        ///< median |f| over the last 0.1 s
  bool real_force_trusted = true;                                    ///< false when the real force sensor is frozen
};

/// Summary of a comparison: mean absolute differences, and the surface friction at which the simulated force
/// level would match the real one (median over live-sensor pushes of mu x real / simulated mid-push force per
/// weight; pushes where the simulated value is under 0.05, i.e. the rod slides off, are left out).
struct ComparisonSummary {
  int pushes = 0, force_pushes = 0;
  double mean_abs_travel_mm = 0, mean_abs_rotation_deg = 0, mean_abs_duration_s = 0;
  double mean_abs_force_per_weight = 0;
  double median_real_force_spread_N = 0, median_simulated_force_spread_N = 0;
  double matching_surface_friction = 0;
};
ComparisonSummary summarise_comparison(const Batch<RealComparison>& batch, double surface_friction);
std::string comparison_table(const Batch<RealComparison>& batch, double surface_friction);

}  // namespace pushpred
