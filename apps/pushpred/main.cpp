// pushpred: the command-line front end. Each subcommand lives in its own file and only parses arguments and
// calls the library; see `pushpred --help`.
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/core/version.hpp"
#include "pushpred/runtime/mpi_world.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace {

/// Prints an error that ended the run and returns its exit code. Under mpirun with several ranks, the other ranks
/// may be waiting for this one's results, so the error names the rank and stops the whole job (exit 2); the scratch
/// folders of the ranks stopped so are removed by their signal handlers, this rank's by the unwinding that led here.
int report_error(const std::exception& e, int code, const pushpred::MpiSession* mpi) {
  const int ranks = pushpred::mpi_launch_size();
  if (ranks > 1) {
    std::cerr << "pushpred: error on rank " << pushpred::mpi_launch_rank() << " of " << ranks << ": "
              << pushpred::plain_text(e.what()) << "; stopping every rank\n";
    if (mpi) mpi->abort(pushpred::app::kExitNothingDone);
    std::exit(pushpred::app::kExitNothingDone);  // MPI could not be started: nothing waits for this process
  }
  std::cerr << "pushpred: error: " << pushpred::plain_text(e.what()) << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pushpred: predict where a pushed object goes, and explain why predictions miss"};
  app.set_version_flag("--version", std::string("pushpred ") + pushpred::kVersion);
  app.require_subcommand(1);
  // Every option's default in --help (subcommands copy these defaults when they are added).
  app.option_defaults()->always_capture_default();
  for (const auto& add : pushpred::app::all_commands()) add(app);
  // CLI11 takes a mistyped command for a stray argument ("A subcommand is required"): name it and the nearest command.
  if (argc > 1)
    if (const auto code = pushpred::app::refuse_unknown_command(app, argv[1])) return *code;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print and succeed; any other parse error is a bad argument: CLI11 prints it, and the
    // exit code is the README's for "nothing was done" (CLI11's own codes, 104 to 114, mean nothing to a script).
    const int code = app.exit(e);
    return code == 0 ? 0 : pushpred::app::kExitNothingDone;
  }
  // A run stopped by a signal removes its half-written output (runtime/output_files.hpp).
  pushpred::install_output_cleanup_on_signals();
  // Started by an MPI launcher: MPI from here to the end of the run (the session finalises it), for the commands
  // that split their work over the ranks; the others refuse to run as one of several processes.
  std::optional<pushpred::MpiSession> mpi;
  try {
    if (pushpred::mpi_launched()) mpi.emplace();
    return pushpred::app::run_selected(app, mpi ? &*mpi : nullptr);
  } catch (const pushpred::InputError& e) {
    return report_error(e, pushpred::app::kExitNothingDone, mpi ? &*mpi : nullptr);
  } catch (const std::exception& e) {
    return report_error(e, 1, mpi ? &*mpi : nullptr);
  }
}
