#include "pushpred/jobs/diagnosis_job.hpp"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <utility>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/push_groups.hpp"
#include "pushpred/jobs/partial_codecs.hpp"
#include "pushpred/reports/diagnosis_overview.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "pushpred/reports/prediction_summary.hpp"
#include "pushpred/runtime/batch_runner.hpp"
#include "pushpred/runtime/shard.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

nlohmann::json num(double x) { return exact_number_json(x); }

/// What tells two per-object runs apart (--jobs changes nothing), and what the merge prints of the reading: how
/// many pushes were read and which inputs could not be (the same in every shard, since every shard reads all).
nlohmann::json options_json(const DiagnoseRun& run, std::size_t pushes_read, const std::vector<BatchFailure>& failed) {
  const DiagnosisOptions& o = run.options;
  nlohmann::json failures = nlohmann::json::array();
  for (const auto& f : failed) failures.push_back({{"source", f.source}, {"reason", f.reason}});
  return {{"per_object", true},
          {"study", prediction_options_json(o.study)},
          {"settings",
           {{"mu", num(o.study.friction_coefficient)},
            {"shape", run.shape},
            {"rate_hz", num(run.preprocess.rate_hz)},
            {"bic_threshold", num(o.bic_threshold)},
            {"relevance_fraction", num(o.relevance_fraction)},
            {"floor_margin_std", num(o.floor_margin_std)},
            {"sensor_zero_spread_N", num(o.sensor_zero_spread_N)},
            {"measured_contact_compliance", o.measured_contact_compliance},
            {"fit_base_settings", o.fit_base_settings},
            {"max_refits", o.max_refits},
            {"exclude", run.exclude},
            {"plots", run.plots}}},
          {"read", {{"pushes", pushes_read}, {"failures", failures}}}};
}

/// The overview's renderer from a run's options (options_json), which say what was read: how many pushes, which
/// inputs failed. A merge of shards lists the unreadable inputs, which a whole run and an MPI job's rank 0 listed as
/// they read them.
std::unique_ptr<BatchRenderer<DiagnosedObject>> diagnosis_renderer(StagedOutput& out, const nlohmann::json& options,
                                                                   RenderFor mode) {
  std::size_t pushes_read = 0;
  std::vector<BatchFailure> read_failures;
  try {
    if (!options.at("per_object").get<bool>()) throw InputError("not --per-object");
    const auto& read = options.at("read");
    pushes_read = json_whole_number<std::size_t>(read.at("pushes"), "pushes");
    for (const auto& f : read.at("failures"))
      read_failures.push_back({f.at("source").get<std::string>(), f.at("reason").get<std::string>()});
  } catch (const std::exception&) {
    throw InputError("its partial.json's options are not those of `diagnose --per-object`");
  }
  return diagnosis_overview_renderer(out, pushes_read, std::move(read_failures), mode == RenderFor::shard_merge);
}

PartialCodec<DiagnosedObject> diagnosis_codec() {
  PartialCodec<DiagnosedObject> codec;
  codec.encode = diagnosed_object_exact_json;
  codec.decode = diagnosed_object_from_exact_json;
  codec.files = [](std::size_t, const DiagnosedObject& d) { return d.files; };
  codec.name = [](std::size_t index) { return "object " + std::to_string(index + 1); };
  return codec;
}

/// The files under `folder`, as sorted paths relative to its parent (`name/...`).
std::vector<std::string> files_under(const fs::path& folder, const std::string& name) {
  std::vector<std::string> files;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) files.push_back(name + "/" + fs::relative(entry.path(), folder).generic_string());
  std::sort(files.begin(), files.end());
  return files;
}

/// The standard candidate effects less those the run excludes.
EffectLibrary effect_library(const DiagnoseRun& run) {
  EffectLibrary library = EffectLibrary::standard();
  for (const auto& kind : run.exclude) library.remove(kind);
  return library;
}

/// Refuses the splits a diagnosis cannot take: --shard under mpirun, and either without --per-object.
void check_split(const DiagnoseRun& run, bool mpi) {
  if (mpi && run.shard)
    throw InputError("--shard " + run.shard->text() +
                     " under mpirun: the ranks split the objects already; use one "
                     "or the other");
  if (run.shard && !run.per_object)
    throw InputError("--shard " + run.shard->text() +
                     ": `diagnose` splits its work only with --per-object (one "
                     "object is one unit of work, and a diagnosis of one object cannot be split); drop --shard, or "
                     "pass --per-object for a batch of several objects");
  if (mpi && !run.per_object)
    throw InputError(
        "`diagnose` runs under mpirun only with --per-object (the ranks split the objects; a diagnosis "
        "of one object is one process's work); run it as one process");
}

/// Refuses pushes of several objects (or surfaces) without --per-object, naming them.
void check_one_object(const std::vector<PushGroup>& groups) {
  if (groups.size() <= 1) return;
  std::string names;
  for (const auto& g : groups)
    names += (names.empty() ? "" : ", ") + g.name() + " (" + std::to_string(g.pushes.size()) + ")";
  throw InputError("the pushes are of " + std::to_string(groups.size()) + " objects or surfaces: " + names +
                   "; a diagnosis fits one object on one surface: give one, or pass --per-object");
}

/// One diagnosis of all the pushes (one object), written to run.out.
BatchRunOutcome diagnose_single_object(const DiagnoseRun& run, const EffectLibrary& library,
                                       const std::vector<SynchronisedPush>& pushes,
                                       const std::vector<BatchFailure>& read_failures) {
  const DiagnosisOptions& o = run.options;
  DiagnosisResult result = diagnose(pushes, library, o);
  // Pushes read but left out by the diagnosis; the unreadable ones were listed above.
  for (const auto& f : result.failures) std::cerr << "LEFT OUT " << f.source << ": " << f.reason << "\n";
  result.failures.insert(result.failures.begin(), read_failures.begin(), read_failures.end());
  StagedOutput out(run.out);
  write_diagnosis_report(result, o, out, run.plots);
  out.commit();
  BatchRunOutcome outcome;
  for (const auto& line : result.log) outcome.report += line + "\n";
  outcome.report += diagnosis_summary_text(result);
  outcome.report += "report in " + run.out + "/report.md, data in " + run.out + "/diagnosis.json\n";
  outcome.exit_code = result.failures.empty() ? 0 : 1;
  return outcome;
}

}  // namespace

BatchRunOutcome write_merged_diagnoses(const MergedParts& merged, StagedOutput& out) {
  if (merged.command != kDiagnoseCommand)
    throw InputError("merge: the parts are partial outputs of `" + plain_text(merged.command) + "`, not of `diagnose`");
  return merge_batch<DiagnosedObject>(merged, out, diagnosis_codec(), diagnosis_renderer);
}

BatchRunOutcome run_diagnose(const DiagnoseRun& run) {
  run.options.validate();
  const EffectLibrary library = effect_library(run);
  const BatchSplit split{run.shard, run.mpi};
  check_split(run, split.over_ranks());
  const bool speaks = split.speaks();

  // Every shard and every rank reads every input: the groups are known only once the files are read.
  const auto inputs = expand_inputs(run.inputs);
  const Batch<SynchronisedPush> loaded = run_batch(
      inputs, [&](const fs::path& path) { return load_push(path, run.shape, run.preprocess); }, run.jobs, nullptr);
  if (speaks)
    for (const auto& f : loaded.failures) std::cerr << "FAILED " << f.source << ": " << f.reason << "\n";
  if (loaded.results.empty()) {
    if (!speaks) {  // rank 0 says it
      BatchRunOutcome quiet;
      quiet.quiet = true;
      return quiet;
    }
    throw InputError("no push could be read; nothing written");
  }
  std::vector<PushGroup> groups = group_by_object(loaded.results);
  if (!run.per_object) {
    check_one_object(groups);
    return diagnose_single_object(run, library, groups.front().pushes, loaded.failures);
  }

  // One diagnosis per object: all of them, or the shard's, or this rank's.
  BatchJob<DiagnosedObject> job;
  job.command = job.label = kDiagnoseCommand;
  job.unit = "objects";
  for (const auto& g : groups) job.units.emplace_back(g.name());
  // The units are the objects; the fingerprint covers the input files as given and the objects they make.
  std::vector<fs::path> listed = inputs;
  listed.emplace_back("");
  listed.insert(listed.end(), job.units.begin(), job.units.end());
  job.fingerprint = inputs_fingerprint(listed);
  job.options = options_json(run, loaded.results.size(), loaded.failures);
  job.jobs = run.jobs;
  const bool partial = split.partial();
  // An object that cannot be diagnosed is reported in the overview and the others go on.
  job.item = [&](std::size_t index, FileSink& files) {
    const PushGroup& g = groups[index];
    DiagnosedObject d;
    d.outcome = DiagnosisGroupOutcome{g.name(), g.pushes.size(), std::nullopt, ""};
    try {
      DiagnosisResult result = diagnose(g.pushes, library, run.options);
      write_diagnosis_report(result, run.options, files.path(g.name()), run.plots);
      d.printed = diagnosis_summary_text(result);
      for (const auto& f : result.failures) d.complaints += "LEFT OUT " + f.source + ": " + f.reason + "\n";
      d.left_out = result.failures.size();
      d.outcome.result = std::move(result);
    } catch (const InputError& e) {
      d.outcome.error = e.what();
      d.complaints += "FAILED " + g.name() + ": " + e.what() + "\n";
    }
    if (partial) d.files = files_under(files.path(g.name()), g.name());
    return d;
  };
  job.codec = diagnosis_codec();
  job.note = [](const DiagnosedObject& d) {
    ShardNote note;
    note.counted = d.outcome.result.has_value();
    note.failed = !d.outcome.result || d.left_out > 0;
    note.text = d.complaints;
    return note;
  };
  const bool read_failed = !loaded.failures.empty();
  job.shard_outcome = [read_failed](const ShardDone& done) {
    BatchRunOutcome outcome;
    outcome.partial = true;
    outcome.report = "diagnosed " + std::to_string(done.counted) + " of the " + std::to_string(done.here) +
                     " objects of shard " + done.shard.text() + " (" + std::to_string(done.all) +
                     " objects in all); partial output in " + done.destination +
                     "; when every shard is done: pushpred merge --out DIR PART...\n";
    outcome.notes = done.notes;
    outcome.exit_code = read_failed || done.failed > 0 || !done.failures.empty() ? 1 : 0;
    return outcome;
  };
  return run_batch_job<DiagnosedObject>(job, split, run.out, diagnosis_renderer);
}

}  // namespace pushpred
