#pragma once
// Running one job over many input files: a bad file does not stop the batch; each failure is kept with its
// reason so that the app can list them all at the end and exit non-zero.
#include <filesystem>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"

namespace pushpred {

struct BatchFailure {
  std::string source;
  std::string reason;  ///< one line of plain text (see plain_text)
  bool skipped = false;  ///< the input is valid but the job cannot use it (UnsuitableInput): not a failure
};

template <class Result>
struct Batch {
  std::vector<Result> results;
  std::vector<BatchFailure> failures;
};

/// Inputs as a user gives them: files stay as they are, folders expand into the recordings below them. Never
/// throws: an input that cannot be expanded (a missing file, a symbolic-link loop, an unreadable folder, a folder
/// holding no recording) stays in the list as it is, so that reading it fails by name in the batch. A file reached
/// twice (listed twice, or listed and inside a listed folder, or through a link) is kept once, where it first
/// appears: a push counted twice would weigh twice in every aggregate. `repeated`, when given, receives each
/// dropped repeat as it was reached (for a note to the user: repeated_inputs_note).
inline std::vector<std::filesystem::path> expand_inputs(const std::vector<std::string>& inputs,
                                                        std::vector<std::filesystem::path>* repeated = nullptr) {
  std::vector<std::filesystem::path> out;
  std::set<std::string> seen;
  const auto add = [&](std::filesystem::path p) {
    if (seen.insert(file_identity(p)).second)
      out.push_back(std::move(p));
    else if (repeated)
      repeated->push_back(std::move(p));
  };
  for (const auto& in : inputs) {
    std::error_code ec;
    if (!std::filesystem::is_directory(in, ec)) {
      add(in);
      continue;
    }
    std::vector<std::filesystem::path> found;
    try {
      found = list_recordings(in);
    } catch (const std::exception&) {
      // left in the list: reading the folder says why
    }
    if (found.empty()) add(in);
    for (auto& p : found) add(std::move(p));
  }
  return out;
}

/// One line telling the user that expand_inputs dropped repeats ("note: 2 inputs reach a push already given
/// (first: 'abs/x.h5'); each push is studied once"), or "" when there were none: a user who listed a folder and a
/// file in it would otherwise count fewer pushes in the output than inputs without being told why.
inline std::string repeated_inputs_note(const std::vector<std::string>& inputs) {
  std::vector<std::filesystem::path> repeated;
  expand_inputs(inputs, &repeated);
  if (repeated.empty()) return "";
  const std::size_t n = repeated.size();
  return "note: " + std::to_string(n) + (n == 1 ? " input reaches" : " inputs reach") +
         " a push already given (first: '" + plain_text(repeated.front().string()) +
         "'); each push is studied once\n";
}

/// A name per input for its own output file, unique within the batch: the file's stem, and where two inputs from
/// different folders share a stem, the later ones "STEM-2", "STEM-3", ... in input order (so that one push's output
/// does not overwrite another's, and the names do not depend on which thread finished first). distinct_names takes
/// the stems themselves (a batch that keeps a name per input rather than its path).
inline std::vector<std::string> distinct_names(const std::vector<std::string>& stems) {
  std::vector<std::string> names;
  std::set<std::string> taken(stems.begin(), stems.end());
  std::set<std::string> used;
  for (const auto& stem : stems) {
    std::string name = stem;
    if (used.count(name)) {
      for (int k = 2;; ++k) {
        const std::string candidate = name + "-" + std::to_string(k);
        if (!taken.count(candidate) && !used.count(candidate)) {
          name = candidate;
          break;
        }
      }
    }
    used.insert(name);
    names.push_back(std::move(name));
  }
  return names;
}

inline std::vector<std::string> distinct_stems(const std::vector<std::filesystem::path>& inputs) {
  std::vector<std::string> stems;
  stems.reserve(inputs.size());
  for (const auto& p : inputs) stems.push_back(p.stem().string());
  return distinct_names(stems);
}

/// Calls `job(path)` for every input; any exception becomes a BatchFailure naming the file, with a reason in
/// plain text (no raw bytes from a corrupt file), and the batch goes on.
template <class Job>
auto run_batch(const std::vector<std::filesystem::path>& inputs, Job&& job) -> Batch<decltype(job(inputs.front()))> {
  Batch<decltype(job(inputs.front()))> batch;
  for (const auto& path : inputs) {
    std::string reason;
    bool skipped = false;
    try {
      batch.results.push_back(job(path));
      continue;
    } catch (const UnsuitableInput& e) {
      reason = e.what();
      skipped = true;
    } catch (const std::exception& e) {
      reason = e.what();
    } catch (...) {
      reason = "unexpected error";
    }
    const std::string prefix = path.string() + ": ";
    if (reason.rfind(prefix, 0) == 0) reason = reason.substr(prefix.size());
    batch.failures.push_back({plain_text(path.string()), plain_text(reason), skipped});
  }
  return batch;
}

}  // namespace pushpred
