#pragma once
// `pushpred reproduce`: the paper's study end to end. The six rect2 cases of its Table I (simulated from
// data/paper/case<n>.json, since the real rect2 pushes are not in the data folder; real ones can be given),
// the observer against the PID reconstruction (figures 2 and 4), u against d_hat with the fitted lines
// (figure 5), the switching between identification and prediction (figure 6), the prediction errors of the
// proposed and the simple algorithm per case and per phase (figures 7 and 8) and the best prediction
// (figure 9); then the same study over every real ABS push. Writes report.md, summary.json, figures (PNG where
// gnuplot is installed, always the gnuplot scripts and their data) into a StagedOutput.
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

struct ReproductionOptions {
  /// Real recordings folder; its abs/ pushes make the second part of the report. Empty: skip that part.
  std::filesystem::path data_folder;
  /// Real rect2 recordings standing for cases 1..6, in order. Empty: simulate the six cases.
  std::vector<std::filesystem::path> case_files;
  StudyOptions study;
};

struct ReproductionResult {
  std::vector<PushStudy> cases;
  Batch<PushStudy> real;  ///< the study over every real ABS push
  std::vector<std::string> plot_notes;  ///< plots that could not be drawn, and why
};

/// Runs the whole reproduction, writing into `out` (not committed: the caller commits). Progress lines go to
/// `log`. Throws InputError for unusable options; a real push that fails is listed in the report, not fatal.
ReproductionResult reproduce_paper(const ReproductionOptions& options, const StagedOutput& out, std::ostream& log);

}  // namespace pushpred
