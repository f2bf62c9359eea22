// `pushpred forecast-study PUSHES... --out DIR`: the whole-push forecast scored leaving one push out per object
// (forecast/forecast_study.hpp): DIR/summary.json (per method and overall, and per object), DIR/pushes.csv (per push
// and method), DIR/tables.md and the figure final_errors.gp (.png where gnuplot is installed). All or nothing.
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "learn_arguments.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/reports/forecast_report.hpp"
#include "pushpred/reports/plotting.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred::app {
namespace {

struct StudyArgs {
  std::vector<std::string> files;
  std::string out, data;
  int jobs = default_jobs();
  LearnArguments learning;
};

int run_study(const StudyArgs& a) {
  StagedOutput out(a.out);
  const std::filesystem::path data = data_folder_if_any(a.data.empty() ? std::nullopt : std::optional(a.data));
  const ForecastInputs in =
      load_forecast_inputs(a.files, data, a.jobs, nullptr, true, limit_surface_named(a.learning.limit_surface));
  ForecastStudyOptions options;
  options.jobs = a.jobs;
  a.learning.apply_to(options.learn);
  std::vector<std::pair<std::string, std::string>> excluded = in.excluded;
  const std::vector<ForecastStudyPush> pushes = run_forecast_study(in.cases, in.fits, options, &excluded);
  if (pushes.empty()) {
    for (const auto& e : excluded) std::cerr << "not forecast " << e.first << ": " << e.second << "\n";
    const int code = report_failures(in.failures, 0);
    std::cerr
        << "pushpred: error: no push could be forecast (each needs 2 other pushes of its object); nothing written\n";
    return code == 0 ? kExitNothingDone : code;
  }
  const nlohmann::json summary = forecast_study_summary(pushes, excluded, in.failures);
  write_text_atomically(out.path("summary.json"), json_text(summary));
  write_text_atomically(out.path("pushes.csv"), forecast_study_csv(pushes));
  write_text_atomically(out.path("tables.md"), forecast_study_tables(summary));
  write_text_atomically(out.path("final_errors.gp"), forecast_study_figure_script("final_errors.png"));
  const PlotRun drawn = run_gnuplot(out.path("final_errors.gp"));
  out.commit();
  std::printf("%-15s %7s %9s %9s %9s %9s %8s %8s\n", "method", "pushes", "final mm", "final deg", "traj mm", "traj deg",
              "cov pos", "cov yaw");
  for (const auto& [name, m] : summary.at("methods").items()) {
    auto num = [&](const char* key) { return m.at(key).is_number() ? m.at(key).get<double>() : NAN; };
    std::printf("%-15s %7zu %9.2f %9.2f %9.2f %9.2f %8.3f %8.3f\n", name.c_str(), m.at("pushes").get<std::size_t>(),
                num("final_pos_mm_mean"), num("final_yaw_deg_mean"), num("trajectory_pos_mm_mean"),
                num("trajectory_yaw_deg_mean"), num("coverage90_pos"), num("coverage90_yaw"));
  }
  const auto& f = summary.at("methods").at("forecast");
  std::printf("median 90 %% region: %.2f mm, +-%.2f deg (final: %.2f mm, +-%.2f deg)\n",
              f.at("region90_radius_mm_median").get<double>(), f.at("region90_yaw_halfwidth_deg_median").get<double>(),
              f.at("region90_final_radius_mm_median").get<double>(),
              f.at("region90_final_yaw_halfwidth_deg_median").get<double>());
  std::cout << excluded.size() << " pushes not forecast (listed in summary.json)\n";
  if (!drawn.drawn) std::cout << "note: " << drawn.note << "\n";
  std::cout << "wrote " << a.out << "/summary.json, pushes.csv, tables.md, final_errors.gp"
            << (drawn.drawn ? ", final_errors.png" : "") << "\n";
  return report_failures(in.failures, in.cases.size());
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<StudyArgs>();
  auto* sub = app.add_subcommand("forecast-study", "The whole-push forecast scored leaving one push out per object");
  add_recordings(*sub, a->files);
  add_out_folder(*sub, a->out);
  sub->add_option("--data", a->data, "Data folder (butter's outline); default: PUSHPRED_DATA or ../shared/data/mcube");
  add_shapes(*sub);
  a->learning.add_to(*sub);
  add_jobs(*sub, a->jobs,
           "Pushes fitted and forecast in parallel (default: all cores); the output does not depend on it");
  sub->callback([a, &run] { run = [a] { return run_study(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
