// `pushpred observe FILE --out DIR`: the disturbance observer and the PID force reconstruction on one push,
// side by side (paper figures 2 and 4). Writes DIR/observer.csv, resimulation.csv, observation.json, the gnuplot
// scripts and, where gnuplot is installed, their PNGs; all or nothing (StagedOutput).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/observers/observation.hpp"
#include "pushpred/reports/observation_report.hpp"
#include "pushpred/reports/plotting.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred::app {
namespace {

struct ObserveArgs {
  std::string file, out, shape, hold = "first";
  double start_s = 0, end_s = -1, wn_rad_s = 300, zeta = 1 / std::sqrt(2.0);
  bool no_plots = false;
};

int run_observe(const ObserveArgs& a) {
  ObservationOptions options;
  options.t_start_s = a.start_s;
  options.t_end_s = a.end_s;
  options.observer.wn_rad_s = a.wn_rad_s;
  options.observer.zeta = a.zeta;
  options.observer.hold = a.hold == "zero" ? Hold::Zero : Hold::First;
  StagedOutput out(a.out);  // checks the destination before any work
  const Observation observation = on_file(a.file, [&] { return observe_push(load_push(a.file, a.shape), options); });
  for (const auto& f : observation_files(observation)) write_text_atomically(out.path(f.name), f.text);
  std::vector<std::string> notes;
  if (!a.no_plots)
    for (const auto& script : observation_plot_scripts()) {
      const PlotRun run = run_gnuplot(out.path(script));
      if (!run.drawn && std::find(notes.begin(), notes.end(), run.note) == notes.end()) notes.push_back(run.note);
    }
  out.commit();
  std::cout << observation_summary(observation);
  for (const auto& n : notes) std::cout << "note: " << n << "\n";
  std::cout << "wrote " << a.out << "/observer.csv, resimulation.csv, observation.json"
            << (a.no_plots || !notes.empty() ? "" : ", forces.png, trajectory.png") << "\n";
  return 0;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto args = std::make_shared<ObserveArgs>();
  auto* sub = app.add_subcommand("observe", "Disturbance observer and PID force reconstruction on one push");
  sub->add_option("file", args->file, "Recording (.h5 or .json)")->required();
  add_out_folder(*sub, args->out);
  add_shape(*sub, args->shape);
  // A span within the longest push a recording may hold (PlausibilityLimits::max_span_s, 600 s).
  const double longest_s = PlausibilityLimits{}.max_span_s;
  sub->add_option("--start", args->start_s, "Start of the span [s from the recording's start], 0 to 600")
      ->check(finite_number_in(0, longest_s));
  sub->add_option("--end", args->end_s, "End of the span [s], up to 600; default (-1): the end of the push")
      ->check(CLI::Validator(
          [longest_s](std::string& text) -> std::string {
            double value = 0;
            const bool ok = CLI::detail::lexical_cast(text, value) &&
                            (value == -1 || (std::isfinite(value) && value > 0 && value <= longest_s));
            return ok ? std::string()
                      : "must be a finite number in (0, 600] or -1 (the push's end), got '" + text + "'";
          },
          "NUMBER"));
  sub->add_option("--wn", args->wn_rad_s, "Natural frequency of the Q-filter [rad/s], at most 7854")
      ->check(positive_number_up_to(kMaxObserverFrequency_rad_s));
  sub->add_option("--zeta", args->zeta, "Damping of the Q-filter, at most 10")
      ->check(positive_number_up_to(kMaxObserverDamping));
  sub->add_option("--hold", args->hold, "How samples are held between grid times")
      ->check(CLI::IsMember({"first", "zero"}));
  sub->add_flag("--no-plots", args->no_plots, "Write the data and scripts only");
  sub->callback([args, &run] { run = [args] { return run_observe(*args); }; });
});

}  // namespace
}  // namespace pushpred::app
