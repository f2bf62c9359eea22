#pragma once
// Splitting a batch over processes and putting it back together: `--shard I/N` runs share I of N of a command's
// inputs (of `diagnose --per-object`'s objects, jobs/diagnosis_job.hpp) and writes a *partial output*;
// `pushpred merge` combines the partial outputs of shards 1..N into exactly what one run over every input writes; an
// MPI run (mpi_world.hpp) does both in one job, its ranks sending their partial outputs to rank 0.
//
// The split: the expanded inputs (expand_inputs, in the order given) are sorted by path, and the k-th of the sorted
// list (k = 0, 1, ...) goes to shard (k mod N) + 1. Each item keeps its position in the list as given, so that a
// merge puts results and failures back in the order one unsharded run has them. Every shard must be given the same
// inputs in the same order and the same options: a partial output records how many inputs there were, a
// fingerprint of their list and the command's options, and a merge refuses parts that differ in any of them.
//
// A partial output is a folder (written as a StagedOutput, so never half-written) holding `partial.json`:
//
//   {"pushpred_partial": 1, "pushpred_version": ..., "command": "predict", "shard": {"index": I, "count": N},
//    "inputs": {"count": M, "fingerprint": "..."}, "options": {...},
//    "items": [{"index": k, "result": {...}, "files": ["predictions/x.csv"]},
//              {"index": j, "failure": {"source": ..., "reason": ...}}]}
//
// and each item's files, at the relative paths the item lists (the files one run writes for that item).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

/// A whole-number field of a file pushpred wrote (a partial output, its results and options). nlohmann's get<> of a
/// fraction or of a number beyond the type into an integer is undefined behaviour, so anything but a whole number
/// that T holds is refused as an InputError that starts with `what`.
template <class T>
T json_whole_number(const nlohmann::json& v, const std::string& what) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(std::numeric_limits<T>::max())) return static_cast<T>(u);
  } else if (v.is_number_integer()) {
    const auto s = v.get<std::int64_t>();
    const bool fits =
        s < 0 ? std::numeric_limits<T>::is_signed && s >= static_cast<std::int64_t>(std::numeric_limits<T>::min())
              : static_cast<std::uint64_t>(s) <= static_cast<std::uint64_t>(std::numeric_limits<T>::max());
    if (fits) return static_cast<T>(s);
  }
  throw InputError(what + " is not a whole number in range: " + v.dump());
}

/// What a batch command did: the failures to list, how many inputs gave results, and what it prints on stdout.
/// `partial`: a shard's partial output was written (its failures are listed, but a merge decides the exit code).
/// `quiet`: an MPI rank other than 0 (rank 0 lists and prints everything). A command with its own exit rule sets
/// `exit_code` and puts what it says on stderr in `notes` (then `failures` and `used` are not read).
struct BatchRunOutcome {
  std::vector<BatchFailure> failures;
  std::size_t used = 0;
  std::string report;
  bool partial = false;
  bool quiet = false;
  std::optional<int> exit_code;
  std::string notes;
};

/// The manifest's name in a partial output folder.
inline constexpr const char* kPartialManifestName = "partial.json";

/// `--shard I/N`: share `index` (1-based) of `count`. 1/1 holds every input (and is still written as a partial
/// output: an array job of one task).
struct ShardSpec {
  int index = 1;
  int count = 1;
  std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
};

/// A double for a partial output: a JSON number that reads back to the same bits (nlohmann writes the shortest
/// digits that do), or "nan", "inf", "-inf" for the non-finite ones JSON has no number for.
nlohmann::json exact_number_json(double x);
/// The double exact_number_json wrote; throws InputError for anything else.
double exact_number(const nlohmann::json& j);

/// Parses "I/N" (1 <= I <= N, decimal integers, N at most 1,000,000); throws InputError naming --shard and the
/// problem otherwise ("0/2", "3/2", "x", "1/0", "1/2/3", "").
ShardSpec parse_shard_spec(const std::string& text);

/// The positions (in `inputs` as given) of the items of `shard`: the sorted list's k-th item for every k with
/// k mod count == index - 1, in the order given. Equal paths keep their order given.
std::vector<std::size_t> shard_positions(const std::vector<std::filesystem::path>& inputs, const ShardSpec& shard);

/// A fingerprint of the input list as given (FNV-1a, 64 bits, of the paths and their order), in hexadecimal.
std::string inputs_fingerprint(const std::vector<std::filesystem::path>& inputs);

/// Where the files of one item go while a batch runs: into a staged folder (a shard, or a whole run), or into a
/// plain folder (an MPI rank's scratch folder, whose files are sent to rank 0 one at a time at the end: held in
/// memory, a rank's share would grow with its pushes). Safe to call from several threads.
class FileSink {
 public:
  /// Into the staged folder `out` (which must outlive the sink).
  explicit FileSink(const StagedOutput& out) : out_(&out) {}
  /// Into the plain folder `folder` (which must exist); names() lists what was written.
  explicit FileSink(std::filesystem::path folder) : folder_(std::move(folder)) {}

  /// Writes `text` at the relative path `name` (write_text_atomically; subfolders made as needed).
  void write(const std::string& name, const std::string& text);
  /// The relative paths written so far, sorted.
  std::vector<std::string> names() const;
  /// Where the relative path `name` is, for a writer that makes its own files there (names() does not list them).
  std::filesystem::path path(const std::string& name) const;

 private:
  const StagedOutput* out_ = nullptr;
  std::filesystem::path folder_;
  std::set<std::string> names_;
  mutable std::mutex mutex_;
};

/// One item of a sharded batch: its position among all inputs, and its result (as the command encodes it, made
/// text by partial_result_text as soon as it is known: a shard of many pushes would otherwise hold every result as a
/// tree, several times its text) with the files it wrote, or its failure.
struct PartialItem {
  std::size_t index = 0;
  std::optional<std::string> result_json;
  std::vector<std::string> files;  ///< relative paths
  std::optional<BatchFailure> failure;
};

/// A result as PartialItem holds it: compact JSON text, invalid UTF-8 replaced.
std::string partial_result_text(const nlohmann::json& result);

/// The text of one shard's partial.json (see the top of this file): the document indented, each item on a line of
/// its own with its result's text as given. `options` is whatever the command needs to write its outputs and to
/// tell two runs apart. Each item's text is dropped from `items` once in the manifest.
std::string partial_manifest(const std::string& command, const ShardSpec& shard,
                             const std::vector<std::filesystem::path>& inputs, const nlohmann::json& options,
                             std::vector<PartialItem> items);

/// The same for a batch whose units are not its input files (`diagnose --per-object`: the objects): `count` units,
/// and a `fingerprint` of whatever tells its inputs apart.
std::string partial_manifest(const std::string& command, const ShardSpec& shard, std::size_t count,
                             const std::string& fingerprint, const nlohmann::json& options,
                             std::vector<PartialItem> items);

/// partial_manifest's text written one item at a time to `out` (which must outlive the writer): the head when made,
/// each item, in the order of the list, as it is added, the end at finish(). A shard of many pushes then holds no
/// result after its push is done (`predict --shard`, docs/performance.md).
class PartialManifestWriter {
 public:
  PartialManifestWriter(std::ostream& out, const std::string& command, const ShardSpec& shard, std::size_t count,
                        const std::string& fingerprint, const nlohmann::json& options);
  PartialManifestWriter(const PartialManifestWriter&) = delete;
  PartialManifestWriter& operator=(const PartialManifestWriter&) = delete;
  void add(PartialItem item);
  void finish();

 private:
  std::ostream& out_;
  std::string tail_;  ///< what follows the items
  bool first_ = true;
};

/// Writes `manifest` (partial_manifest's text) as out's partial.json and commits `out` (the items' files are in it
/// already).
void write_partial_output(StagedOutput& out, const std::string& manifest);

/// A partial output as a merge reads it: its name (the folder, or "rank R" of an MPI run), its partial.json, and
/// how to read one of its files by relative path (throws InputError naming the part when it is missing).
/// The items' results are not held in the manifest (a parsed result takes several times its text, and a merge of many
/// pushes would hold every one; issue 12): each item's "result" is replaced by its position k, and result_text(k)
/// gives the result's JSON text, read again from partial.json when asked for (read_partial_output), or from memory
/// (partial_output). Make one with partial_output() or read_partial_output().
struct PartialOutput {
  std::string name;
  nlohmann::json manifest;
  std::function<std::string(const std::string&)> read_file;
  std::function<std::string(std::size_t)> result_text;
  std::size_t results = 0;  ///< how many items hold a result
};

/// A partial output from a manifest in memory (partial_manifest's), its results set aside as compact text.
PartialOutput partial_output(std::string name, nlohmann::json manifest,
                             std::function<std::string(const std::string&)> read_file);

/// Reads the partial output in `folder`; throws InputError naming the folder when it is not one (no partial.json,
/// not JSON, not pushpred's partial format). partial.json is parsed as a stream, and of each item's result only where
/// it lies in the file is kept (its text is read again when asked for), so a merge holds a few bytes per item. Its
/// files are read from disk only when asked for (read_file), one at a time. `name` is the part's name in messages;
/// the folder's path when empty. The folder must stay as it is until the merge is written.
PartialOutput read_partial_output(const std::filesystem::path& folder, const std::string& name = "");

/// One file of a partial output as a byte string, to send to another process (an MPI rank sends its partial.json
/// and then each of its files so, one at a time): `data` as the bytes it is (a plot is binary) at the relative path
/// `name`, behind a line giving the two lengths:
///
///   pushpred-bundle 1\n
///   NAME_BYTES DATA_BYTES\nNAMEDATA
std::string file_bundle(const std::string& name, const std::string& data);
/// file_bundle of the file at `path`, read straight into the bundle (a large partial.json is not held twice); throws
/// InputError naming the file when it cannot be read.
std::string file_bundle_of(const std::string& name, const std::filesystem::path& path);
/// Writes the file of `bundle` (file_bundle's, from another process) under `folder` at its relative path, making
/// the folders it needs, and returns that path. `name` names the sender in messages ("rank 1"); throws InputError
/// when the bundle is not one (its first line, its length line, a length beyond its end, bytes after its file) or
/// its file's name is not a path inside the output (nothing is then written).
std::string unpack_file_bundle(const std::string& name, const std::string& bundle, const std::filesystem::path& folder);

/// The items of every part, checked to be one whole batch, in input order: the same command, version, inputs and
/// options in every part; shards 1..N each given once; every input's item present exactly once. Each item comes with
/// the part that holds it (MergedParts owns the parts). Throws InputError naming the part and the problem otherwise.
struct MergedItem {
  std::size_t index = 0;                 ///< position among all inputs
  std::optional<std::size_t> result_at;  ///< the item's result: its position among its part's (result_text)
  std::vector<std::string> files;        ///< relative paths in its part
  std::optional<BatchFailure> failure;
  const PartialOutput* part = nullptr;
  /// The item's result, read from its part and parsed (one item at a time, so a merge never holds every result);
  /// throws InputError when the item has no result or its part cannot give it, nlohmann's exception when its text is
  /// not JSON.
  nlohmann::json result() const;
};
struct MergedParts {
  std::string command;
  nlohmann::json options;
  std::vector<PartialOutput> parts;  ///< as given; the items point into it
  std::vector<MergedItem> items;     ///< one per input, in the order given
};
MergedParts check_partial_outputs(std::vector<PartialOutput> parts);

}  // namespace pushpred
