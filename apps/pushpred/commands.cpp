#include "commands.hpp"

#include <algorithm>
#include <iostream>

#include "pushpred/core/batch.hpp"
#include "pushpred/runtime/mpi_world.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/reading/shape_table.hpp"

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

namespace {

/// The number of single-character insertions, deletions and substitutions that turn `a` into `b`.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::optional<int> refuse_unknown_command(const CLI::App& app, const std::string& word) {
  if (word.empty() || word[0] == '-') return std::nullopt;
  std::string nearest, names;
  std::size_t best = std::string::npos;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    const std::string& name = sub->get_name();
    if (name == word) return std::nullopt;
    names += (names.empty() ? "" : ", ") + name;
    const std::size_t d = edit_distance(word, name);
    if (d < best) best = d, nearest = name;
  }
  std::cerr << "pushpred: unknown command '" << plain_text(word) << "'";
  // Close enough to be a typo: at most a third of the word's letters changed (and at least two allowed).
  if (best <= std::max<std::size_t>(2, word.size() / 3))
    std::cerr << "; did you mean '" << nearest << "'?\n";
  else
    std::cerr << "; the commands are: " << names << " (pushpred --help)\n";
  return kExitNothingDone;
}

namespace {
const MpiSession* the_mpi_session = nullptr;
}  // namespace

const MpiSession* mpi_session() { return the_mpi_session; }

int run_selected(CLI::App& app, const MpiSession* mpi) {
  the_mpi_session = mpi;
  for (const CLI::App* sub : app.get_subcommands()) {
    const std::string& name = sub->get_name();
    // Several processes started by mpirun would each do the whole job and write the same output.
    // diagnose refuses mpirun itself without --per-object.
    if (name != "predict" && name != "validate-diagnosis" && name != "diagnose" && mpi_launch_size() > 1)
      throw InputError("`" + name + "` does not run under mpirun (only `predict`, `validate-diagnosis` and `diagnose "
                       "--per-object` split their work over MPI ranks); run it as one process");
    // Inputs that reach a push twice are studied once (expand_inputs): said once per job, on stderr.
    // A user's own objects join the known shapes before any input is read (flags.hpp, add_shapes).
    const CLI::Option* shapes = sub->get_option_no_throw("--shapes");
    if (shapes && shapes->count() > 0) ShapeTable::use_own_shapes(ShapeTable::from_file(shapes->as<std::string>()));
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
  std::size_t failed = 0;
  for (const auto& f : outcome.failures) {
    std::cerr << (f.skipped ? "SKIPPED " : "FAILED ") << plain_text(f.source) << ": " << plain_text(f.reason) << "\n";
    failed += f.skipped ? 0 : 1;
  }
  if (failed == 0) return 0;
  std::cerr << failed << " of " << outcome.failures.size() + outcome.used << " inputs of this shard failed\n";
  return kExitSomeFailed;
}

int report_failures(const std::vector<BatchFailure>& failures, std::size_t used, const std::string& label) {
  std::size_t failed = 0, skipped = 0;
  for (const auto& f : failures) {
    std::cerr << (f.skipped ? std::string("SKIPPED") : label) << " " << plain_text(f.source) << ": "
              << plain_text(f.reason) << "\n";
    (f.skipped ? skipped : failed) += 1;
  }
  if (failures.empty()) return 0;
  const std::size_t inputs = failures.size() + used;
  if (skipped > 0)
    std::cerr << skipped << " of " << inputs << " inputs skipped (valid, but not usable by this command)\n";
  if (failed > 0) std::cerr << failed << " of " << inputs << " inputs failed\n";
  if (used == 0) {
    std::cerr << "nothing written\n";
    return kExitNothingDone;
  }
  return failed > 0 ? kExitSomeFailed : 0;
}

std::string json_text(const nlohmann::json& doc) { return json_file_text(doc); }

}  // namespace pushpred::app
