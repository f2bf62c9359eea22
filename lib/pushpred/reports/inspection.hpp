#pragma once
// `pushpred inspect`: what each recording holds, what the reader repaired, and what to be wary of.
// Reported in mm, degrees and newtons.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

struct InspectionOptions {
  std::string shape_override;
  PreprocessOptions preprocess;
  int jobs = 1;           ///< files read in parallel (runtime/parallel_batch.hpp); the result does not depend on it
  bool progress = false;  ///< a progress report on stderr (BatchProgress)
};

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
};

Inspection inspect(const SynchronisedPush& push);

using InspectionBatch = Batch<Inspection>;
InspectionBatch inspect_files(const std::vector<std::string>& inputs, const InspectionOptions& options = {});

std::string inspection_table(const InspectionBatch& batch);
nlohmann::json inspection_json(const InspectionBatch& batch);

}  // namespace pushpred
