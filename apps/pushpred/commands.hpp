#pragma once
// How subcommands join the `pushpred` executable: each command file defines a function that adds its
// CLI11 subcommand and, when that subcommand is chosen, sets the runner; a static `CommandRegistration`
// puts it on the list. Adding a command touches no other file.
#include <CLI/CLI.hpp>
#include <functional>
#include <vector>

namespace pushpred::app {

using Runner = std::function<int()>;
using AddCommand = std::function<void(CLI::App&, Runner&)>;

std::vector<std::function<void(CLI::App&)>> all_commands();
int run_selected(CLI::App& app);

struct CommandRegistration {
  explicit CommandRegistration(AddCommand add);
};

}  // namespace pushpred::app
