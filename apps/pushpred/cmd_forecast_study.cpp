// `pushpred forecast-study PUSHES... --out DIR`: the whole-push forecast scored leaving one push out per object
// (forecast/forecast_study.hpp): DIR/summary.json (per method and overall, and per object), DIR/pushes.csv (per push
// and method), DIR/tables.md and the figure final_errors.gp (.png where gnuplot is installed). All or nothing.
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
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
  std::string central = kCentralForecastDefaultChoice;
  std::string residual_correction = kResidualCorrectionDefaultChoice;
  std::string centre_of_friction = "chosen";
  std::string trend = kTrendDefaultChoice;
  std::string similarity = kSimilarityDefaultChoice;
  std::string limit_surface = "ellipsoid";
  std::string pressure_shape = kPressureShapeDefaultChoice;
};

int run_study(const StudyArgs& a) {
  StagedOutput out(a.out);
  const std::filesystem::path data = data_folder_if_any(a.data.empty() ? std::nullopt : std::optional(a.data));
  const ForecastInputs in =
      load_forecast_inputs(a.files, data, a.jobs, nullptr, true, limit_surface_named(a.limit_surface));
  ForecastStudyOptions options;
  options.jobs = a.jobs;
  options.learn.central = central_forecast_named(a.central);
  options.learn.residual_correction = residual_correction_named(a.residual_correction);
  set_centre_of_friction_choice(options.learn, a.centre_of_friction);
  set_trend_choice(options.learn, a.trend);
  set_similarity_choice(options.learn, a.similarity);
  set_pressure_shape_choice(options.learn, a.pressure_shape);
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
  const std::string central_help =
      "The central forecast at each time from the learned pushes' own forecasts: ensemble_mean (their weighted mean), "
      "ensemble_median (their positions' weighted geometric median and their yaws' weighted median) or median (the "
      "forecast of their parameters' median); default " +
      std::string(kCentralForecastDefaultChoice);
  sub->add_option("--central", a->central, central_help)->check(CLI::IsMember(kCentralForecastNames));
  const std::string residual_help =
      "Shift the central forecast by the learned pushes' leave-one-out final errors (similarity-weighted, shrunk, "
      "growing with the tip's progress): none, loo (always) or chosen (when it forecasts the learned pushes better "
      "leaving one out); default " +
      std::string(kResidualCorrectionDefaultChoice);
  sub->add_option("--residual-correction", a->residual_correction, residual_help)
      ->check(CLI::IsMember(kResidualCorrectionNames));
  sub->add_option("--centre-of-friction", a->centre_of_friction,
                  "chosen (default: learned jointly over the pushes when that forecasts them better in "
                  "cross-validation, else the centroid), learned (always) or centroid (never learned)")
      ->check(CLI::IsMember({"chosen", "learned", "centroid"}));
  sub->add_option("--trend", a->trend,
                  "none (default) or chosen (the parameters follow the plan along a ridge-regression trend over the "
                  "learned pushes when that forecasts them better leaving each out)")
      ->check(CLI::IsMember({"chosen", "none"}));
  sub->add_option("--similarity", a->similarity,
                  "How the learned pushes are weighted by how alike they push to the plan: chosen (one bandwidth, "
                  "chosen by their own leave-one-out error) or averaged (the weights under the bandwidths 0, 2, 1 and "
                  "0.5 averaged; none chosen)")
      ->check(CLI::IsMember({"chosen", "averaged"}));
  sub->add_option("--limit-surface", a->limit_surface,
                  "ellipsoid (default: the ellipsoidal limit surface of a ratio c fitted per push) or outline (the "
                  "limit surface of a planar pressure over the outline centred at the centre of friction; no c)")
      ->check(CLI::IsMember({"ellipsoid", "outline"}));
  sub->add_option("--pressure-shape", a->pressure_shape,
                  "with --limit-surface outline: chosen (default: the pressure's rim weight learned jointly with the "
                  "centre of friction when that forecasts the pushes better in cross-validation, else uniform), "
                  "learned (always) or uniform (never learned)")
      ->check(CLI::IsMember({"chosen", "learned", "uniform"}));
  add_jobs(*sub, a->jobs,
           "Pushes fitted and forecast in parallel (default: all cores); the output does not depend on it");
  sub->callback([a, &run] { run = [a] { return run_study(*a); }; });
});

}  // namespace
}  // namespace pushpred::app
