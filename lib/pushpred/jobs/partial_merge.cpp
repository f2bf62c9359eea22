#include "pushpred/jobs/partial_merge.hpp"

#include <filesystem>

#include "pushpred/core/error.hpp"
#include "pushpred/jobs/diagnosis_job.hpp"
#include "pushpred/jobs/prediction_job.hpp"
#include "pushpred/jobs/validation_job.hpp"

namespace fs = std::filesystem;

namespace pushpred {

BatchRunOutcome merge_partial_outputs(const std::vector<std::string>& part_folders, const std::string& out_folder) {
  std::vector<PartialOutput> parts;
  std::error_code ec;
  for (const auto& folder : part_folders) {
    if (fs::exists(out_folder, ec) && fs::equivalent(folder, out_folder, ec))
      throw InputError("--out " + plain_text(out_folder) + " is one of the parts; merge into another folder");
    parts.push_back(read_partial_output(folder));
  }
  const MergedParts merged = check_partial_outputs(std::move(parts));
  if (merged.command != "predict" && merged.command != kValidationCommand && merged.command != kDiagnoseCommand)
    throw InputError("merge: the parts are partial outputs of `" + plain_text(merged.command) +
                     "`, which this pushpred cannot merge");
  StagedOutput out(out_folder);
  if (merged.command == kValidationCommand) return write_merged_validation(merged, out);
  if (merged.command == kDiagnoseCommand) return write_merged_diagnoses(merged, out);
  return write_merged_predictions(merged, out);
}

}  // namespace pushpred
