#include "commands.hpp"

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

int run_selected(CLI::App&) { return selected_runner() ? selected_runner()() : 0; }

}  // namespace pushpred::app
