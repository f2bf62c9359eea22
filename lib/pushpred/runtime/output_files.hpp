#pragma once
// Output that is never half-written: files are written into a hidden staging folder beside the destination,
// `.NAME.staging-PID-N`, and the whole folder is renamed into place only when the job succeeded; an existing
// destination is replaced as a whole (atomically where the file system allows), so no file of an earlier run is
// left beside the new ones. If the job throws, the staging folder is removed and the destination is left as it
// was. A run stopped by SIGINT, SIGTERM or SIGHUP removes its staging folders (install_output_cleanup_on_signals);
// a run killed outright leaves one, which the next run into the same destination removes.
//
// An existing destination is replaced only when it is empty, or was written by pushpred and holds nothing else: its
// marker file `.pushpred-output` lists every file and folder the run wrote, and anything in it the list does not
// name (a recording a user copied there, a note) makes the run refuse the folder, touching nothing. `--out .` or
// `--out ~` can never wipe a user's folder. A folder owned by another user is refused too: its files could not all
// be removed, and the old output would be left behind in a hidden folder. Names made from a destination's or an
// input's name stay within the file system's limit (bounded_file_name).
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace pushpred {

/// Writes `text` to `path` through a temporary file in the same folder and a rename. The folder must exist (throws
/// InputError otherwise); it is never created, so that a write cannot bring back a folder a stop signal removed.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);
/// write_text_atomically for a file written piece by piece: `write` streams the contents, so that a large file is
/// never held whole in memory.
void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// The bytes of the file at `path`; throws InputError naming it when it cannot be read.
std::string read_file_bytes(const std::filesystem::path& path);

/// JSON text for an output file: indented by 2, ending in a newline, invalid UTF-8 (from a file name) replaced
/// rather than aborting the run.
std::string json_file_text(const nlohmann::json& doc);

/// json_file_text of `doc` around the value of its top-level `key`, for a caller that writes that value itself (a
/// long list, streamed one entry at a time): the text up to and including `"key": ` and the text after the value.
/// Throws std::logic_error when `doc` is not an object.
struct JsonTextAround {
  std::string before, after;
};
JsonTextAround json_file_text_around(nlohmann::json doc, const std::string& key);

/// The name of the marker file every StagedOutput folder holds.
inline constexpr const char* kOutputMarker = ".pushpred-output";

/// `name` when it has at most `max_bytes` bytes; otherwise its first bytes and a hash of the whole name
/// ("PREFIX-0123456789abcdef"), `max_bytes` long, the same for the same name on every run. File names derived from
/// inputs and destinations go through it so that a name near the file system's 255-byte limit, with a prefix or
/// suffix added, stays below it.
std::string bounded_file_name(const std::string& name, std::size_t max_bytes = 200);

/// A folder of outputs that appear together or not at all.
///
///   StagedOutput out("results/run1");
///   write_text_atomically(out.path("summary.json"), json);
///   out.commit();            // now results/run1 holds summary.json and nothing else
class StagedOutput {
 public:
  /// Checks the destination (throws InputError when it is a file, or a folder pushpred did not write) and creates
  /// the staging folder, after removing stale staging folders of dead pushpred processes for this destination.
  explicit StagedOutput(std::filesystem::path destination);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  /// Where to write the file `name` (a relative path) while staging.
  std::filesystem::path path(const std::string& name) const;
  const std::filesystem::path& staging_folder() const { return staging_; }
  const std::filesystem::path& destination() const { return destination_; }

  /// Renames the staging folder into place, replacing the destination's earlier contents as a whole.
  void commit();

 private:
  std::filesystem::path destination_;  ///< as given, for messages
  std::filesystem::path target_;       ///< absolute, normalised
  std::filesystem::path staging_;
  int slot_ = -1;  ///< in the signal clean-up registry
  bool committed_ = false;
};

/// A folder of this process's own under the system's temporary folder (TMPDIR, else /tmp), `pushpred-NAME-PID`,
/// for files a run needs on the way but never outputs: an MPI rank's diagnosis plots before they are sent, the ranks'
/// partial outputs on rank 0 while it merges them (issue 12). Never inside an output folder, so nothing of it can be
/// committed. Removed with everything in it when the object goes (also when a scope is left by an exception), and by
/// a stop signal as staging folders are; a process killed outright leaves it.
class ScratchFolder {
 public:
  /// Creates the folder (after removing what an earlier process with the same id left there); throws InputError
  /// when it cannot.
  explicit ScratchFolder(const std::string& name);
  ~ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int slot_ = -1;  ///< in the signal clean-up registry
};

/// Installs handlers for SIGINT, SIGTERM and SIGHUP (unless ignored) that remove the staging folders of every
/// live StagedOutput (and every live ScratchFolder) and then let the signal end the process as it would have. For
/// programs, not libraries: call once at the start of main.
void install_output_cleanup_on_signals();

}  // namespace pushpred
