#include "pushpred/reports/diagnosis_batch.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>
#include <utility>

#include "pushpred/core/error.hpp"
#include "pushpred/runtime/mpi_world.hpp"
#include "pushpred/runtime/parallel_batch.hpp"
#include "pushpred/diagnosis/push_groups.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "pushpred/reports/prediction_summary.hpp"

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

BatchRunOutcome merged_diagnoses(const MergedParts& merged, StagedOutput& out, bool list_read_failures) {
  if (merged.command != kDiagnoseCommand)
    throw InputError("merge: the parts are partial outputs of `" + plain_text(merged.command) +
                     "`, not of `diagnose`");
  const std::string first = merged.items.empty() ? std::string("the parts") : merged.items.front().part->name;
  std::size_t pushes_read = 0;
  std::vector<BatchFailure> read_failures;
  try {
    if (!merged.options.at("per_object").get<bool>()) throw InputError("not --per-object");
    const auto& read = merged.options.at("read");
    pushes_read = read.at("pushes").get<std::size_t>();
    for (const auto& f : read.at("failures"))
      read_failures.push_back({f.at("source").get<std::string>(), f.at("reason").get<std::string>()});
  } catch (const std::exception&) {
    throw InputError("merge: " + plain_text(first) + ": its partial.json's options are not those of `diagnose "
                                                     "--per-object`");
  }
  std::vector<ObjectDone> objects;
  for (const auto& m : merged.items) {
    try {
      objects.push_back(object_from_exact_json(m.result()));
    } catch (const std::exception& e) {
      throw InputError(about(plain_text(m.part->name),
                             "object " + std::to_string(m.index + 1) + " is not readable: " + e.what()));
    }
  }
  for (const auto& m : merged.items)
    for (const auto& file : m.files) write_text_atomically(out.path(file), m.part->read_file(file));
  return finish_per_object(std::move(objects), pushes_read, !read_failures.empty(),
                           list_read_failures ? failure_lines(read_failures) : std::string(), out);
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

/// The positions of the groups this process diagnoses: all of them, or the shard's (the sorted groups dealt out as
/// shard_positions deals out inputs).
std::vector<std::size_t> groups_of_this_process(const std::vector<fs::path>& names, bool partial,
                                                const ShardSpec& shard) {
  if (partial) return shard_positions(names, shard);
  std::vector<std::size_t> mine;
  for (std::size_t i = 0; i < names.size(); ++i) mine.push_back(i);
  return mine;
}

/// Diagnoses the groups at `mine`, shared out over the jobs, each written to folder_of(its name): an object that
/// cannot be diagnosed is reported and the others go on. What each prints is kept, in the objects' order, whatever
/// the jobs.
std::vector<ObjectDone> diagnose_objects(std::vector<PushGroup>& groups, const std::vector<std::size_t>& mine,
                                         const DiagnoseRun& run, const EffectLibrary& library,
                                         const std::function<fs::path(const std::string&)>& folder_of,
                                         const std::string& label, bool speaks) {
  const DiagnosisOptions& o = run.options;
  std::vector<ObjectDone> done(mine.size());
  BatchProgress progress(label, "objects", mine.size(), speaks);
  std::atomic<std::size_t> next{0};
  const auto one_object = [&](std::size_t k) {
    PushGroup& g = groups[mine[k]];
    ObjectDone& d = done[k];
    d.outcome = DiagnosisGroupOutcome{g.name(), g.pushes.size(), std::nullopt, ""};
    try {
      DiagnosisResult result = diagnose(g.pushes, library, o);
      write_diagnosis_report(result, o, folder_of(g.name()), run.plots);
      d.printed = diagnosis_summary_text(result);
      for (const auto& f : result.failures) d.complaints += "LEFT OUT " + f.source + ": " + f.reason + "\n";
      d.left_out = result.failures.size();
      d.outcome.result = std::move(result);
    } catch (const InputError& e) {
      d.outcome.error = e.what();
      d.complaints += "FAILED " + g.name() + ": " + e.what() + "\n";
    }
    progress.item_done();
  };
  const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, run.jobs)), mine.size());
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < threads; ++t)
    pool.emplace_back([&] {
      for (std::size_t k = next++; k < mine.size(); k = next++) one_object(k);
    });
  for (auto& t : pool) t.join();
  progress.finish();
  return done;
}

std::string progress_label(bool mpi, bool partial, const MpiWorld& world, const ShardSpec& shard) {
  return mpi       ? "diagnose (rank 0 of " + std::to_string(world.size()) + " ranks)"
         : partial ? "diagnose (shard " + shard.text() + ")"
                   : std::string("diagnose");
}

/// This process's share of a split per-object run, as the items of its partial output.
struct PartialShare {
  std::vector<PartialItem> items;
  std::vector<std::string> files;  ///< every file of this rank's objects (relative paths), for MPI rank 0
  bool anything_failed = false;
  std::string complaints;
  std::size_t diagnosed = 0;
};

PartialShare partial_share(const std::vector<ObjectDone>& done, const std::vector<std::size_t>& mine, bool read_failed,
                           const std::function<fs::path(const std::string&)>& folder_of) {
  PartialShare share;
  share.anything_failed = read_failed;
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const ObjectDone& d = done[k];
    PartialItem item;
    item.index = mine[k];
    item.result_json = partial_result_text(object_exact_json(d));
    item.files = files_under(folder_of(d.outcome.name), d.outcome.name);
    share.files.insert(share.files.end(), item.files.begin(), item.files.end());
    share.anything_failed = share.anything_failed || !d.outcome.result || d.left_out > 0;
    share.diagnosed += d.outcome.result ? 1 : 0;
    share.complaints += d.complaints;
    share.items.push_back(std::move(item));
  }
  return share;
}

/// The outcome of a shard (not an MPI rank): what it prints once its partial output is written.
BatchRunOutcome shard_outcome(const PartialShare& share, std::size_t objects_here, std::size_t objects_in_all,
                              const ShardSpec& shard, const StagedOutput& out) {
  BatchRunOutcome outcome;
  outcome.partial = true;
  outcome.report = "diagnosed " + std::to_string(share.diagnosed) + " of the " + std::to_string(objects_here) +
                   " objects of shard " + shard.text() + " (" + std::to_string(objects_in_all) +
                   " objects in all); partial output in " + out.destination().string() +
                   "; when every shard is done: pushpred merge --out DIR PART...\n";
  outcome.notes = share.complaints;
  outcome.exit_code = share.anything_failed ? 1 : 0;
  return outcome;
}

}  // namespace

BatchRunOutcome write_merged_diagnoses(const MergedParts& merged, StagedOutput& out) {
  return merged_diagnoses(merged, out, true);
}

BatchRunOutcome run_diagnose(const DiagnoseRun& run) {
  run.options.validate();
  const EffectLibrary library = effect_library(run);
  const MpiWorld& world = MpiWorld::get();
  const bool mpi = world.size() > 1;
  check_split(run, mpi);
  const bool speaks = !mpi || world.root();

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
  const std::size_t loaded_count = loaded.results.size();
  std::vector<PushGroup> groups = group_by_object(loaded.results);
  if (!run.per_object) {
    check_one_object(groups);
    return diagnose_single_object(run, library, groups.front().pushes, loaded.failures);
  }

  // One diagnosis per object: all of them, or the shard's, or this rank's.
  const bool partial = mpi || run.shard.has_value();
  const ShardSpec shard = mpi ? ShardSpec{world.rank() + 1, world.size()} : run.shard.value_or(ShardSpec{});
  std::vector<fs::path> names;
  for (const auto& g : groups) names.emplace_back(g.name());
  const std::vector<std::size_t> mine = groups_of_this_process(names, partial, shard);

  std::optional<StagedOutput> out;  // under MPI only rank 0 writes
  open_output_at_root(world, run.out, out);
  std::optional<ScratchFolder> scratch;  // under MPI each rank's objects go from there to rank 0
  if (mpi) scratch.emplace("diagnose-rank" + std::to_string(world.rank()));
  const std::function<fs::path(const std::string&)> folder_of = [&](const std::string& name) {
    return mpi ? scratch->path() / name : out->path(name);
  };
  std::vector<ObjectDone> done =
      diagnose_objects(groups, mine, run, library, folder_of, progress_label(mpi, partial, world, shard), speaks);
  if (!partial) return finish_per_object(std::move(done), loaded_count, !loaded.failures.empty(), "", *out);

  PartialShare share = partial_share(done, mine, !loaded.failures.empty(), folder_of);
  // The units are the objects; the fingerprint covers the input files as given and the objects they make.
  std::vector<fs::path> listed = inputs;
  listed.emplace_back("");
  listed.insert(listed.end(), names.begin(), names.end());
  std::string manifest = partial_manifest(kDiagnoseCommand, shard, groups.size(), inputs_fingerprint(listed),
                                          options_json(run, loaded_count, loaded.failures), std::move(share.items));
  if (mpi)
    return merge_at_root(world, std::move(manifest), scratch->path(), share.files,
                         [&](const MergedParts& merged) { return merged_diagnoses(merged, *out, false); });
  write_partial_output(*out, manifest);
  return shard_outcome(share, mine.size(), groups.size(), shard, *out);
}

}  // namespace pushpred
