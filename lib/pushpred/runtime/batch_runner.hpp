#pragma once
// The one batch runner of `predict`, `diagnose --per-object` and `validate-diagnosis`: a command's units (input
// files, objects, trials), one item function each, run
// - whole, on this process's threads (parallel_batch.hpp), each result handed in unit order to the command's
//   renderer, which writes the outputs;
// - as one share of them (`--shard I/N`, shard.hpp), each result encoded by the command's codec into a partial
//   output, which `pushpred merge` reads back;
// - as one rank of the program's MPI session (mpi_world.hpp), each rank's partial output sent to rank 0, which
//   merges them.
// A merge decodes each item, copies its files into the output at the paths it lists and hands it to the same
// renderer, in unit order, so that a merge writes what the whole run writes, byte for byte.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/runtime/mpi_world.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/parallel_batch.hpp"
#include "pushpred/runtime/shard.hpp"

namespace pushpred {

/// How a run is split: whole, one shard (`--shard I/N`), or one rank of the program's MPI session.
struct BatchSplit {
  std::optional<ShardSpec> shard;   ///< --shard given (1/1 included: a partial output of every unit)
  const MpiSession* mpi = nullptr;  ///< the program's session (none: a plain run); split over its ranks when several

  bool over_ranks() const { return mpi && mpi->size() > 1; }
  bool partial() const { return over_ranks() || shard.has_value(); }
  /// This process's share: its rank's under MPI, the shard's, or 1/1.
  ShardSpec share() const {
    return over_ranks() ? ShardSpec{mpi->rank() + 1, mpi->size()} : shard.value_or(ShardSpec{});
  }
  /// Whether this process prints (rank 0 of a job, or a plain process).
  bool speaks() const { return !over_ranks() || mpi->root(); }
  /// Throws InputError for --shard under mpirun; `units` names what the ranks split ("inputs", "trials").
  void refuse_shard_under_mpi(const std::string& units) const {
    if (over_ranks() && shard)
      throw InputError("--shard " + shard->text() + " under mpirun: the ranks split the " + units +
                       " already; use one or the other");
  }
};

/// What a shard says of one of its results: whether it counts as done ("diagnosed 3 of the 4 objects"), whether it
/// makes the shard's exit code 1, and lines for stderr.
struct ShardNote {
  bool counted = true;
  bool failed = false;
  std::string text;
};

/// A shard's run, for the command's report once its partial output is written.
struct ShardDone {
  ShardSpec shard;
  std::size_t here = 0;                ///< units of this shard
  std::size_t all = 0;                 ///< units of the whole run
  std::size_t counted = 0;             ///< results counted (ShardNote::counted)
  std::size_t failed = 0;              ///< results failed (ShardNote::failed)
  std::vector<BatchFailure> failures;  ///< units that gave no result
  std::string notes;                   ///< the results' ShardNote texts, in unit order
  std::string destination;             ///< the partial output's folder
};

/// A command's results made into its outputs, in unit order: a whole run's as they finish, a merge's as read back
/// from the parts (each item's files already copied into the output at the paths it lists).
template <class Result>
class BatchRenderer {
 public:
  virtual ~BatchRenderer() = default;
  virtual void add(std::size_t index, Result&& result) = 0;
  virtual void add_failure(std::size_t index, BatchFailure&& failure) = 0;
  /// Writes what is left and commits the output (or leaves it uncommitted when nothing was made); what the run says.
  virtual BatchRunOutcome finish() = 0;
};

/// Where a renderer's results come from: a whole run, the merge of an MPI job's ranks, or `pushpred merge`.
enum class RenderFor { whole_run, mpi_merge, shard_merge };

/// Makes a command's renderer writing into `out`, from the options its partial output records (a merge's are read
/// back from the parts: throws InputError when they are not the command's).
template <class Result>
using RendererFactory =
    std::function<std::unique_ptr<BatchRenderer<Result>>(StagedOutput& out, const nlohmann::json& options, RenderFor)>;

/// How a result crosses a partial output: as JSON that reads back to the same result (the parts the renderer reads),
/// with the files its item wrote.
template <class Result>
struct PartialCodec {
  std::function<nlohmann::json(const Result&)> encode;
  /// Throws (InputError or nlohmann's exception) on a malformed document.
  std::function<Result(const nlohmann::json&)> decode;
  /// The relative paths unit `index`'s item wrote; none when not given.
  std::function<std::vector<std::string>(std::size_t index, const Result&)> files;
  /// How a merge names unit `index` in a message ("object 3").
  std::function<std::string(std::size_t index)> name;
};

/// A command's batch: its units, the work of one, and what its partial output records.
template <class Result>
struct BatchJob {
  std::string command;  ///< the partial output's "command"
  std::string label;    ///< the progress bar's ("predict")
  std::string unit;     ///< the units' name in the progress bar ("pushes")
  /// One name per unit: a shard's units are the sorted names' k-th with k mod N = I - 1 (shard_positions), or with
  /// `dealt_in_order` the k-th as given (units whose names do not sort in their order, such as numbered trials).
  std::vector<std::filesystem::path> units;
  bool dealt_in_order = false;
  std::string fingerprint;  ///< of the inputs; empty: inputs_fingerprint(units)
  nlohmann::json options;   ///< what tells two runs apart, and what the renderer reads
  int jobs = 1;
  /// Unit `index`'s result; the files it writes go into `files` at relative paths. An exception is the unit's
  /// failure (run_batch's, named by the unit's name).
  std::function<Result(std::size_t index, FileSink& files)> item;
  PartialCodec<Result> codec;
  std::function<ShardNote(const Result&)> note;  ///< optional
  /// What a shard says once its partial output is written.
  std::function<BatchRunOutcome(const ShardDone&)> shard_outcome;
  /// Replaces the progress bar: called with (done, total) after each unit, one call at a time.
  std::function<void(std::size_t, std::size_t)> progress;
};

namespace batch_runner_detail {

/// Copies each item's files from its part into `out`, decodes its result and hands it to the renderer, in order.
template <class Result>
BatchRunOutcome render_merged(const MergedParts& merged, StagedOutput& out, const PartialCodec<Result>& codec,
                              BatchRenderer<Result>& renderer) {
  for (const auto& m : merged.items) {
    if (m.failure) {
      BatchFailure failure = *m.failure;
      renderer.add_failure(m.index, std::move(failure));
      continue;
    }
    std::optional<Result> result;
    try {
      result.emplace(codec.decode(m.result()));
    } catch (const std::exception& e) {
      throw InputError(about(plain_text(m.part->name), codec.name(m.index) + " is not readable: " + e.what()));
    }
    for (const auto& file : m.files) write_text_atomically(out.path(file), m.part->read_file(file));
    renderer.add(m.index, std::move(*result));
  }
  return renderer.finish();
}

/// One unit of a partial run as the worker leaves it: its result's text and files, and its note.
struct EncodedItem {
  std::string text;
  std::vector<std::string> files;
  ShardNote note;
};

}  // namespace batch_runner_detail

/// The checked parts of a run of `command` (check_partial_outputs) written to `out` as the whole run writes them.
template <class Result>
BatchRunOutcome merge_batch(const MergedParts& merged, StagedOutput& out, const PartialCodec<Result>& codec,
                            const RendererFactory<Result>& render, RenderFor mode = RenderFor::shard_merge) {
  std::unique_ptr<BatchRenderer<Result>> renderer;
  try {
    renderer = render(out, merged.options, mode);
  } catch (const InputError& e) {
    const std::string first = merged.items.empty() ? std::string("the parts") : merged.items.front().part->name;
    throw InputError("merge: " + plain_text(first) + ": " + e.what());
  }
  return batch_runner_detail::render_merged(merged, out, codec, *renderer);
}

/// Runs `job` as `split` says and writes its outputs into `out_folder`: the whole run's (through the renderer), a
/// shard's partial output, or, under MPI, on rank 0 the whole run's from every rank's part. The output folder is
/// opened first, so that a bad one fails before any work.
template <class Result>
BatchRunOutcome run_batch_job(const BatchJob<Result>& job, const BatchSplit& split, const std::string& out_folder,
                              const RendererFactory<Result>& render) {
  namespace fs = std::filesystem;
  const bool mpi = split.over_ranks();
  const bool partial = split.partial();
  const ShardSpec shard = split.share();

  // Under MPI only rank 0 writes; if its folder is bad, it stops the whole job.
  std::optional<StagedOutput> out;
  open_output_at_root(split.mpi, out_folder, out);
  std::optional<ScratchFolder> scratch;  // under MPI each rank's files go there, and from there to rank 0
  std::optional<FileSink> sink;
  if (mpi) {
    scratch.emplace(job.command + "-rank" + std::to_string(split.mpi->rank()));
    sink.emplace(scratch->path());
  } else {
    sink.emplace(*out);
  }
  std::optional<BatchProgress> bar;
  std::size_t done = 0;
  const auto progress_of = [&](std::size_t total) -> BatchProgress* {
    if (job.progress) return nullptr;
    const std::string label = mpi       ? job.label + " (rank 0 of " + std::to_string(split.mpi->size()) + " ranks)"
                              : partial ? job.label + " (shard " + shard.text() + ")"
                                        : job.label;
    bar.emplace(label, job.unit, total, split.speaks());
    return &*bar;
  };
  const auto count_done = [&](std::size_t total) {
    if (job.progress && split.speaks()) job.progress(++done, total);
  };

  if (!partial) {
    const std::unique_ptr<BatchRenderer<Result>> renderer = render(*out, job.options, RenderFor::whole_run);
    BatchProgress* progress = progress_of(job.units.size());
    run_batch_in_order(
        job.units, [&](std::size_t index, const fs::path&) { return job.item(index, *sink); },
        [&](std::size_t index, BatchItem<Result>&& item) {
          count_done(job.units.size());
          if (item.result)
            renderer->add(index, std::move(*item.result));
          else
            renderer->add_failure(index, std::move(*item.failure));
        },
        job.jobs, progress);
    return renderer->finish();
  }

  std::vector<std::size_t> positions;
  if (job.dealt_in_order) {
    for (std::size_t k = 0; k < job.units.size(); ++k)
      if (k % static_cast<std::size_t>(shard.count) == static_cast<std::size_t>(shard.index - 1))
        positions.push_back(k);
  } else {
    positions = shard_positions(job.units, shard);
  }
  std::vector<fs::path> mine;
  for (std::size_t k : positions) mine.push_back(job.units[k]);
  // partial.json is written as the units finish (in their order), so that a shard holds no result once its unit is
  // done: into the staged output of a shard, or into the rank's scratch folder (sent to rank 0 at the end).
  const fs::path manifest_path = mpi ? scratch->path() / kPartialManifestName : out->path(kPartialManifestName);
  std::ofstream manifest_file(manifest_path, std::ios::binary | std::ios::trunc);
  if (!manifest_file) throw InputError(about(manifest_path.string(), "cannot be written"));
  const auto require_written = [&] {
    if (!manifest_file) throw InputError(about(manifest_path.string(), "cannot be written (is the disk full?)"));
  };
  PartialManifestWriter manifest(manifest_file, job.command, shard, job.units.size(),
                                 job.fingerprint.empty() ? inputs_fingerprint(job.units) : job.fingerprint,
                                 job.options);
  ShardDone tally;
  tally.shard = shard;
  tally.here = mine.size();
  tally.all = job.units.size();
  std::vector<std::string> files;  // every file of this process's units, for rank 0
  {
    BatchProgress* progress = progress_of(mine.size());
    run_batch_in_order(
        mine,
        [&](std::size_t k, const fs::path&) {
          // Encoded on the worker, so that a result is text as soon as it is known.
          Result result = job.item(positions[k], *sink);
          batch_runner_detail::EncodedItem encoded;
          encoded.text = partial_result_text(job.codec.encode(result));
          if (job.codec.files) encoded.files = job.codec.files(positions[k], result);
          if (job.note) encoded.note = job.note(result);
          return encoded;
        },
        [&](std::size_t k, BatchItem<batch_runner_detail::EncodedItem>&& done_k) {
          count_done(mine.size());
          PartialItem item;
          item.index = positions[k];
          if (done_k.result) {
            item.result_json = std::move(done_k.result->text);
            item.files = std::move(done_k.result->files);
            files.insert(files.end(), item.files.begin(), item.files.end());
            const ShardNote& note = done_k.result->note;
            tally.counted += note.counted ? 1 : 0;
            tally.failed += note.failed ? 1 : 0;
            tally.notes += note.text;
          } else {
            item.failure = done_k.failure;
            tally.failures.push_back(std::move(*done_k.failure));
          }
          manifest.add(std::move(item));
          require_written();
        },
        job.jobs, progress);
  }
  manifest.finish();
  manifest_file.close();
  require_written();

  if (mpi)
    return merge_at_root(*split.mpi, scratch->path(), files, [&](const MergedParts& merged) {
      return merge_batch(merged, *out, job.codec, render, RenderFor::mpi_merge);
    });
  out->commit();
  tally.destination = out->destination().string();
  return job.shard_outcome(tally);
}

}  // namespace pushpred
