#include "pushpred/jobs/validation_job.hpp"

#include <unistd.h>

#include <exception>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>

#include "pushpred/core/error.hpp"
#include "pushpred/jobs/partial_codecs.hpp"
#include "pushpred/reports/validation_outputs.hpp"
#include "pushpred/runtime/batch_runner.hpp"
#include "pushpred/runtime/shard.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

/// What the outputs read of the options and what tells two runs apart (--jobs changes nothing).
nlohmann::json options_json(const ValidationOptions& o) {
  return {{"trials_per_kind", o.trials_per_kind},
          {"seed", o.seed},
          {"kinds", o.kinds},
          {"min_pushes", o.min_pushes},
          {"max_pushes", o.max_pushes},
          {"min_floor_multiple", exact_number_json(o.min_floor_multiple)},
          {"max_floor_multiple", exact_number_json(o.max_floor_multiple)},
          {"relevance_fraction", exact_number_json(o.diagnosis.relevance_fraction)},
          {"bic_threshold", exact_number_json(o.diagnosis.bic_threshold)},
          {"floor_margin_std", exact_number_json(o.diagnosis.floor_margin_std)},
          {"sensor_zero_spread_N", exact_number_json(o.diagnosis.sensor_zero_spread_N)},
          {"measured_contact_compliance", o.diagnosis.measured_contact_compliance},
          {"fit_base_settings", o.diagnosis.fit_base_settings},
          {"hide", o.hide},
          {"draw_preloads", o.draw_preloads},
          {"draw_sensor_offsets", o.draw_sensor_offsets},
          {"sensor_offset_spread_N", exact_number_json(o.sensor_offset_spread_N)}};
}

ValidationOptions options_from(const nlohmann::json& j) {
  try {
    ValidationOptions o;
    o.trials_per_kind = json_whole_number<int>(j.at("trials_per_kind"), "trials_per_kind");
    o.seed = json_whole_number<std::uint64_t>(j.at("seed"), "seed");
    o.kinds = j.at("kinds").get<std::vector<std::string>>();
    o.min_pushes = json_whole_number<int>(j.at("min_pushes"), "min_pushes");
    o.max_pushes = json_whole_number<int>(j.at("max_pushes"), "max_pushes");
    o.min_floor_multiple = exact_number(j.at("min_floor_multiple"));
    o.max_floor_multiple = exact_number(j.at("max_floor_multiple"));
    o.diagnosis.relevance_fraction = exact_number(j.at("relevance_fraction"));
    o.diagnosis.bic_threshold = exact_number(j.at("bic_threshold"));
    o.diagnosis.floor_margin_std = exact_number(j.at("floor_margin_std"));
    o.diagnosis.sensor_zero_spread_N = exact_number(j.at("sensor_zero_spread_N"));
    o.diagnosis.measured_contact_compliance = j.at("measured_contact_compliance").get<bool>();
    o.diagnosis.fit_base_settings = j.at("fit_base_settings").get<bool>();
    o.hide = j.at("hide").get<std::vector<std::string>>();
    o.draw_preloads = j.at("draw_preloads").get<bool>();
    o.draw_sensor_offsets = j.at("draw_sensor_offsets").get<bool>();
    o.sensor_offset_spread_N = exact_number(j.at("sensor_offset_spread_N"));
    return o;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("its options are not those of validate-diagnosis: ") + e.what());
  }
}

/// Trials done on stderr: on a terminal a line redrawn in place, otherwise every tenth and the last.
std::function<void(int, int)> progress_printer(bool enabled) {
  if (!enabled) return {};
  const bool terminal = isatty(STDERR_FILENO) != 0;
  return [terminal](int done, int total) {
    if (terminal) {
      std::cerr << "\rtrials " << done << " / " << total << std::flush;
      if (done == total) std::cerr << "\n";
    } else if (done == total || done % 10 == 0) {
      std::cerr << "trials " << done << " / " << total << "\n";
    }
  };
}

PartialCodec<ValidationTrial> validation_codec() {
  PartialCodec<ValidationTrial> codec;
  codec.encode = validation_trial_exact_json;
  codec.decode = validation_trial_from_exact_json;
  codec.name = [](std::size_t index) { return "trial " + std::to_string(index); };
  return codec;
}

/// The renderer of a whole run (its options as given, kinds filled in), or of a merge (the options its parts record).
RendererFactory<ValidationTrial> validation_renderer_for(std::optional<ValidationOptions> whole_run) {
  return [whole_run](StagedOutput& out, const nlohmann::json& options, RenderFor mode) {
    return validation_renderer(out, mode == RenderFor::whole_run && whole_run ? *whole_run : options_from(options));
  };
}

}  // namespace

BatchRunOutcome run_validation(const ValidateRun& run) {
  run.options.validate();  // before any work: a bad kind or range is an input error, nothing written
  const BatchSplit split{run.shard, run.mpi};
  split.refuse_shard_under_mpi("trials");
  // The options as a whole run reports them (the kinds filled in); each trial runs on one thread of the batch.
  const ValidationOptions options = validate_diagnosis_trials(run.options, {}).options;
  ValidationOptions one_trial = options;
  one_trial.jobs = 1;
  const int count = validation_trial_count(options);
  BatchJob<ValidationTrial> job;
  job.command = job.label = kValidationCommand;
  job.unit = "trials";
  // The trials are the inputs: their count is what a merge compares (the options carry the seed and the kinds).
  // Trial k goes to shard k mod N + 1.
  for (int k = 0; k < count; ++k) job.units.emplace_back("trial " + std::to_string(k));
  job.dealt_in_order = true;
  job.options = options_json(options);
  job.jobs = run.options.jobs;
  job.item = [&](std::size_t index, FileSink&) {
    return validate_diagnosis_trials(one_trial, {static_cast<int>(index)}).trials.front();
  };
  job.codec = validation_codec();
  job.note = [](const ValidationTrial& t) {
    ShardNote note;
    note.failed = !t.failure.empty();
    return note;
  };
  job.shard_outcome = [](const ShardDone& done) {
    BatchRunOutcome outcome;
    outcome.partial = true;
    outcome.report = "ran " + std::to_string(done.counted) + " of the " + std::to_string(done.all) + " trials (shard " +
                     done.shard.text() + "); partial output in " + done.destination +
                     "; when every shard is done: pushpred merge --out DIR PART...\n";
    if (done.failed > 0)
      outcome.notes = std::to_string(done.failed) + " trial(s) of this shard could not be diagnosed\n";
    outcome.exit_code = done.failed > 0 ? 1 : 0;
    return outcome;
  };
  if (run.progress) {
    const auto print = progress_printer(true);
    job.progress = [print](std::size_t done, std::size_t total) {
      print(static_cast<int>(done), static_cast<int>(total));
    };
  }
  return run_batch_job<ValidationTrial>(job, split, run.out, validation_renderer_for(options));
}

BatchRunOutcome write_merged_validation(const MergedParts& merged, StagedOutput& out) {
  return merge_batch<ValidationTrial>(merged, out, validation_codec(), validation_renderer_for(std::nullopt));
}

}  // namespace pushpred
