#pragma once
// Running one job over many input files: a bad file does not stop the batch; each failure is kept with its
// reason so that the app can list them all at the end and exit non-zero.
#include <filesystem>
#include <string>
#include <vector>

#include "pushpred/core/data_folder.hpp"

namespace pushpred {

struct BatchFailure {
  std::string source;
  std::string reason;
};

template <class Result>
struct Batch {
  std::vector<Result> results;
  std::vector<BatchFailure> failures;
};

/// Inputs as a user gives them: files stay as they are (a missing one fails later, by name), folders expand
/// into the recordings below them.
inline std::vector<std::filesystem::path> expand_inputs(const std::vector<std::string>& inputs) {
  std::vector<std::filesystem::path> out;
  for (const auto& in : inputs) {
    if (std::filesystem::is_directory(in)) {
      for (auto& p : list_recordings(in)) out.push_back(p);
    } else {
      out.emplace_back(in);
    }
  }
  return out;
}

/// Calls `job(path)` for every input; any std::exception becomes a BatchFailure naming the file.
template <class Job>
auto run_batch(const std::vector<std::filesystem::path>& inputs, Job&& job) -> Batch<decltype(job(inputs.front()))> {
  Batch<decltype(job(inputs.front()))> batch;
  for (const auto& path : inputs) {
    try {
      batch.results.push_back(job(path));
    } catch (const std::exception& e) {
      std::string reason = e.what();
      const std::string prefix = path.string() + ": ";
      if (reason.rfind(prefix, 0) == 0) reason = reason.substr(prefix.size());
      batch.failures.push_back({path.string(), reason});
    }
  }
  return batch;
}

}  // namespace pushpred
