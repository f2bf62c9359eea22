#include "pushpred/jobs/prediction_job.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/jobs/partial_codecs.hpp"
#include "pushpred/reports/prediction_outputs.hpp"
#include "pushpred/reports/prediction_summary.hpp"
#include "pushpred/runtime/batch_runner.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

constexpr const char* kCommand = "predict";

/// The renderer from a run's options (predict_options_json): what the summary and the printed report read of them,
/// checked before anything is written.
std::unique_ptr<BatchRenderer<PushStudy>> renderer_from_options(StagedOutput& out, const nlohmann::json& run_options,
                                                                RenderFor) {
  const nlohmann::json& options = run_options.contains("summary") ? run_options["summary"] : run_options;
  const auto is_names = [](const nlohmann::json& list) {
    if (!list.is_array()) return false;
    for (const auto& n : list)
      if (!n.is_string()) return false;
    return true;
  };
  if (!options.is_object() || !options.contains("intervals") || !options["intervals"].is_number_integer() ||
      !options.contains("span") || !options["span"].is_string() || !options.contains("methods") ||
      !is_names(options["methods"]))
    throw InputError("its partial.json's options are not those of `predict`");
  return prediction_renderer(out, options);
}

PartialCodec<PushStudy> prediction_codec() {
  PartialCodec<PushStudy> codec;
  codec.encode = push_study_exact_json;
  codec.decode = push_study_from_exact_json;
  codec.files = [](std::size_t index, const PushStudy&) {
    return std::vector<std::string>{pending_predictions_file(index)};
  };
  codec.name = [](std::size_t index) { return "the result of input " + std::to_string(index + 1); };
  return codec;
}

nlohmann::json predict_options_json(const PredictRun& run) {
  // "summary": what summary.json says; "settings": the rest that changes a result, so that a merge refuses parts
  // run with other values.
  return {{"summary", prediction_options_json(run.study)},
          {"settings",
           {{"mu", exact_number_json(run.study.friction_coefficient)},
            {"shape", run.shape},
            {"rate_hz", exact_number_json(run.preprocess.rate_hz)}}}};
}

}  // namespace

BatchRunOutcome write_merged_predictions(const MergedParts& merged, StagedOutput& out) {
  if (merged.command != kCommand)
    throw InputError("merge: the parts are partial outputs of `" + merged.command + "`, which cannot be merged");
  return merge_batch<PushStudy>(merged, out, prediction_codec(), renderer_from_options);
}

BatchRunOutcome run_predict(const PredictRun& run) {
  const std::vector<fs::path> inputs = expand_inputs(run.inputs);
  const BatchSplit split{run.shard, run.mpi};
  split.refuse_shard_under_mpi("inputs");
  BatchJob<PushStudy> job;
  job.command = job.label = kCommand;
  job.unit = "pushes";
  job.units = inputs;
  job.options = predict_options_json(run);
  job.jobs = run.jobs;
  // Each push's predictions are written under its input's position while the batch runs (threads, shards and ranks
  // finish in any order) and named by the renderer at the end, once it is known which inputs were studied.
  job.item = [&](std::size_t index, FileSink& files) {
    PushStudy study = run_prediction_study(load_push(inputs[index], run.shape, run.preprocess), run.study);
    files.write(pending_predictions_file(index), predictions_csv(study));
    drop_samples(study);  // the summary and tables need only errors and parameters
    return study;
  };
  job.codec = prediction_codec();
  job.shard_outcome = [](const ShardDone& done) {
    BatchRunOutcome outcome;
    outcome.partial = true;
    outcome.failures = done.failures;
    outcome.used = done.counted;
    outcome.report = "predicted " + std::to_string(done.counted) + " of the " + std::to_string(done.here) +
                     " pushes of shard " + done.shard.text() + " (" + std::to_string(done.all) +
                     " inputs in all); partial output in " + done.destination +
                     "; when every shard is done: pushpred merge --out DIR PART...\n";
    return outcome;
  };
  return run_batch_job<PushStudy>(job, split, run.out, renderer_from_options);
}

}  // namespace pushpred
