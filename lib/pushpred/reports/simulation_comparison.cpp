#include "pushpred/reports/simulation_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "pushpred/core/robust_statistics.hpp"

namespace pushpred {

ComparisonSummary summarise_comparison(const Batch<RealComparison>& batch, double surface_friction) {
  ComparisonSummary s;
  std::vector<double> matching, spread_real, spread_sim;
  for (const auto& c : batch.results) {
    ++s.pushes;
    s.mean_abs_travel_mm += std::abs(c.real.travel_mm - c.simulated.travel_mm);
    s.mean_abs_rotation_deg += std::abs(c.real.rotation_deg - c.simulated.rotation_deg);
    s.mean_abs_duration_s += std::abs(c.real.duration_s - c.simulated.duration_s);
    if (!c.real_force_trusted || !std::isfinite(c.real_force_per_weight) ||
        !std::isfinite(c.simulated_force_per_weight))
      continue;
    ++s.force_pushes;
    s.mean_abs_force_per_weight += std::abs(c.real_force_per_weight - c.simulated_force_per_weight);
    if (std::isfinite(c.real_force_spread_N) && std::isfinite(c.simulated_force_spread_N)) {
      spread_real.push_back(c.real_force_spread_N);
      spread_sim.push_back(c.simulated_force_spread_N);
    }
    if (c.simulated_force_per_weight >= 0.05)
      matching.push_back(surface_friction * c.real_force_per_weight / c.simulated_force_per_weight);
  }
  if (s.pushes > 0) {
    s.mean_abs_travel_mm /= s.pushes;
    s.mean_abs_rotation_deg /= s.pushes;
    s.mean_abs_duration_s /= s.pushes;
  }
  if (s.force_pushes > 0) s.mean_abs_force_per_weight /= s.force_pushes;
  s.matching_surface_friction = upper_median(matching);
  s.median_real_force_spread_N = upper_median(spread_real);
  s.median_simulated_force_spread_N = upper_median(spread_sim);
  return s;
}

std::string comparison_table(const Batch<RealComparison>& batch, double surface_friction) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-38s %-6s %13s %13s %13s %13s %13s %13s %13s\n", "file (real / simulated)",
                "shape", "duration_s", "travel_mm", "rotation_deg", "f_mean_N", "f/(m g) mid", "f_std_N mid",
                "f_end_N");
  out += line;
  for (const auto& c : batch.results) {
    std::string name = std::filesystem::path(c.source).filename().string();
    if (const auto pos = name.find("_a="); pos != std::string::npos) name = name.substr(pos + 1);
    if (const auto dot = name.rfind('.'); dot != std::string::npos) name = name.substr(0, dot);
    char force[64], ratio[64], spread[64], final[64];
    if (c.real_force_trusted) {
      std::snprintf(final, sizeof final, "%5.2f / %5.2f", c.real_final_force_N, c.simulated_final_force_N);
      std::snprintf(force, sizeof force, "%5.2f / %5.2f", c.real.mean_contact_force_N,
                    c.simulated.mean_contact_force_N);
      std::snprintf(ratio, sizeof ratio, "%5.2f / %5.2f", c.real_force_per_weight, c.simulated_force_per_weight);
      std::snprintf(spread, sizeof spread, "%5.2f / %5.2f", c.real_force_spread_N, c.simulated_force_spread_N);
    } else {
      std::snprintf(force, sizeof force, "  -   / %5.2f", c.simulated.mean_contact_force_N);
      std::snprintf(ratio, sizeof ratio, "  -   / %5.2f", c.simulated_force_per_weight);
      std::snprintf(spread, sizeof spread, "  -   / %5.2f", c.simulated_force_spread_N);
      std::snprintf(final, sizeof final, "  -   / %5.2f", c.simulated_final_force_N);
    }
    std::snprintf(line, sizeof line, "%-38s %-6s %5.2f / %5.2f %5.1f / %5.1f %5.1f / %5.1f %13s %13s %13s %13s\n",
                  name.c_str(), c.real.shape.c_str(), c.real.duration_s, c.simulated.duration_s, c.real.travel_mm,
                  c.simulated.travel_mm, c.real.rotation_deg, c.simulated.rotation_deg, force, ratio, spread, final);
    out += line;
  }
  std::snprintf(line, sizeof line, "%zu recordings compared, %zu failed%s\n", batch.results.size(),
                batch.failures.size(), "; '-': real force sensor frozen (flagged by inspect), not compared");
  out += line;
  const ComparisonSummary s = summarise_comparison(batch, surface_friction);
  std::snprintf(line, sizeof line,
                "mean |real - simulated|: duration %.3f s, travel %.1f mm, rotation %.1f deg (%d pushes); "
                "f/(m g) %.3f (%d live-sensor pushes)\n",
                s.mean_abs_duration_s, s.mean_abs_travel_mm, s.mean_abs_rotation_deg, s.pushes,
                s.mean_abs_force_per_weight, s.force_pushes);
  out += line;
  std::snprintf(line, sizeof line, "surface friction at which the simulated force level matches (median): %.3f\n",
                s.matching_surface_friction);
  out += line;
  std::snprintf(line, sizeof line,
                "force fluctuation while pushing, median std of |f|: real %.2f N, simulated %.2f N\n",
                s.median_real_force_spread_N, s.median_simulated_force_spread_N);
  out += line;
  return out;
}

}  // namespace pushpred
