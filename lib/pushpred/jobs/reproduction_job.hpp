#pragma once
// `pushpred reproduce` as a job: the paper's study end to end. The six rect2 cases of its Table I (simulated from
// data/paper/case<n>.json, since the real rect2 pushes are not in the data folder; real ones can be given), the
// observer, the disturbance estimates and the prediction study on each, then the same study over every real ABS
// push, gathered into a PaperReproduction; reports/paper_reproduction.hpp renders it. The app only parses arguments
// and calls these.
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/reports/paper_reproduction.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

struct ReproductionOptions {
  /// Real recordings folder; its abs/ pushes make the second part of the report. Empty: skip that part.
  std::filesystem::path data_folder;
  /// Real rect2 recordings standing for cases 1..6, in order. Empty: simulate the six cases.
  std::vector<std::filesystem::path> case_files;
  StudyOptions study;
};

/// Computes everything the report shows. Simulated cases are written to `out` as cases/case<n>.h5 and read back
/// from there, as a user would read them. Progress lines go to `log`. Throws InputError for unusable options; a real
/// push that fails is among the failures of PaperReproduction::real, not fatal.
PaperReproduction run_paper_reproduction(const ReproductionOptions& options, const StagedOutput& out,
                                         std::ostream& log);

struct ReproductionResult {
  PaperReproduction reproduction;
  std::vector<std::string> plot_notes;  ///< plots that could not be drawn, and why
};

/// The whole of `pushpred reproduce`: run_paper_reproduction, then write_reproduction_report into `out` (not
/// committed: the caller commits).
ReproductionResult reproduce_paper(const ReproductionOptions& options, const StagedOutput& out, std::ostream& log);

}  // namespace pushpred
