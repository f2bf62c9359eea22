// `pushpred diagnose FILE... --out DIR`: finds what the paper's method leaves unexplained on pushes of one object,
// tests a library of candidate physical effects against it, adds the selected ones and reports the prediction
// error before and after on held-out phases (DIR/diagnosis.json, DIR/report.md, plots). With --per-object, a batch
// of several objects or surfaces is diagnosed one object at a time: DIR/<shape>_on_<surface>/ each, and
// DIR/overview.md and DIR/overview.json side by side.
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include "commands.hpp"
#include "study_arguments.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/core/output_files.hpp"
#include "pushpred/core/parallel_batch.hpp"
#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/push_groups.hpp"
#include "pushpred/reports/diagnosis_report.hpp"

namespace pushpred::app {
namespace {

struct DiagnoseArgs {
  std::vector<std::string> files;
  std::string out, shape;
  StudyArguments study;
  double bic_threshold = 10.0, rate_hz = 250.0;
  std::vector<std::string> exclude;
  bool per_object = false, no_plots = false, quick_base = false;
  double relevance_fraction = 0.05;
  int jobs = default_jobs();
};

int run_diagnose(const DiagnoseArgs& a) {
  DiagnosisOptions o;
  o.study = a.study.options();
  o.bic_threshold = a.bic_threshold;
  o.relevance_fraction = a.relevance_fraction;
  o.fit_base_settings = !a.quick_base;
  o.validate();
  EffectLibrary library = EffectLibrary::standard();
  for (const auto& kind : a.exclude) library.remove(kind);
  PreprocessOptions pre;
  pre.rate_hz = a.rate_hz;

  const auto inputs = expand_inputs(a.files);
  const Batch<SynchronisedPush> loaded = run_batch(
      inputs, [&](const std::filesystem::path& path) { return load_push(path, a.shape, pre); }, a.jobs, nullptr);
  for (const auto& f : loaded.failures) std::cerr << "FAILED " << f.source << ": " << f.reason << "\n";
  if (loaded.results.empty()) throw InputError("no push could be read; nothing written");
  const std::size_t loaded_count = loaded.results.size();
  std::vector<PushGroup> groups = group_by_object(loaded.results);
  if (groups.size() > 1 && !a.per_object) {
    std::string names;
    for (const auto& g : groups) names += (names.empty() ? "" : ", ") + g.name() + " (" + std::to_string(g.pushes.size()) + ")";
    throw InputError("the pushes are of " + std::to_string(groups.size()) + " objects or surfaces: " + names +
                     "; a diagnosis fits one object on one surface: give one, or pass --per-object");
  }

  if (!a.per_object) {
    DiagnosisResult result = diagnose(groups.front().pushes, library, o);
    // Pushes read but left out by the diagnosis; the unreadable ones were listed above.
    for (const auto& f : result.failures) std::cerr << "LEFT OUT " << f.source << ": " << f.reason << "\n";
    result.failures.insert(result.failures.begin(), loaded.failures.begin(), loaded.failures.end());
    StagedOutput out(a.out);
    write_diagnosis_report(result, o, out, !a.no_plots);
    out.commit();
    for (const auto& line : result.log) std::cout << line << "\n";
    std::cout << diagnosis_summary_text(result);
    std::cout << "report in " << a.out << "/report.md, data in " << a.out << "/diagnosis.json\n";
    return result.failures.empty() ? 0 : 1;
  }

  // One diagnosis per object, the objects shared out over the jobs: a group that cannot be diagnosed is reported
  // and the others go on. What each prints is kept and printed in the objects' order, whatever the jobs.
  StagedOutput out(a.out);
  std::vector<DiagnosisGroupOutcome> outcomes(groups.size());
  std::vector<std::string> printed(groups.size()), complaints(groups.size());
  std::vector<std::size_t> left_out_of(groups.size(), 0);
  BatchProgress progress("diagnose", "objects", groups.size());
  std::atomic<std::size_t> next{0};
  const auto one_object = [&](std::size_t i) {
    PushGroup& g = groups[i];
    DiagnosisGroupOutcome outcome{g.name(), g.pushes.size(), std::nullopt, ""};
    try {
      DiagnosisResult result = diagnose(g.pushes, library, o);
      write_diagnosis_report(result, o, out.path(g.name()), !a.no_plots);
      printed[i] = diagnosis_summary_text(result);
      for (const auto& f : result.failures) complaints[i] += "LEFT OUT " + f.source + ": " + f.reason + "\n";
      left_out_of[i] = result.failures.size();
      outcome.result = std::move(result);
    } catch (const InputError& e) {
      outcome.error = e.what();
      complaints[i] += "FAILED " + g.name() + ": " + e.what() + "\n";
    }
    outcomes[i] = std::move(outcome);
    progress.item_done();
  };
  const std::size_t threads = std::min<std::size_t>(static_cast<std::size_t>(a.jobs), groups.size());
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < threads; ++t)
    pool.emplace_back([&] {
      for (std::size_t i = next++; i < groups.size(); i = next++) one_object(i);
    });
  for (auto& t : pool) t.join();
  progress.finish();
  std::size_t left_out = 0;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    std::cout << printed[i];
    std::cerr << complaints[i];
    left_out += left_out_of[i];
  }
  std::size_t failed_groups = 0;
  for (const auto& g : outcomes) failed_groups += g.result ? 0 : 1;
  if (failed_groups == outcomes.size()) throw InputError("no object could be diagnosed; nothing written");
  write_text_atomically(out.path("overview.md"), diagnosis_overview_markdown(outcomes));
  write_text_atomically(out.path("overview.json"), json_text(diagnosis_overview_json(outcomes)));
  out.commit();
  std::cout << outcomes.size() - failed_groups << " of " << outcomes.size() << " objects diagnosed (" << loaded_count
            << " pushes read); overview in " << a.out << "/overview.md\n";
  if (failed_groups > 0) std::cerr << failed_groups << " of " << outcomes.size() << " objects failed\n";
  return failed_groups == 0 && left_out == 0 && loaded.failures.empty() ? 0 : 1;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<DiagnoseArgs>();
  auto* sub = app.add_subcommand(
      "diagnose", "Find the residual of the paper's method, test candidate effects, report the error before and after");
  sub->add_option("files", a->files, "Recordings of one object on one surface (.h5 or .json), or folders of them")
      ->required();
  sub->add_option("--out", a->out, "Output folder (diagnosis.json, report.md, plots)")->required();
  sub->add_option("--shape", a->shape, "Object shape, for files whose name does not carry it");
  a->study.add_to(*sub, {3, false, true, true});  // the diagnosis runs the paper's observer
  sub->add_option("--bic-threshold", a->bic_threshold, "BIC drop an effect needs to be selected (default 10)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--exclude", a->exclude, "Candidate effect kinds to leave out (repeatable)");
  sub->add_flag("--per-object", a->per_object,
                "Diagnose each object and surface of the batch on its own (DIR/<shape>_on_<surface>/, DIR/overview.md)");
  sub->add_option("--relevance", a->relevance_fraction,
                  "Share of the support friction force below which an effect is negligible (default 0.05)")
      ->check(CLI::Range(1e-6, 0.999999));
  sub->add_flag("--quick-base", a->quick_base,
                "Do not fit the base model's settings (quasi-static stop fraction) on the fit phases: faster");
  sub->add_flag("--no-plots", a->no_plots, "Do not draw plots");
  sub->add_option("--rate", a->rate_hz, "Resampling rate [Hz]")->check(CLI::PositiveNumber);
  sub->add_option("--jobs", a->jobs,
                  "Files read, and with --per-object objects diagnosed, in parallel (default: all cores); the output "
                  "does not depend on it")
      ->check(CLI::PositiveNumber);
  add_shard_refusal(*sub);
  sub->callback([a, &run] { run = [a] { return run_diagnose(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
