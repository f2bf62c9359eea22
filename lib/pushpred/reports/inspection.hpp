#pragma once
// `pushpred inspect`'s output: what each recording holds, what the reader repaired, and what to be wary of, as a
// table or JSON, from the inspections jobs/inspection_job.hpp makes. Reported in mm, degrees and newtons.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"

namespace pushpred {

/// What `pushpred inspect` reports of one recording.
struct Inspection {
  std::string source;
  std::string surface, shape;
  double duration_s = 0;
  double object_rate_hz = 0, force_rate_hz = 0, tip_rate_hz = 0;
  bool has_contact = false;
  double contact_start_s = 0, contact_end_s = 0;
  int glitches_removed = 0;
  std::vector<std::string> repairs;
  std::vector<std::string> flags;
  double travel_mm = 0, rotation_deg = 0;
  double mean_contact_force_N = 0;
  double max_tip_yaw_deg = 0;
  /// The mean force before the tip moves [N, robot frame]; NaN without such samples. It is a preload when it points
  /// into the contact (rest_preload), otherwise the sensor's zero error on this push.
  double rest_force_x_N = 0, rest_force_y_N = 0;
  bool rest_preload = false;
  /// Whether the rest force can tell a zero: the sensor live and the outline known (so a preload can be told).
  bool rest_force_tells_zero = false;
};

using InspectionBatch = Batch<Inspection>;

/// The sensor's zero error push to push, as `inspect` reads it: of the recordings whose rest force can tell a zero
/// (rest_force_tells_zero, and finite), the preloads counted apart, and the others' rest force's RMS per axis [N]
/// (0 without any).
struct RestZeroSpread {
  int zeros = 0, preloads = 0;
  double rms_per_axis_N = 0;
};
RestZeroSpread rest_zero_spread(const std::vector<Inspection>& inspections);

std::string inspection_table(const InspectionBatch& batch);
nlohmann::json inspection_json(const InspectionBatch& batch);

}  // namespace pushpred
