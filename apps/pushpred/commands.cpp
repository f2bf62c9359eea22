#include "commands.hpp"

#include <iostream>

#include "pushpred/core/batch.hpp"
#include "pushpred/core/mpi_world.hpp"
#include "pushpred/core/output_files.hpp"

namespace pushpred::app {
namespace {

std::vector<AddCommand>& registry() {
  static std::vector<AddCommand> r;
  return r;
}

Runner& selected_runner() {
  static Runner r;
  return r;
}

}  // namespace

CommandRegistration::CommandRegistration(AddCommand add) { registry().push_back(std::move(add)); }

std::vector<std::function<void(CLI::App&)>> all_commands() {
  std::vector<std::function<void(CLI::App&)>> out;
  for (const auto& add : registry()) out.push_back([add](CLI::App& app) { add(app, selected_runner()); });
  return out;
}

static std::vector<std::string>& shard_refusals() {
  static std::vector<std::string> names;
  return names;
}

void add_shard_refusal(CLI::App& sub) {
  shard_refusals().push_back(sub.get_name());
  static std::string ignored;  // never read: run_selected refuses the flag
  sub.add_option("--shard", ignored,
                 "Not supported by `" + sub.get_name() +
                     "` yet (only by predict, validate-diagnosis and diagnose --per-object): refused");
}

int run_selected(CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands()) {
    const std::string& name = sub->get_name();
    for (const auto& refusing : shard_refusals())
      if (refusing == name && sub->count("--shard") > 0)
        throw InputError("--shard: `" + name + "` cannot split its inputs into shards yet (only `predict`, "
                         "`validate-diagnosis` and `diagnose --per-object` can); run it on every input, or split the "
                         "inputs yourself");
    // Several processes started by mpirun would each do the whole job and write the same output.
    // diagnose refuses mpirun itself without --per-object.
    if (name != "predict" && name != "validate-diagnosis" && name != "diagnose" && mpi_launch_size() > 1)
      throw InputError("`" + name + "` does not run under mpirun (only `predict`, `validate-diagnosis` and `diagnose "
                       "--per-object` split their work over MPI ranks); run it as one process");
    // Inputs that reach a push twice are studied once (expand_inputs): said once per job, on stderr.
    const CLI::Option* files = sub->get_option_no_throw("files");
    if (files && files->count() > 0 && mpi_launch_rank() == 0)
      std::cerr << repeated_inputs_note(files->as<std::vector<std::string>>());
  }
  return selected_runner() ? selected_runner()() : 0;
}

int finish_outcome(const BatchRunOutcome& outcome) {
  if (outcome.quiet) return 0;  // an MPI rank other than 0: rank 0 reports
  std::cout << outcome.report;
  if (outcome.exit_code) {
    std::cerr << outcome.notes;
    return *outcome.exit_code;
  }
  if (!outcome.partial) return report_failures(outcome.failures, outcome.used);
  for (const auto& f : outcome.failures)
    std::cerr << "FAILED " << plain_text(f.source) << ": " << plain_text(f.reason) << "\n";
  if (outcome.failures.empty()) return 0;
  std::cerr << outcome.failures.size() << " of " << outcome.failures.size() + outcome.used
            << " inputs of this shard failed\n";
  return kExitSomeFailed;
}

int report_failures(const std::vector<BatchFailure>& failures, std::size_t used, const std::string& label) {
  for (const auto& f : failures) std::cerr << label << " " << plain_text(f.source) << ": " << plain_text(f.reason) << "\n";
  if (failures.empty()) return 0;
  std::cerr << failures.size() << " of " << failures.size() + used << " inputs failed"
            << (used == 0 ? "; nothing written" : "") << "\n";
  return used == 0 ? kExitNothingDone : kExitSomeFailed;
}

std::string json_text(const nlohmann::json& doc) { return json_file_text(doc); }

}  // namespace pushpred::app
