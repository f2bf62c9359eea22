#pragma once
// The outputs of `pushpred predict` made from its studies in input order (a whole run's as they finish, a merge's
// as read back from the parts): summary.json, tables.md and predictions/NAME.csv, and what the run prints.
// jobs/prediction_job.hpp runs the studies and hands them here.
#include <cstddef>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/runtime/batch_runner.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

/// Where the predictions of the input at `position` wait (a path relative to the output) until the renderer knows
/// which inputs were studied and names them predictions/NAME.csv.
std::string pending_predictions_file(std::size_t position);

/// The renderer of a predict run writing into `out`: each study's summary entry and errors as it comes (only its
/// file's stem is kept, so that a run holds a few hundred bytes per push), its predictions file (left by the item at
/// pending_predictions_file) named at the end among the pushes studied. `summary_options` is summary.json's
/// "options" object (prediction_options_json): the printed report reads its "intervals", "span" and "methods".
std::unique_ptr<BatchRenderer<PushStudy>> prediction_renderer(StagedOutput& out, nlohmann::json summary_options);

}  // namespace pushpred
