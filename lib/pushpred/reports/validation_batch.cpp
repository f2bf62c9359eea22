#include "pushpred/reports/validation_batch.hpp"

#include <unistd.h>

#include <exception>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "pushpred/reports/validation_report.hpp"
#include "pushpred/runtime/batch_runner.hpp"

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
          {"fit_base_settings", o.diagnosis.fit_base_settings},
          {"hide", o.hide},
          {"draw_preloads", o.draw_preloads},
          {"draw_sensor_offsets", o.draw_sensor_offsets}};
}

ValidationOptions options_from(const nlohmann::json& j) {
  try {
    ValidationOptions o;
    o.trials_per_kind = j.at("trials_per_kind").get<int>();
    o.seed = j.at("seed").get<std::uint64_t>();
    o.kinds = j.at("kinds").get<std::vector<std::string>>();
    o.min_pushes = j.at("min_pushes").get<int>();
    o.max_pushes = j.at("max_pushes").get<int>();
    o.min_floor_multiple = exact_number(j.at("min_floor_multiple"));
    o.max_floor_multiple = exact_number(j.at("max_floor_multiple"));
    o.diagnosis.relevance_fraction = exact_number(j.at("relevance_fraction"));
    o.diagnosis.bic_threshold = exact_number(j.at("bic_threshold"));
    o.diagnosis.floor_margin_std = exact_number(j.at("floor_margin_std"));
    o.diagnosis.fit_base_settings = j.at("fit_base_settings").get<bool>();
    o.hide = j.at("hide").get<std::vector<std::string>>();
    o.draw_preloads = j.at("draw_preloads").get<bool>();
    o.draw_sensor_offsets = j.at("draw_sensor_offsets").get<bool>();
    return o;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("its options are not those of validate-diagnosis: ") + e.what());
  }
}

/// Writes validation.json and validation.md, commits `out`, and says what the whole run says.
BatchRunOutcome write_validation_outputs(const ValidationResult& r, StagedOutput& out) {
  write_text_atomically(out.path("validation.json"), validation_json(r).dump(2) + "\n");
  write_text_atomically(out.path("validation.md"), validation_markdown(r));
  out.commit();
  const ValidationSummary s = summarise_validation(r);
  std::ostringstream report;
  report << "right kind named at >= 2 floors: " << s.named_at_twice_floor << " / " << s.effect_trials_at_twice_floor
         << "; nothing named on clean: " << s.clean_nothing_named << " / " << s.clean_trials
         << "; corrected below the paper: " << s.after_below_paper << " / " << s.compared
         << ", below const_velocity: " << s.after_below_const_velocity << " / " << s.compared << "\n";
  if (s.hidden_trials_at_twice_floor > 0 || s.clean_adequacy_tested > 0)
    report << "hidden kinds at >= 2 floors: unexplained " << s.hidden_unexplained << " / " << s.hidden_adequacy_tested
           << " tested (" << s.hidden_trials_at_twice_floor << " trials), no kind named " << s.hidden_none_named
           << " / " << s.hidden_trials_at_twice_floor << "; clean explained " << s.clean_explained << " / "
           << s.clean_adequacy_tested << " tested\n";
  report << "report in " << out.destination().string() << "/validation.md\n";
  BatchRunOutcome outcome;
  outcome.report = report.str();
  if (s.failed > 0) outcome.notes = std::to_string(s.failed) + " trial(s) could not be diagnosed (listed in validation.md)\n";
  outcome.exit_code = s.failed > 0 ? 1 : 0;
  return outcome;
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

}  // namespace

nlohmann::json validation_trial_exact_json(const ValidationTrial& t) {
  return {{"index", t.index},
          {"seed", t.seed},
          {"true_kind", t.true_kind},
          {"amount", exact_number_json(t.amount)},
          {"floor", exact_number_json(t.floor)},
          {"floor_multiple", exact_number_json(t.floor_multiple)},
          {"shape", t.shape},
          {"surface_friction", exact_number_json(t.surface_friction)},
          {"contact_friction", exact_number_json(t.contact_friction)},
          {"contact_stiffness_N_m", exact_number_json(t.contact_stiffness_N_m)},
          {"pressure_rim_weight", exact_number_json(t.pressure_rim_weight)},
          {"pushes", t.pushes},
          {"named", t.named},
          {"negligible", t.negligible},
          {"true_named", t.true_named},
          {"fitted_amount", exact_number_json(t.fitted_amount)},
          {"true_score", exact_number_json(t.true_score)},
          {"true_passed", t.true_passed},
          {"true_negligible", t.true_negligible},
          {"true_amount", exact_number_json(t.true_amount)},
          {"true_floor", exact_number_json(t.true_floor)},
          {"true_note", t.true_note},
          {"hidden", t.hidden},
          {"preloaded_pushes", t.preloaded_pushes},
          {"adequacy_tested", t.adequacy_tested},
          {"explained", t.explained},
          {"errors",
           held_out_errors_exact_json({&t.before, &t.base, &t.after, &t.hold, &t.const_velocity, &t.quasi_static})},
          {"failure", t.failure}};
}

ValidationTrial validation_trial_from_exact_json(const nlohmann::json& j) {
  try {
    ValidationTrial t;
    t.index = j.at("index").get<int>();
    t.seed = j.at("seed").get<std::uint64_t>();
    t.true_kind = j.at("true_kind").get<std::string>();
    t.amount = exact_number(j.at("amount"));
    t.floor = exact_number(j.at("floor"));
    t.floor_multiple = exact_number(j.at("floor_multiple"));
    t.shape = j.at("shape").get<std::string>();
    t.surface_friction = exact_number(j.at("surface_friction"));
    t.contact_friction = exact_number(j.at("contact_friction"));
    t.contact_stiffness_N_m = exact_number(j.at("contact_stiffness_N_m"));
    t.pressure_rim_weight = exact_number(j.at("pressure_rim_weight"));
    t.pushes = j.at("pushes").get<int>();
    t.named = j.at("named").get<std::vector<std::string>>();
    t.negligible = j.at("negligible").get<std::vector<std::string>>();
    t.true_named = j.at("true_named").get<bool>();
    t.fitted_amount = exact_number(j.at("fitted_amount"));
    t.true_score = exact_number(j.at("true_score"));
    t.true_passed = j.at("true_passed").get<bool>();
    t.true_negligible = j.at("true_negligible").get<bool>();
    t.true_amount = exact_number(j.at("true_amount"));
    t.true_floor = exact_number(j.at("true_floor"));
    t.true_note = j.at("true_note").get<std::string>();
    t.hidden = j.at("hidden").get<bool>();
    t.preloaded_pushes = j.at("preloaded_pushes").get<int>();
    t.adequacy_tested = j.at("adequacy_tested").get<bool>();
    t.explained = j.at("explained").get<bool>();
    held_out_errors_from_exact_json(j.at("errors"),
                                    {&t.before, &t.base, &t.after, &t.hold, &t.const_velocity, &t.quasi_static},
                                    "a trial");
    t.failure = j.at("failure").get<std::string>();
    return t;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not a trial written by pushpred: ") + e.what());
  }
}

namespace {

/// The trials of a run, in order, made into validation.json and validation.md.
class ValidationRenderer final : public BatchRenderer<ValidationTrial> {
 public:
  ValidationRenderer(StagedOutput& out, ValidationOptions options) : out_(out) { result_.options = std::move(options); }
  void add(std::size_t index, ValidationTrial&& trial) override {
    if (trial.index != static_cast<int>(index))
      throw InputError("trial " + std::to_string(index) + ": its index differs");
    result_.trials.push_back(std::move(trial));
  }
  void add_failure(std::size_t index, BatchFailure&& failure) override {
    ValidationTrial trial;  // a trial catches what a diagnosis throws: only the unexpected reaches here
    trial.index = static_cast<int>(index);
    trial.failure = failure.reason;
    result_.trials.push_back(std::move(trial));
  }
  BatchRunOutcome finish() override { return write_validation_outputs(result_, out_); }

 private:
  StagedOutput& out_;
  ValidationResult result_;
};

PartialCodec<ValidationTrial> validation_codec() {
  PartialCodec<ValidationTrial> codec;
  codec.encode = validation_trial_exact_json;
  codec.decode = validation_trial_from_exact_json;
  codec.name = [](std::size_t index) { return "trial " + std::to_string(index); };
  return codec;
}

/// The renderer of a whole run (its options as given, kinds filled in), or of a merge (the options its parts record).
RendererFactory<ValidationTrial> validation_renderer(std::optional<ValidationOptions> whole_run) {
  return [whole_run](StagedOutput& out, const nlohmann::json& options, RenderFor mode) {
    return std::make_unique<ValidationRenderer>(
        out, mode == RenderFor::whole_run && whole_run ? *whole_run : options_from(options));
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
  return run_batch_job<ValidationTrial>(job, split, run.out, validation_renderer(options));
}

BatchRunOutcome write_merged_validation(const MergedParts& merged, StagedOutput& out) {
  return merge_batch<ValidationTrial>(merged, out, validation_codec(), validation_renderer(std::nullopt));
}

}  // namespace pushpred
