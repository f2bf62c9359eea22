// `pushpred reproduce [--data DIR] --out DIR`: the paper's study end to end (report.md, summary.json, figures).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/reports/paper_reproduction.hpp"

namespace pushpred::app {
namespace {

struct ReproduceArgs {
  std::string data, out, span = "whole", observer = "dob", estimator = "rls";
  std::vector<std::string> cases;
  int intervals = 4;
  double plan_rate_hz = 10.0;
  bool no_real = false;
};

int run_reproduce(const ReproduceArgs& a) {
  ReproductionOptions o;
  o.study.schedule.intervals = a.intervals;
  o.study.schedule.span = parse_schedule_span(a.span);
  o.study.plan_rate_hz = a.plan_rate_hz;
  o.study.observer = a.observer;
  o.study.estimator = a.estimator;
  make_disturbance_estimator(o.study.observer);
  make_relation_estimator(o.study.estimator);
  if (!a.no_real) o.data_folder = resolve_data_folder(a.data.empty() ? std::nullopt : std::optional<std::string>(a.data));
  for (const auto& c : a.cases) o.case_files.emplace_back(c);
  StagedOutput out(a.out);
  const ReproductionResult r = reproduce_paper(o, out, std::cout);
  out.commit();
  std::cout << "report: " << a.out << "/report.md (" << r.cases.size() << " paper cases, " << r.real.results.size()
            << " real pushes, " << r.real.failures.size() << " real pushes left out with reasons)\n";
  for (const auto& n : r.plot_notes) std::cerr << "note: plot not drawn: " << n << "\n";
  return 0;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<ReproduceArgs>();
  auto* sub = app.add_subcommand("reproduce", "Reproduce the paper's study (six rect2 cases) and run it on the real ABS pushes");
  sub->add_option("--out", a->out, "Output folder (report.md, summary.json, figures)")->required();
  sub->add_option("--data", a->data, "Real recordings folder (default: PUSHPRED_DATA or ../shared/data/mcube)");
  sub->add_flag("--no-real", a->no_real, "Only the six paper cases, not the real pushes");
  sub->add_option("--cases", a->cases, "Six real rect2 recordings for cases 1-6 (default: simulate them)")
      ->expected(6);
  sub->add_option("--intervals", a->intervals, "Number of equal intervals")->check(CLI::Range(2, 100));
  sub->add_option("--span", a->span, "whole or contact")->check(CLI::IsMember({"whole", "contact"}));
  sub->add_option("--plan-rate", a->plan_rate_hz, "Planned-force sampling rate [Hz]")->check(CLI::PositiveNumber);
  sub->add_option("--observer", a->observer, "Disturbance estimator: dob or pid");
  sub->add_option("--estimator", a->estimator, "Relation estimator (see `pushpred predict --help`)");
  sub->callback([a, &run] { run = [a] { return run_reproduce(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
