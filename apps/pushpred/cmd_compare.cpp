// `pushpred compare FILE... --out DIR`: RLS against the Ceres batch fits (plain and robust) on the same pushes, with
// the prediction errors of the methods chosen by --methods (default: dob and dob_velinit, the ones that use the
// relation the estimators fit).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/jobs/comparison_job.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/parallel_batch.hpp"
#include "study_arguments.hpp"

namespace pushpred::app {
namespace {

struct CompareArgs {
  std::vector<std::string> files;
  std::vector<std::string> estimators{"rls", "rls_forget", "batch", "batch_huber", "batch_cauchy", "batch_joint"};
  std::string out, shape;
  StudyArguments study;
  int jobs = default_jobs();
};

int run_compare(const CompareArgs& a) {
  const StudyOptions o = a.study.options();
  StagedOutput out(a.out);
  const EstimatorComparison c = compare_estimators(a.files, a.estimators, o, a.shape, a.jobs);
  const std::size_t used = c.rows.empty() ? 0 : static_cast<std::size_t>(c.rows.front().pushes);
  if (used == 0) return report_failures(c.failures, 0);  // nothing written
  const std::string md = comparison_markdown(c);
  write_text_atomically(out.path("compare.md"), md);
  out.commit();
  std::cout << md;
  return report_failures(c.failures, used);
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<CompareArgs>();
  auto* sub = app.add_subcommand("compare", "Compare RLS with Ceres batch fits (plain and robust) on the same pushes");
  add_recordings(*sub, a->files);
  add_out_folder(*sub, a->out, "Output folder (compare.md)");
  sub->add_option("--estimators", a->estimators, "Estimators to compare; the first is the reference")->delimiter(',');
  add_shape(*sub, a->shape);
  // The library's default (the methods that use the fitted relation), shown as --methods' default.
  for (const auto& m : default_comparison_methods()) a->study.methods += (a->study.methods.empty() ? "" : ",") + m;
  a->study.methods_note = "; one pair of error columns each";
  a->study.add_to(*sub, {2, true, false, true, true});
  // The estimators compared come from --estimators.
  add_jobs(*sub, a->jobs, "Pushes studied in parallel (default: all cores); the results do not depend on it");
  sub->callback([a, &run] { run = [a] { return run_compare(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
