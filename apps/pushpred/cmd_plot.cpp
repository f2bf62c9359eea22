// `pushpred plot FILE --out DIR`: one push's prediction study drawn against the measurement, one PNG per
// prediction method (--methods, default every built-in one; prediction_<method>.png: x, y and yaw over time, the
// measured pose over the whole push and the method's prediction in every prediction phase, the intervals marked) and
// all methods together (prediction_all.png). Writes the data (measured.csv, predictions.csv: mm and degrees), the
// gnuplot scripts and, where gnuplot is installed, the PNGs; all or nothing (StagedOutput).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/reports/plotting.hpp"
#include "pushpred/reports/prediction_summary.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "study_arguments.hpp"

namespace pushpred::app {
namespace {

struct PlotArgs {
  std::string file, out, shape;
  StudyArguments study;
};

/// The measured pose over the whole push, in mm and degrees.
std::string measured_csv(const SynchronisedPush& push) {
  std::ostringstream out;
  out.precision(10);
  out << "t_s,x_mm,y_mm,theta_deg\n";
  for (Eigen::Index k = 0; k < push.size(); ++k)
    out << push.t_s(k) << "," << 1e3 * push.pose(k, 0) << "," << 1e3 * push.pose(k, 1) << ","
        << push.pose(k, 2) * 180.0 / M_PI << "\n";
  return out.str();
}

/// A gnuplot script drawing `methods` (indices into the method names, whose columns follow the measured pose in
/// predictions.csv) against the measurement.
std::string plot_script(const PushStudy& study, const std::vector<std::string>& names,
                        const std::vector<std::size_t>& methods, const std::string& png, const std::string& title) {
  std::ostringstream gp;
  gp << "# " << title << ". Data: measured.csv (whole push), predictions.csv (prediction phases); mm and degrees.\n"
     << png_terminal(png, 1100, 950) << "set termoption noenhanced\nset datafile separator ','\nset grid\n"
     << "set key outside right top\n"
     << "set multiplot layout 3,1 title " << gnuplot_quoted(title) << " noenhanced\n";
  for (const auto& iv : study.intervals)
    gp << "set arrow from " << iv.t0_s << ", graph 0 to " << iv.t0_s << ", graph 1 nohead dt 3 lc 'gray'\n";
  const char* labels[3] = {"x [mm]", "y [mm]", "yaw [deg]"};
  const int phases = static_cast<int>(study.phases.size());
  for (int c = 0; c < 3; ++c) {
    gp << "set ylabel '" << labels[c] << "'\n" << (c == 2 ? "set xlabel 't [s]'\n" : "unset xlabel\n")
       << "plot 'measured.csv' every ::1 using 1:" << 2 + c << " with lines lw 2 lc 'black' title 'measured'";
    for (std::size_t i = 0; i < methods.size(); ++i) {
      const std::size_t m = methods[i];
      const std::size_t column = 6 + 3 * m + static_cast<std::size_t>(c);
      // One curve per phase, so that no line joins the end of one phase to the start of the next.
      for (int ph = 1; ph <= phases; ++ph)
        gp << ", 'predictions.csv' every ::1 using ($1==" << ph << " ? $2 : 1/0):" << column
           << " with lines lw 1.5 lc " << i + 1 << " " << (ph == 1 ? "title " + gnuplot_quoted(names[m]) : "notitle");
    }
    gp << "\n";
  }
  gp << "unset multiplot\n";
  return gp.str();
}

int run_plot(const PlotArgs& a) {
  const StudyOptions options = a.study.options();
  StagedOutput out(a.out);  // checks the destination before any work
  const SynchronisedPush push = load_push(a.file, a.shape);
  const PushStudy study = run_prediction_study(push, options);
  const std::vector<std::string>& names = study.methods;  // --methods, in its order
  write_text_atomically(out.path("measured.csv"), measured_csv(push));
  write_text_atomically(out.path("predictions.csv"), predictions_csv(study));
  const std::string file = std::filesystem::path(a.file).filename().string();
  std::vector<std::string> scripts, notes;
  std::vector<std::size_t> all;
  for (std::size_t m = 0; m < names.size(); ++m) {
    all.push_back(m);
    scripts.push_back("prediction_" + names[m] + ".gp");
    write_text_atomically(out.path(scripts.back()),
                          plot_script(study, names, {m}, "prediction_" + names[m] + ".png", names[m] + ": " + file));
  }
  scripts.push_back("prediction_all.gp");
  write_text_atomically(out.path(scripts.back()),
                        plot_script(study, names, all, "prediction_all.png", "every method: " + file));
  for (const auto& script : scripts) {
    const PlotRun run = run_gnuplot(out.path(script));
    if (!run.drawn && std::find(notes.begin(), notes.end(), run.note) == notes.end()) notes.push_back(run.note);
  }
  out.commit();
  std::cout << "prediction phases: " << study.phases.size() << " (" << study.span << " span)\n";
  const auto errors = aggregate_errors({study});
  for (const auto& name : names) {
    const auto& e = errors.at(name);
    std::printf("%-16s mean error x %.2f mm, y %.2f mm, yaw %.2f deg\n", name.c_str(), e.x_mm_mean, e.y_mm_mean,
                e.theta_deg_mean);
  }
  for (const auto& n : notes) std::cout << "note: " << n << "\n";
  std::cout << "wrote " << a.out << "/measured.csv, predictions.csv, " << scripts.size() << " gnuplot scripts"
            << (notes.empty() ? " and their PNGs" : "") << "\n";
  return 0;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto args = std::make_shared<PlotArgs>();
  auto* sub = app.add_subcommand("plot", "One push's prediction against the measurement, for every method, as PNG");
  sub->add_option("file", args->file, "Recording (.h5 or .json)")->required();
  add_out_folder(*sub, args->out);
  add_shape(*sub, args->shape);
  args->study.methods_note = ", one PNG each";
  args->study.add_to(*sub, {2, true, true, true, true});
  sub->callback([args, &run] { run = [args] { return run_plot(*args); }; });
});

}  // namespace
}  // namespace pushpred::app
