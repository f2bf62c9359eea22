#pragma once
// The outputs of `pushpred validate-diagnosis` made from its trials in order (a whole run's as they finish, a
// merge's as read back from the parts): validation.json, validation.md and what the run prints.
// jobs/validation_job.hpp runs the trials and hands them here.
#include <memory>

#include "pushpred/diagnosis/validation.hpp"
#include "pushpred/runtime/batch_runner.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

/// The renderer of a validate-diagnosis run with `options` (its kinds filled in) writing into `out`: trial k must
/// come as unit k. At the end validation.json and validation.md are written and `out` committed; the exit code is 1
/// when some trial could not be diagnosed, 0 otherwise.
std::unique_ptr<BatchRenderer<ValidationTrial>> validation_renderer(StagedOutput& out, ValidationOptions options);

}  // namespace pushpred
