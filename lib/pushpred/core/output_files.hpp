#pragma once
// Output that is never half-written: files are written into a hidden staging folder beside the destination and
// moved into place only when the whole job succeeded. If the job throws, the staging folder is removed and the
// destination is left as it was.
#include <filesystem>
#include <string>
#include <vector>

namespace pushpred {

/// Writes `text` to `path` through a temporary file in the same folder and a rename.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

/// A folder of outputs that appear together or not at all.
///
///   StagedOutput out("results/run1");
///   write_text_atomically(out.path("summary.json"), json);
///   out.commit();            // now results/run1/summary.json exists
class StagedOutput {
 public:
  explicit StagedOutput(std::filesystem::path destination);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  /// Where to write the file `name` (a relative path) while staging.
  std::filesystem::path path(const std::string& name) const;
  const std::filesystem::path& staging_folder() const { return staging_; }
  const std::filesystem::path& destination() const { return destination_; }

  /// Moves every staged file into the destination (creating it), replacing files of the same name.
  void commit();

 private:
  std::filesystem::path destination_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace pushpred
