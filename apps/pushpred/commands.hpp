#pragma once
// How subcommands join the `pushpred` executable: each command file defines a function that adds its
// CLI11 subcommand and, when that subcommand is chosen, sets the runner; a static `CommandRegistration`
// puts it on the list. Adding a command touches no other file.
#include <CLI/CLI.hpp>
#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/core/shard.hpp"

namespace pushpred::app {

using Runner = std::function<int()>;
using AddCommand = std::function<void(CLI::App&, Runner&)>;

std::vector<std::function<void(CLI::App&)>> all_commands();
int run_selected(CLI::App& app);

struct CommandRegistration {
  explicit CommandRegistration(AddCommand add);
};

// Exit codes every subcommand keeps (README): 0 every input used; 1 some inputs failed, the others' results written
// and the failures listed; 2 nothing done: a bad argument or output folder, or no input usable, nothing written.
inline constexpr int kExitSomeFailed = 1;
inline constexpr int kExitNothingDone = 2;

/// Lists each failure as "FAILED source: reason" on stderr, then "N of M inputs failed"; returns the exit code for
/// a batch of `inputs` items with `used` of them giving results.
int report_failures(const std::vector<BatchFailure>& failures, std::size_t used, const std::string& label = "FAILED");

/// Adds `--shard I/N` to a subcommand that cannot split its inputs yet (compare, inspect, fit-pid): given, it is
/// refused with an error naming the subcommand, exit 2, before anything is read or written.
void add_shard_refusal(CLI::App& sub);

/// The help text of --shard where it is supported.
inline constexpr const char* kShardHelp =
    "Only share I of N of the inputs (the sorted list's k-th input goes to share k mod N + 1); writes a partial "
    "output folder that `pushpred merge` combines with the other shares' into what one run writes";

/// Prints what a batch run says (its report on stdout; its notes, or its failures, on stderr) and gives its exit
/// code: its own when it sets one, otherwise report_failures's; a shard's partial output exits 1 when some of its
/// inputs failed, 0 otherwise (the merge lists them again and decides); an MPI rank other than 0 prints nothing.
int finish_outcome(const BatchRunOutcome& outcome);

/// Runs `job` on one input file; any failure becomes an InputError that names the file (once) and says why in plain
/// text, for the commands that read a single file (a solver failure on a file is a problem of that file).
template <class Job>
auto on_file(const std::string& file, Job&& job) -> decltype(job()) {
  try {
    return job();
  } catch (const std::exception& e) {
    std::string reason = e.what();
    if (reason.rfind(file + ": ", 0) == 0) reason = reason.substr(file.size() + 2);
    throw InputError(about(plain_text(file), plain_text(reason)));
  }
}

/// JSON text for an output file: invalid UTF-8 (from a file name) replaced rather than aborting the run.
std::string json_text(const nlohmann::json& doc);

}  // namespace pushpred::app
