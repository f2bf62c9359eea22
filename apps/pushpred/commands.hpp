#pragma once
// How subcommands join the `pushpred` executable: each command file defines a function that adds its
// CLI11 subcommand and, when that subcommand is chosen, sets the runner; a static `CommandRegistration`
// puts it on the list. Adding a command touches no other file.
#include <CLI/CLI.hpp>
#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/runtime/shard.hpp"

namespace pushpred {
class MpiSession;
}

namespace pushpred::app {

using Runner = std::function<int()>;
using AddCommand = std::function<void(CLI::App&, Runner&)>;

std::vector<std::function<void(CLI::App&)>> all_commands();
/// Runs the selected command. `mpi`: the program's MPI session (main makes it when a launcher started this process
/// as one of several), handed to the commands that split their work over ranks (mpi_session()).
int run_selected(CLI::App& app, const MpiSession* mpi);
/// The session run_selected was given (nullptr: a plain run).
const MpiSession* mpi_session();

struct CommandRegistration {
  explicit CommandRegistration(AddCommand add);
};

// Exit codes every subcommand keeps (docs/exit-codes.md): 0 every input used or skipped (a valid input the command
// cannot use by design, such as a frozen force sensor, is listed as SKIPPED); 1 some inputs failed, the others'
// results written and the failures listed; 2 nothing done: a bad argument or output folder, or no input usable,
// nothing written.
inline constexpr int kExitSomeFailed = 1;
inline constexpr int kExitNothingDone = 2;

/// When `word` (the first argument) is neither an option nor a command, says so on stderr with the nearest command
/// ("unknown command 'predcit'; did you mean 'predict'?") and gives exit code 2; otherwise nothing.
std::optional<int> refuse_unknown_command(const CLI::App& app, const std::string& word);

/// Lists each failure as "FAILED source: reason" (a skip as "SKIPPED source: reason") on stderr, then how many of the
/// inputs failed and were skipped; returns the exit code for a batch with `used` inputs giving results: 0 when none
/// failed (skips are not failures), 1 when some did, 2 when no input gave a result.
int report_failures(const std::vector<BatchFailure>& failures, std::size_t used, const std::string& label = "FAILED");

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
