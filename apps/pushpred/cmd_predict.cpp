// `pushpred predict FILE... --out DIR`: the paper's identification/prediction study on each push, with the
// `dob`, `dob_velinit`, `simple`, `hold` and `const_velocity` methods; DIR/summary.json and per-push CSVs.
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "pushpred/core/output_files.hpp"
#include "pushpred/reports/prediction_summary.hpp"

namespace pushpred::app {
namespace {

struct PredictArgs {
  std::vector<std::string> files;
  std::string out, shape, span = "whole", observer = "dob", estimator = "rls";
  int intervals = 4;
  double plan_rate_hz = 10.0, mu = -1.0, rate_hz = 250.0;
};

int run_predict(const PredictArgs& a) {
  StudyOptions o;
  o.schedule.intervals = a.intervals;
  o.schedule.span = parse_schedule_span(a.span);
  o.plan_rate_hz = a.plan_rate_hz;
  o.observer = a.observer;
  o.estimator = a.estimator;
  o.friction_coefficient = a.mu;
  // Fail on a bad name before any file is read.
  make_disturbance_estimator(o.observer);
  make_relation_estimator(o.estimator);
  PreprocessOptions pre;
  pre.rate_hz = a.rate_hz;

  StagedOutput out(a.out);
  const Batch<PushStudy> batch = run_batch(expand_inputs(a.files), [&](const std::filesystem::path& path) {
    PushStudy s = run_prediction_study(load_push(path, a.shape, pre), o);
    write_text_atomically(out.path("predictions/" + path.stem().string() + ".csv"), predictions_csv(s));
    return s;
  });
  const nlohmann::json summary = prediction_summary_json(batch, o);
  write_text_atomically(out.path("summary.json"), summary.dump(2) + "\n");
  out.commit();

  std::cout << "predicted " << batch.results.size() << " pushes (" << o.schedule.intervals << " intervals over the "
            << schedule_span_name(o.schedule.span) << " span); summary in " << a.out << "/summary.json\n";
  for (const auto& name : prediction_method_names()) {
    if (!summary["aggregate"].contains(name)) continue;
    const auto& e = summary["aggregate"][name];
    std::printf("  %-15s x %7.2f mm  y %7.2f mm  theta %7.2f deg\n", name.c_str(), e["x_mm_mean"].get<double>(),
                e["y_mm_mean"].get<double>(), e["theta_deg_mean"].get<double>());
  }
  for (const auto& f : batch.failures) std::cerr << "FAILED " << f.source << ": " << f.reason << "\n";
  if (!batch.failures.empty()) std::cerr << batch.failures.size() << " of " << batch.failures.size() + batch.results.size() << " files failed\n";
  return batch.failures.empty() ? 0 : 1;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<PredictArgs>();
  auto* sub = app.add_subcommand("predict", "Identify and predict on each push as in the paper; write summary.json");
  sub->add_option("files", a->files, "Recordings (.h5 or .json), or folders of them")->required();
  sub->add_option("--out", a->out, "Output folder")->required();
  sub->add_option("--estimator", a->estimator, "Relation estimator: " + [] {
    std::string s;
    for (const auto& n : relation_estimator_names()) s += (s.empty() ? "" : ", ") + n;
    return s;
  }());
  sub->add_option("--observer", a->observer, "Disturbance estimator: dob or pid");
  sub->add_option("--shape", a->shape, "Object shape, for files whose name does not carry it");
  sub->add_option("--intervals", a->intervals, "Number of equal intervals (identify on the first)")
      ->check(CLI::Range(2, 100));
  sub->add_option("--span", a->span, "Split the whole recording or only the contact span")
      ->check(CLI::IsMember({"whole", "contact"}));
  sub->add_option("--plan-rate", a->plan_rate_hz, "Planned-force sampling rate [Hz]")->check(CLI::PositiveNumber);
  sub->add_option("--mu", a->mu, "Friction coefficient for the simple baseline (default: from the surface)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--rate", a->rate_hz, "Resampling rate [Hz]")->check(CLI::PositiveNumber);
  sub->callback([a, &run] { run = [a] { return run_predict(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
