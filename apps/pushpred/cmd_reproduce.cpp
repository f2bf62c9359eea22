// `pushpred reproduce [--data DIR] --out DIR`: the paper's study end to end (report.md, summary.json, figures).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/jobs/reproduction_job.hpp"
#include "study_arguments.hpp"

namespace pushpred::app {
namespace {

struct ReproduceArgs {
  std::string data, out;
  std::vector<std::string> cases;
  StudyArguments study;
  bool no_real = false;
};

int run_reproduce(const ReproduceArgs& a) {
  ReproductionOptions o;
  o.study = a.study.options();
  if (!a.no_real) o.data_folder = resolve_data_folder(a.data.empty() ? std::nullopt : std::optional<std::string>(a.data));
  for (const auto& c : a.cases) o.case_files.emplace_back(c);
  StagedOutput out(a.out);
  const ReproductionResult result = reproduce_paper(o, out, std::cout);
  out.commit();
  const PaperReproduction& r = result.reproduction;
  std::cout << "report: " << a.out << "/report.md (" << r.cases.size() << " paper cases, " << r.real.results.size()
            << " real pushes, " << r.real.failures.size() << " real pushes left out with reasons)\n";
  for (const auto& n : result.plot_notes) std::cerr << "note: plot not drawn: " << n << "\n";
  // The real pushes by predict's rule: a skipped push (frozen force sensor) is listed and leaves the exit code 0, a
  // failed one makes it 1; the paper's cases and the report are written either way.
  std::size_t failed = 0;
  for (const auto& f : r.real.failures) {
    std::cerr << (f.skipped ? "SKIPPED " : "FAILED ") << plain_text(f.source) << ": " << plain_text(f.reason) << "\n";
    failed += f.skipped ? 0 : 1;
  }
  return failed > 0 ? kExitSomeFailed : 0;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<ReproduceArgs>();
  auto* sub = app.add_subcommand("reproduce", "Reproduce the paper's study (six rect2 cases) and run it on the real ABS pushes");
  add_out_folder(*sub, a->out, "Output folder (report.md, summary.json, figures)");
  sub->add_option("--data", a->data, "Real recordings folder (default: PUSHPRED_DATA or ../shared/data/mcube)");
  add_shapes(*sub);
  sub->add_flag("--no-real", a->no_real, "Only the six paper cases, not the real pushes");
  sub->add_option("--cases", a->cases, "Six real rect2 recordings for cases 1-6 (default: simulate them)")
      ->expected(6);
  a->study.methods_note =
      "; the per-method tables and summary.json hold them, and dob and simple, which always run since Table II and "
      "figures 7-9 compare them";
  a->study.add_to(*sub, {2, true, true, false, true});  // the simple baseline keeps the paper's abs value (no --mu)
  sub->callback([a, &run] { run = [a] { return run_reproduce(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
