#include "pushpred/reports/diagnosis_batch.hpp"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <utility>

#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/push_groups.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "pushpred/reports/prediction_summary.hpp"
#include "pushpred/runtime/batch_runner.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

nlohmann::json num(double x) { return exact_number_json(x); }

/// One object's diagnosis as a per-object run reports it: its outcome (for the overview), what it prints on stdout
/// and on stderr, and how many of its pushes the diagnosis left out.
struct ObjectDone {
  DiagnosisGroupOutcome outcome;
  std::string printed;
  std::string complaints;
  std::size_t left_out = 0;
  std::vector<std::string> files;  ///< what its report wrote, relative to the output (a shard's or rank's only)
};

// --- An object's outcome in a partial output: what the overview and the printed report read of it, exactly.

nlohmann::json object_exact_json(const ObjectDone& d) {
  nlohmann::json j = {{"name", d.outcome.name},       {"pushes", d.outcome.pushes}, {"printed", d.printed},
                      {"complaints", d.complaints},   {"left_out", d.left_out},     {"error", d.outcome.error}};
  if (!d.outcome.result) {
    j["overview"] = nullptr;
    return j;
  }
  // The overview reads the object's shape and surface, its selected effects and six error summaries.
  const DiagnosisResult& r = *d.outcome.result;
  nlohmann::json selected = nlohmann::json::array();
  for (const auto& e : r.effects)
    if (e.selected) selected.push_back({{"kind", e.kind}, {"structural", e.structural}});
  j["overview"] = {{"shape", r.shape},
                   {"surface", r.surface},
                   {"selected", selected},
                   {"adequacy", {{"tested", r.adequacy.tested}, {"explained", r.adequacy.explained}}},
                   {"errors", held_out_errors_exact_json({&r.error_before, &r.error_base, &r.error_after, &r.hold,
                                                          &r.const_velocity, &r.quasi_static})}};
  return j;
}

ObjectDone object_from_exact_json(const nlohmann::json& j) {
  try {
    ObjectDone d;
    d.outcome.name = j.at("name").get<std::string>();
    d.outcome.pushes = j.at("pushes").get<std::size_t>();
    d.outcome.error = j.at("error").get<std::string>();
    d.printed = j.at("printed").get<std::string>();
    d.complaints = j.at("complaints").get<std::string>();
    d.left_out = j.at("left_out").get<std::size_t>();
    const auto& o = j.at("overview");
    if (o.is_null()) return d;
    DiagnosisResult r;
    r.shape = o.at("shape").get<std::string>();
    r.surface = o.at("surface").get<std::string>();
    for (const auto& e : o.at("selected")) {
      EffectReport report;
      report.kind = e.at("kind").get<std::string>();
      report.structural = e.at("structural").get<bool>();
      report.selected = true;
      r.effects.push_back(std::move(report));
    }
    r.adequacy.tested = o.at("adequacy").at("tested").get<bool>();
    r.adequacy.explained = o.at("adequacy").at("explained").get<bool>();
    held_out_errors_from_exact_json(
        o.at("errors"), {&r.error_before, &r.error_base, &r.error_after, &r.hold, &r.const_velocity, &r.quasi_static},
        "an object");
    d.outcome.result = std::move(r);
    return d;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not an object's diagnosis written by pushpred: ") + e.what());
  }
}

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
            {"fit_base_settings", o.fit_base_settings},
            {"max_refits", o.max_refits},
            {"exclude", run.exclude},
            {"plots", run.plots}}},
          {"read", {{"pushes", pushes_read}, {"failures", failures}}}};
}

std::string failure_lines(const std::vector<BatchFailure>& failures) {
  std::string s;
  for (const auto& f : failures) s += "FAILED " + f.source + ": " + f.reason + "\n";
  return s;
}

/// The end of a per-object run (a whole run's, or the merged parts'): overview.md and overview.json written and
/// `out` committed, and what the run prints: each object's report in order, then the count; on stderr
/// `read_failures` (the unreadable inputs, when not listed already), each object's complaints, the failed count.
/// When no object could be diagnosed nothing is written and the exit code is 2.
BatchRunOutcome finish_per_object(std::vector<ObjectDone> objects, std::size_t pushes_read, bool read_failed,
                                  const std::string& read_failures, StagedOutput& out) {
  BatchRunOutcome outcome;
  outcome.notes = read_failures;
  std::vector<DiagnosisGroupOutcome> outcomes;
  std::size_t left_out = 0, failed = 0;
  for (auto& d : objects) {
    outcome.report += d.printed;
    outcome.notes += d.complaints;
    left_out += d.left_out;
    failed += d.outcome.result ? 0 : 1;
    outcomes.push_back(std::move(d.outcome));
  }
  if (failed == outcomes.size()) {
    outcome.notes += "pushpred: error: no object could be diagnosed; nothing written\n";
    outcome.exit_code = 2;
    return outcome;
  }
  write_text_atomically(out.path("overview.md"), diagnosis_overview_markdown(outcomes));
  write_text_atomically(out.path("overview.json"), json_file_text(diagnosis_overview_json(outcomes)));
  out.commit();
  outcome.report += std::to_string(outcomes.size() - failed) + " of " + std::to_string(outcomes.size()) +
                    " objects diagnosed (" + std::to_string(pushes_read) + " pushes read); overview in " +
                    out.destination().string() + "/overview.md\n";
  if (failed > 0)
    outcome.notes += std::to_string(failed) + " of " + std::to_string(outcomes.size()) + " objects failed\n";
  outcome.exit_code = failed == 0 && left_out == 0 && !read_failed ? 0 : 1;
  return outcome;
}

/// The objects of a per-object run, in order, made into its overview. What was read (how many pushes, which inputs
/// failed) comes from the run's options (options_json); a merge of shards lists the unreadable inputs, which a whole
/// run and an MPI job's rank 0 listed as they read them.
class DiagnosisRenderer final : public BatchRenderer<ObjectDone> {
 public:
  DiagnosisRenderer(StagedOutput& out, std::size_t pushes_read, std::vector<BatchFailure> read_failures, bool list)
      : out_(out), pushes_read_(pushes_read), read_failures_(std::move(read_failures)), list_(list) {}
  void add(std::size_t, ObjectDone&& done) override { objects_.push_back(std::move(done)); }
  void add_failure(std::size_t, BatchFailure&& failure) override {
    ObjectDone d;  // an object's diagnosis catches its input errors: only the unexpected reaches here
    d.outcome.name = failure.source;
    d.outcome.error = failure.reason;
    d.complaints = "FAILED " + failure.source + ": " + failure.reason + "\n";
    objects_.push_back(std::move(d));
  }
  BatchRunOutcome finish() override {
    return finish_per_object(std::move(objects_), pushes_read_, !read_failures_.empty(),
                             list_ ? failure_lines(read_failures_) : std::string(), out_);
  }

 private:
  StagedOutput& out_;
  std::size_t pushes_read_;
  std::vector<BatchFailure> read_failures_;
  bool list_;
  std::vector<ObjectDone> objects_;
};

std::unique_ptr<BatchRenderer<ObjectDone>> diagnosis_renderer(StagedOutput& out, const nlohmann::json& options,
                                                              RenderFor mode) {
  std::size_t pushes_read = 0;
  std::vector<BatchFailure> read_failures;
  try {
    if (!options.at("per_object").get<bool>()) throw InputError("not --per-object");
    const auto& read = options.at("read");
    pushes_read = read.at("pushes").get<std::size_t>();
    for (const auto& f : read.at("failures"))
      read_failures.push_back({f.at("source").get<std::string>(), f.at("reason").get<std::string>()});
  } catch (const std::exception&) {
    throw InputError("its partial.json's options are not those of `diagnose --per-object`");
  }
  return std::make_unique<DiagnosisRenderer>(out, pushes_read, std::move(read_failures),
                                             mode == RenderFor::shard_merge);
}

PartialCodec<ObjectDone> diagnosis_codec() {
  PartialCodec<ObjectDone> codec;
  codec.encode = object_exact_json;
  codec.decode = object_from_exact_json;
  codec.files = [](std::size_t, const ObjectDone& d) { return d.files; };
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
    throw InputError("--shard " + run.shard->text() + " under mpirun: the ranks split the objects already; use one "
                     "or the other");
  if (run.shard && !run.per_object)
    throw InputError("--shard " + run.shard->text() + ": `diagnose` splits its work only with --per-object (one "
                     "object is one unit of work, and a diagnosis of one object cannot be split); drop --shard, or "
                     "pass --per-object for a batch of several objects");
  if (mpi && !run.per_object)
    throw InputError("`diagnose` runs under mpirun only with --per-object (the ranks split the objects; a diagnosis "
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
  return merge_batch<ObjectDone>(merged, out, diagnosis_codec(), diagnosis_renderer);
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
  BatchJob<ObjectDone> job;
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
    ObjectDone d;
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
  job.note = [](const ObjectDone& d) {
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
  return run_batch_job<ObjectDone>(job, split, run.out, diagnosis_renderer);
}

}  // namespace pushpred
