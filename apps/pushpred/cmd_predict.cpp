// `pushpred predict FILE... --out DIR`: the paper's identification/prediction study on each push, with the
// prediction methods chosen by name (default: every built-in one, predictor.hpp); DIR/summary.json, DIR/tables.md
// (per object and per pusher speed) and per-push CSVs.
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "study_arguments.hpp"
#include "pushpred/core/output_files.hpp"
#include "pushpred/core/parallel_batch.hpp"
#include "pushpred/reports/prediction_summary.hpp"

namespace pushpred::app {
namespace {

struct PredictArgs {
  std::vector<std::string> files;
  std::string out, shape;
  StudyArguments study;
  double rate_hz = 250.0;
  int jobs = default_jobs();
};

int run_predict(const PredictArgs& a) {
  const StudyOptions o = a.study.options();
  PreprocessOptions pre;
  pre.rate_hz = a.rate_hz;

  StagedOutput out(a.out);
  const auto inputs = expand_inputs(a.files);
  BatchProgress progress("predict", "pushes", inputs.size());
  const Batch<PushStudy> batch = run_batch(inputs, [&](const std::filesystem::path& path) {
    PushStudy s = run_prediction_study(load_push(path, a.shape, pre), o);
    write_text_atomically(out.path("predictions/" + path.stem().string() + ".csv"), predictions_csv(s));
    drop_samples(s);  // the summary and tables need only errors and parameters
    return s;
  }, a.jobs, &progress);
  if (batch.results.empty()) return report_failures(batch.failures, 0);  // nothing written
  const nlohmann::json summary = prediction_summary_json(batch, o);
  write_text_atomically(out.path("summary.json"), json_text(summary));
  write_text_atomically(out.path("tables.md"),
                        "Mean over phases of each phase's mean position error [mm] / yaw error [deg]\n\n" +
                            grouped_errors_markdown(batch.results) + "\n" +
                            losing_phases_markdown(batch.results, "quasi_static", {"hold", "const_velocity"}));
  out.commit();

  std::cout << "predicted " << batch.results.size() << " pushes (" << o.schedule.intervals << " intervals over the "
            << schedule_span_name(o.schedule.span) << " span); summary in " << a.out << "/summary.json\n";
  for (const auto& name : o.methods) {
    if (!summary["aggregate"].contains(name)) continue;
    const auto& e = summary["aggregate"][name];
    std::printf("  %-15s position %6.2f mm (x %6.2f, y %6.2f)  theta %6.2f deg\n", name.c_str(),
                e["pos_mm_mean"].get<double>(), e["x_mm_mean"].get<double>(), e["y_mm_mean"].get<double>(),
                e["theta_deg_mean"].get<double>());
  }
  return report_failures(batch.failures, batch.results.size());
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<PredictArgs>();
  auto* sub = app.add_subcommand("predict", "Identify and predict on each push as in the paper; write summary.json");
  sub->add_option("files", a->files, "Recordings (.h5 or .json), or folders of them")->required();
  sub->add_option("--out", a->out, "Output folder")->required();
  sub->add_option("--shape", a->shape, "Object shape, for files whose name does not carry it");
  a->study.add_to(*sub, {2, true, true, true, true});
  sub->add_option("--rate", a->rate_hz, "Resampling rate [Hz]")->check(CLI::PositiveNumber);
  sub->add_option("--jobs", a->jobs, "Pushes studied in parallel (default: all cores); the output does not depend on it")
      ->check(CLI::PositiveNumber);
  sub->callback([a, &run] { run = [a] { return run_predict(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
