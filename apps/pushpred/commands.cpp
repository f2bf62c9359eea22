#include "commands.hpp"

#include <iostream>

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

int report_failures(const std::vector<BatchFailure>& failures, std::size_t used, const std::string& label) {
  for (const auto& f : failures) std::cerr << label << " " << plain_text(f.source) << ": " << plain_text(f.reason) << "\n";
  if (failures.empty()) return 0;
  std::cerr << failures.size() << " of " << failures.size() + used << " inputs failed"
            << (used == 0 ? "; nothing written" : "") << "\n";
  return used == 0 ? kExitNothingDone : kExitSomeFailed;
}

std::string json_text(const nlohmann::json& doc) {
  return doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace pushpred::app
