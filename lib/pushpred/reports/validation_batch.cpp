#include "pushpred/reports/validation_batch.hpp"

#include <unistd.h>

#include <exception>
#include <iostream>
#include <mutex>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/runtime/mpi_world.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "pushpred/reports/validation_report.hpp"

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

BatchRunOutcome run_validation(const ValidateRun& run) {
  run.options.validate();  // before any work: a bad kind or range is an input error, nothing written
  const MpiWorld& world = MpiWorld::get();
  const bool mpi = world.size() > 1;
  if (mpi && run.shard)
    throw InputError("--shard " + run.shard->text() + " under mpirun: the ranks split the trials already; use one or "
                     "the other");
  std::optional<StagedOutput> out;  // checked before the long run
  open_output_at_root(world, run.out, out);
  if (!mpi && !run.shard)
    return write_validation_outputs(validate_diagnosis(run.options, progress_printer(run.progress)), *out);

  const ShardSpec shard = mpi ? ShardSpec{world.rank() + 1, world.size()} : *run.shard;
  const int count = validation_trial_count(run.options);
  std::vector<int> mine;
  for (int k = 0; k < count; ++k)
    if (k % shard.count == shard.index - 1) mine.push_back(k);
  const ValidationResult r =
      validate_diagnosis_trials(run.options, mine, progress_printer(run.progress && world.root()));
  std::vector<PartialItem> items;
  for (const auto& t : r.trials) {
    PartialItem item;
    item.index = static_cast<std::size_t>(t.index);
    item.result_json = partial_result_text(validation_trial_exact_json(t));
    items.push_back(std::move(item));
  }
  // The trials are the inputs: their count is what a merge compares (the options carry the seed and the kinds).
  std::vector<fs::path> trials;
  for (int k = 0; k < count; ++k) trials.emplace_back("trial " + std::to_string(k));
  std::string manifest =
      partial_manifest(kValidationCommand, shard, trials, options_json(r.options), std::move(items));

  if (mpi) {
    const ScratchFolder part("validate-rank" + std::to_string(world.rank()));  // rank 0's part: no files, a manifest
    return merge_at_root(world, std::move(manifest), part.path(), {},
                         [&](const MergedParts& merged) { return write_merged_validation(merged, *out); });
  }

  write_partial_output(*out, manifest);
  int failed = 0;
  for (const auto& t : r.trials) failed += !t.failure.empty();
  BatchRunOutcome outcome;
  outcome.partial = true;
  outcome.report = "ran " + std::to_string(r.trials.size()) + " of the " + std::to_string(count) +
                   " trials (shard " + shard.text() + "); partial output in " + out->destination().string() +
                   "; when every shard is done: pushpred merge --out DIR PART...\n";
  if (failed > 0) outcome.notes = std::to_string(failed) + " trial(s) of this shard could not be diagnosed\n";
  outcome.exit_code = failed > 0 ? 1 : 0;
  return outcome;
}

BatchRunOutcome write_merged_validation(const MergedParts& merged, StagedOutput& out) {
  ValidationResult r;
  try {
    r.options = options_from(merged.options);
  } catch (const InputError& e) {
    throw InputError("merge: " + plain_text(merged.items.empty() ? std::string("the parts")
                                                                 : merged.items.front().part->name) +
                     ": " + e.what());
  }
  for (const auto& m : merged.items) {
    try {
      r.trials.push_back(validation_trial_from_exact_json(m.result()));
      if (r.trials.back().index != static_cast<int>(m.index)) throw InputError("its index differs");
    } catch (const std::exception& e) {
      throw InputError(about(plain_text(m.part->name),
                             "trial " + std::to_string(m.index) + " is not readable: " + e.what()));
    }
  }
  return write_validation_outputs(r, out);
}

}  // namespace pushpred
