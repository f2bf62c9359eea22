// `pushpred inspect FILE... [--json]`: what each recording holds and what the reader had to repair.
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/jobs/inspection_job.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred::app {
namespace {

struct InspectArgs {
  std::vector<std::string> files;
  bool json = false;
  std::string shape;
  double rate_hz = 250.0;
  int jobs = default_jobs();
};

int run_inspect(const InspectArgs& a) {
  InspectionOptions options;
  options.shape_override = a.shape;
  options.preprocess.rate_hz = a.rate_hz;
  options.jobs = a.jobs;
  options.progress = true;
  const InspectionBatch batch = inspect_files(a.files, options);
  std::cout << (a.json ? json_text(inspection_json(batch)) : inspection_table(batch));
  return report_failures(batch.failures, batch.results.size());
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto args = std::make_shared<InspectArgs>();
  auto* sub = app.add_subcommand("inspect", "Summarise recordings: rates, contact, repairs, flags, travel");
  add_recordings(*sub, args->files);
  sub->add_flag("--json", args->json, "Print JSON instead of a table");
  add_shape(*sub, args->shape);
  add_rate(*sub, args->rate_hz);
  add_jobs(*sub, args->jobs, "Files read in parallel (default: all cores); the output does not depend on it");
  sub->callback([args, &run] { run = [args] { return run_inspect(*args); }; });
});

}  // namespace
}  // namespace pushpred::app
