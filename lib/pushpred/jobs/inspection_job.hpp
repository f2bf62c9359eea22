#pragma once
// `pushpred inspect` as a job: each recording read and summarised (what it holds, what the reader repaired, what to
// be wary of) into an Inspection; reports/inspection.hpp renders the batch as a table or JSON. The app only parses
// arguments and calls these.
#include <string>
#include <vector>

#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/reports/inspection.hpp"

namespace pushpred {

struct InspectionOptions {
  std::string shape_override;
  PreprocessOptions preprocess;
  int jobs = 1;           ///< files read in parallel (runtime/parallel_batch.hpp); the result does not depend on it
  bool progress = false;  ///< a progress report on stderr (BatchProgress)
};

/// The summary of one push: travel in mm, rotation and tip yaw in degrees, force in N.
Inspection inspect(const SynchronisedPush& push);

/// Reads and inspects every recording of `inputs` (files or folders); a file that cannot be read is a failure of
/// the batch, with its reason.
InspectionBatch inspect_files(const std::vector<std::string>& inputs, const InspectionOptions& options = {});

}  // namespace pushpred
