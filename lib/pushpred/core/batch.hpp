#pragma once
// Running one job over many input files: a bad file does not stop the batch; each failure is kept with its
// reason so that the app can list them all at the end and exit non-zero.
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"

namespace pushpred {

struct BatchFailure {
  std::string source;
  std::string reason;  ///< one line of plain text (see plain_text)
};

template <class Result>
struct Batch {
  std::vector<Result> results;
  std::vector<BatchFailure> failures;
};

/// Inputs as a user gives them: files stay as they are, folders expand into the recordings below them. Never
/// throws: an input that cannot be expanded (a missing file, a symbolic-link loop, an unreadable folder, a folder
/// holding no recording) stays in the list as it is, so that reading it fails by name in the batch.
inline std::vector<std::filesystem::path> expand_inputs(const std::vector<std::string>& inputs) {
  std::vector<std::filesystem::path> out;
  for (const auto& in : inputs) {
    std::error_code ec;
    if (!std::filesystem::is_directory(in, ec)) {
      out.emplace_back(in);
      continue;
    }
    std::vector<std::filesystem::path> found;
    try {
      found = list_recordings(in);
    } catch (const std::exception&) {
      // left in the list: reading the folder says why
    }
    if (found.empty()) out.emplace_back(in);
    for (auto& p : found) out.push_back(std::move(p));
  }
  return out;
}

/// Calls `job(path)` for every input; any exception becomes a BatchFailure naming the file, with a reason in
/// plain text (no raw bytes from a corrupt file), and the batch goes on.
template <class Job>
auto run_batch(const std::vector<std::filesystem::path>& inputs, Job&& job) -> Batch<decltype(job(inputs.front()))> {
  Batch<decltype(job(inputs.front()))> batch;
  for (const auto& path : inputs) {
    std::string reason;
    try {
      batch.results.push_back(job(path));
      continue;
    } catch (const std::exception& e) {
      reason = e.what();
    } catch (...) {
      reason = "unexpected error";
    }
    const std::string prefix = path.string() + ": ";
    if (reason.rfind(prefix, 0) == 0) reason = reason.substr(prefix.size());
    batch.failures.push_back({plain_text(path.string()), plain_text(reason)});
  }
  return batch;
}

}  // namespace pushpred
