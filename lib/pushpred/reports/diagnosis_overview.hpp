#pragma once
// The outputs of `pushpred diagnose --per-object` made from its objects' diagnoses in order (a whole run's as they
// finish, a merge's as read back from the parts): overview.md, overview.json and what the run prints. Each object's
// own folder is written by write_diagnosis_report as it is diagnosed (jobs/diagnosis_job.hpp).
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "pushpred/runtime/batch_runner.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

/// One object's diagnosis as a per-object run reports it: its outcome (for the overview), what it prints on stdout
/// and on stderr, and how many of its pushes the diagnosis left out.
struct DiagnosedObject {
  DiagnosisGroupOutcome outcome;
  std::string printed;
  std::string complaints;
  std::size_t left_out = 0;
  std::vector<std::string> files;  ///< what its report wrote, relative to the output (a shard's or rank's only)
};

/// The renderer of a per-object run writing into `out`. At the end overview.md and overview.json are written and
/// `out` committed, and the run prints each object's report in order, then the count; on stderr the unreadable
/// inputs `read_failures` (when `list_read_failures`: a merge of shards, since a whole run and an MPI job's rank 0
/// list them as they read them), each object's complaints, the failed count. `pushes_read`: the pushes read. When no
/// object could be diagnosed nothing is written and the exit code is 2; it is 1 when an object failed, a push was
/// left out or an input could not be read.
std::unique_ptr<BatchRenderer<DiagnosedObject>> diagnosis_overview_renderer(StagedOutput& out, std::size_t pushes_read,
                                                                            std::vector<BatchFailure> read_failures,
                                                                            bool list_read_failures);

}  // namespace pushpred
