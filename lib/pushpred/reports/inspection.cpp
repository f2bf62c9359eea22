#include "pushpred/reports/inspection.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

namespace pushpred {

std::string inspection_table(const InspectionBatch& batch) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-40s %-7s %-6s %6s %17s %13s %4s %4s %7s %7s %6s %9s  %s\n", "file", "surface",
                "shape", "dur_s", "rate_obj/ft/tip", "contact_s", "glit", "rep", "trav_mm", "rot_deg", "f_N",
                "rest_f_N", "flags");
  out += line;
  for (const auto& s : batch.results) {
    std::string name = std::filesystem::path(s.source).filename().string();
    // The surface and shape have their own columns; keep the push parameters a=.._v=.._i=.._s=.._t=..
    if (const auto pos = name.find("_a="); pos != std::string::npos) name = name.substr(pos + 1);
    if (const auto dot = name.rfind('.'); dot != std::string::npos) name = name.substr(0, dot);
    if (name.size() > 40) name = name.substr(0, 37) + "...";
    std::string flags;
    for (const auto& f : s.flags) flags += (flags.empty() ? "" : ",") + f;
    char contact[32];
    if (s.has_contact) std::snprintf(contact, sizeof contact, "%.2f-%.2f", s.contact_start_s, s.contact_end_s);
    else std::snprintf(contact, sizeof contact, "none");
    // The rest force's size, marked "p" when it is a preload (it points into the contact).
    char rest[32];
    std::snprintf(rest, sizeof rest, "%.2f%s", std::hypot(s.rest_force_x_N, s.rest_force_y_N),
                  s.rest_preload ? "p" : "");
    std::snprintf(line, sizeof line,
                  "%-40s %-7s %-6s %6.2f %5.0f/%5.0f/%5.0f %13s %4d %4zu %7.1f %7.1f %6.2f %9s  %s\n", name.c_str(),
                  s.surface.c_str(), s.shape.c_str(), s.duration_s, s.object_rate_hz, s.force_rate_hz, s.tip_rate_hz,
                  contact, s.glitches_removed, s.repairs.size(), s.travel_mm, s.rotation_deg, s.mean_contact_force_N,
                  rest, flags.empty() ? "-" : flags.c_str());
    out += line;
  }
  std::map<std::string, int> flag_counts;
  int repaired = 0, glitched = 0;
  for (const auto& s : batch.results) {
    for (const auto& f : s.flags) ++flag_counts[f];
    repaired += !s.repairs.empty();
    glitched += s.glitches_removed > 0;
  }
  std::string flags;
  for (const auto& [name, count] : flag_counts) flags += " " + name + "=" + std::to_string(count);
  std::snprintf(line, sizeof line, "files with repairs: %d; with glitches removed: %d; flags:%s\n", repaired, glitched,
                flags.empty() ? " none" : flags.c_str());
  out += line;
  if (const RestZeroSpread zeros = rest_zero_spread(batch.results); zeros.zeros > 0) {
    std::snprintf(line, sizeof line,
                  "rest force before the tip moves (p: a preload, pointing into the contact): %d preloads; the other "
                  "%d read the sensor's zero, %.3f N RMS per axis\n",
                  zeros.preloads, zeros.zeros, zeros.rms_per_axis_N);
    out += line;
  }
  std::snprintf(line, sizeof line, "%zu files read, %zu failed\n", batch.results.size(), batch.failures.size());
  out += line;
  return out;
}

RestZeroSpread rest_zero_spread(const std::vector<Inspection>& inspections) {
  RestZeroSpread out;
  double sum2 = 0;
  for (const auto& s : inspections) {
    if (!s.rest_force_tells_zero || !std::isfinite(s.rest_force_x_N)) continue;
    if (s.rest_preload) {
      ++out.preloads;
      continue;
    }
    ++out.zeros;
    sum2 += s.rest_force_x_N * s.rest_force_x_N + s.rest_force_y_N * s.rest_force_y_N;
  }
  if (out.zeros > 0) out.rms_per_axis_N = std::sqrt(sum2 / (2.0 * out.zeros));
  return out;
}

nlohmann::json inspection_json(const InspectionBatch& batch) {
  nlohmann::json files = nlohmann::json::array();
  for (const auto& s : batch.results) {
    files.push_back(
        {{"source", s.source},
         {"surface", s.surface},
         {"shape", s.shape},
         {"duration_s", s.duration_s},
         {"rate_hz", {{"object_pose", s.object_rate_hz}, {"ft_wrench", s.force_rate_hz}, {"tip_pose", s.tip_rate_hz}}},
         {"contact", s.has_contact ? nlohmann::json{{"start_s", s.contact_start_s}, {"end_s", s.contact_end_s}}
                                   : nlohmann::json(nullptr)},
         {"glitches_removed", s.glitches_removed},
         {"repairs", s.repairs},
         {"flags", s.flags},
         {"travel_mm", s.travel_mm},
         {"rotation_deg", s.rotation_deg},
         {"mean_contact_force_N", s.mean_contact_force_N},
         {"max_tip_yaw_deg", s.max_tip_yaw_deg},
         {"rest_force_N", std::isfinite(s.rest_force_x_N) ? nlohmann::json{s.rest_force_x_N, s.rest_force_y_N}
                                                          : nlohmann::json(nullptr)},
         {"rest_preload", s.rest_preload}});
  }
  nlohmann::json failures = nlohmann::json::array();
  for (const auto& f : batch.failures) failures.push_back({{"source", f.source}, {"reason", f.reason}});
  return {{"files", files}, {"failures", failures}};
}

}  // namespace pushpred
