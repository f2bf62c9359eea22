#include "pushpred/jobs/inspection_job.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

#include "pushpred/diagnosis/diagnosis_data.hpp"

#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred {

Inspection inspect(const SynchronisedPush& p) {
  Inspection s;
  s.source = p.source;
  s.surface = p.push.surface;
  s.shape = p.shape.name;
  s.duration_s = p.duration_s();
  s.object_rate_hz = p.stream_rate_hz[0];
  s.force_rate_hz = p.stream_rate_hz[1];
  s.tip_rate_hz = p.stream_rate_hz[2];
  s.has_contact = p.has_contact;
  s.contact_start_s = p.contact_start_s;
  s.contact_end_s = p.contact_end_s;
  s.glitches_removed = p.object_glitches + p.tip_glitches;
  for (const auto& r : p.repairs) s.repairs.push_back(r.stream + ": " + r.what);
  s.flags = p.flags.names();
  const Eigen::Index n = p.size();
  s.travel_mm = 1e3 * (p.pose.row(n - 1).head<2>() - p.pose.row(0).head<2>()).norm();
  s.rotation_deg = (p.pose(n - 1, 2) - p.pose(0, 2)) * 180.0 / M_PI;
  double sum = 0;
  int count = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (p.in_contact[k]) {
      sum += p.force_N.row(k).norm();
      ++count;
    }
  s.mean_contact_force_N = count ? sum / count : 0.0;
  s.max_tip_yaw_deg = p.tip_yaw_rad.cwiseAbs().maxCoeff() * 180.0 / M_PI;
  const std::vector<Eigen::Index> rest = samples_before_tip_moves(p);
  s.rest_force_x_N = s.rest_force_y_N = std::numeric_limits<double>::quiet_NaN();
  if (!rest.empty()) {
    const Eigen::Vector2d mean = mean_force_N(p, rest);
    s.rest_force_x_N = mean.x();
    s.rest_force_y_N = mean.y();
    s.rest_preload = rest_force_points_into_contact(p);
    s.rest_force_tells_zero = p.shape.has_outline() && !p.flags.frozen_force_sensor;
  }
  return s;
}

InspectionBatch inspect_files(const std::vector<std::string>& inputs, const InspectionOptions& options) {
  const auto files = expand_inputs(inputs);
  BatchProgress progress("inspect", "files", files.size(), options.progress);
  return run_batch(
      files,
      [&](const std::filesystem::path& path) {
        return inspect(load_push(path, options.shape_override, options.preprocess));
      },
      options.jobs, &progress);
}

}  // namespace pushpred
