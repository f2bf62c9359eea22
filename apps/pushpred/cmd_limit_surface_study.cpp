// `pushpred limit-surface-study PUSHES... --out DIR`: each recorded push's limit surface ratio c identified from its
// force sensor and motion (identify_torque_ratio), and how well the plan predicts it leaving one push out per object
// (forecast/limit_surface_identification.hpp): DIR/pushes.csv (per push) and DIR/tables.md (per object), printed too.
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/forecast/limit_surface_identification.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred::app {
namespace {

struct Args {
  std::vector<std::string> files;
  std::string out, data;
  int jobs = default_jobs();
};

int run_it(const Args& a) {
  StagedOutput out(a.out);
  const std::filesystem::path data = data_folder_if_any(a.data.empty() ? std::nullopt : std::optional(a.data));
  const ForecastInputs in = load_forecast_inputs(a.files, data, a.jobs, nullptr, true);
  std::vector<TorqueRatioIdentification> identified;
  for (const auto& c : in.cases) identified.push_back(c.identified_torque_ratio);
  const std::vector<LimitSurfaceStudyPush> pushes = run_limit_surface_study(in.cases, in.fits, identified);
  if (pushes.empty()) {
    const int code = report_failures(in.failures, 0);
    std::cerr << "pushpred: error: no push could be studied; nothing written\n";
    return code == 0 ? kExitNothingDone : code;
  }
  const std::string tables = limit_surface_study_tables(pushes);
  write_text_atomically(out.path("pushes.csv"), limit_surface_study_csv(pushes));
  write_text_atomically(out.path("tables.md"), tables);
  out.commit();
  std::cout << tables << "wrote " << a.out << "/pushes.csv, tables.md\n";
  return report_failures(in.failures, in.cases.size());
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<Args>();
  auto* sub = app.add_subcommand(
      "limit-surface-study",
      "Each push's limit surface ratio c from its force sensor and motion, and how well the plan predicts it leaving "
      "one push out per object");
  add_recordings(*sub, a->files);
  add_out_folder(*sub, a->out);
  sub->add_option("--data", a->data, "Data folder (butter's outline); default: PUSHPRED_DATA or ../shared/data/mcube");
  add_shapes(*sub);
  add_jobs(*sub, a->jobs, "Pushes read and fitted in parallel (default: all cores); the output does not depend on it");
  sub->callback([a, &run] { run = [a] { return run_it(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
