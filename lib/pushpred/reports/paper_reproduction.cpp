#include "pushpred/reports/paper_reproduction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>
#include <ostream>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/core/version.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/reading/recording.hpp"
#include "pushpred/reading/shape_table.hpp"
#include "pushpred/reports/markdown_table.hpp"
#include "pushpred/reports/observation_report.hpp"
#include "pushpred/reports/plotting.hpp"
#include "pushpred/reports/prediction_summary.hpp"

namespace pushpred {
namespace {

constexpr double kMm = 1e3, kDeg = 180.0 / M_PI;

/// A number for the report's tables and text: never "-0.0" (table_number).
std::string fmt(const char* f, double v) { return table_number(f, v); }

/// A plot's value range for one pose column of some curves, in report units, padded by a fifth of its span (at least
/// one unit) so that the curves do not touch the frame.
struct FigureRange {
  double lo = 0, hi = 0;
};
FigureRange figure_range(std::initializer_list<const Eigen::MatrixX3d*> curves, int column, double scale) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Eigen::MatrixX3d* m : curves) {
    lo = std::min(lo, scale * m->col(column).minCoeff());
    hi = std::max(hi, scale * m->col(column).maxCoeff());
  }
  const double pad = std::max(1.0, 0.2 * (hi - lo));
  return {lo - pad, hi + pad};
}

/// Writes a gnuplot script and runs it; a plot that cannot be drawn leaves a note, never an error.
void draw(const StagedOutput& out, const std::string& script_name, const std::string& script,
          std::vector<std::string>& notes) {
  write_text_atomically(out.path(script_name), script);
  const PlotRun run = run_gnuplot(out.path(script_name));
  if (!run.drawn) notes.push_back(script_name + ": " + run.note);
}

/// The paper's Table I, as published, for the report's side-by-side.
struct PaperCase {
  double acceleration_m_s2, velocity_m_s;
};
constexpr PaperCase kPaperTableI[6] = {{0.0, 0.01}, {0.0, 0.01}, {0.0, 0.01}, {0.0, 0.05}, {0.2, -0.001}, {2.5, -0.001}};

/// The window over which the tip speed is measured. The largest of many noisy speeds runs above the true peak: by
/// 6 % at 10 mm/s over 20 ms windows on the simulated cases, 3 % over 50 ms; longer windows would average over the
/// stop of the accelerating pushes (case 6 reaches its peak just before a 70 ms stop).
constexpr double kTipSpeedWindow_s = 0.05;

/// Grid samples spanned by the tip speed window (the nearest whole number, halves up).
Eigen::Index tip_speed_step(const SynchronisedPush& p) {
  return std::max<Eigen::Index>(1, static_cast<Eigen::Index>(std::floor(kTipSpeedWindow_s * p.rate_hz + 0.5)));
}

/// The largest tip speed of a recording: tip displacement over tip_speed_step() samples, divided by their time [m/s].
double peak_tip_speed_m_s(const SynchronisedPush& p) {
  const Eigen::Index step = tip_speed_step(p);
  double peak = 0;
  for (Eigen::Index k = 0; k + step < p.size(); ++k)
    peak = std::max(peak, (p.tip_m.row(k + step) - p.tip_m.row(k)).norm() / (p.t_s(k + step) - p.t_s(k)));
  return peak;
}

/// The method whose error picks the real push of figures 10 and 11.
constexpr const char* kTypicalPushMethod = "quasi_static";

double mean_position_error(const PredictionErrors& e) { return 0.5 * (e.x_mm_mean + e.y_mm_mean); }

/// Mean over the phases of a study.
PredictionErrors phase_mean(const PushStudy& s, const std::string& method) {
  return aggregate_errors({s}).at(method);
}

std::string shape_of(const std::string& source) {
  const auto p = parse_push_filename(source);
  return p ? p->shape : "unknown";
}

std::string errors_row(const std::string& label, const PredictionErrors& e) {
  return "| " + markdown_cell(label) + " | " + fmt("%.2f", e.x_mm_mean) + " ± " + fmt("%.2f", e.x_mm_std) + " | " +
         fmt("%.2f", e.y_mm_mean) + " ± " + fmt("%.2f", e.y_mm_std) + " | " + fmt("%.2f", e.theta_deg_mean) + " ± " +
         fmt("%.2f", e.theta_deg_std) + " | " + fmt("%.2f", e.final_pos_mm) + " | " + fmt("%.2f", e.final_theta_deg) +
         " |\n";
}

const char* kErrorsHeader =
    "| | x error [mm] mean ± std | y error [mm] mean ± std | yaw error [deg] mean ± std | final position error [mm] | "
    "final yaw error [deg] |\n|---|---|---|---|---|---|\n";

/// The report's title and how it was made.
void write_introduction(std::ostream& md, const StudyOptions& study_options, bool simulated) {
  md << "# Reproduction of Kim, \"Position prediction using disturbance observer for planar pushing\"\n\n"
     << "Made by `pushpred reproduce` (pushpred " << kVersion << "). Schedule: " << study_options.schedule.intervals
     << " equal intervals over the **" << schedule_span_name(study_options.schedule.span)
     << "** span of each recording, identification on the first, then alternating; planned force sampled at "
     << study_options.plan_rate_hz << " Hz and held; observer `" << study_options.observer << "`";
  if (study_options.observer == "dob")
    md << " (run " << observer_run_name(study_options.observer_run) << ", start "
       << observer_start_name(study_options.observer_options.start) << ", output "
       << observer_output_name(study_options.observer_options.output) << "; docs/reproduction.md)";
  md << ", relation estimator `" << study_options.estimator
     << "`; the simple algorithm uses mu = 0.14 on abs. Prediction methods: "
     << markdown_method_list(study_options.methods) << ".\n\n";
  if (simulated)
    md << "**The six rect2 cases are simulated.** The paper's rect2 recordings are not among the real files in the "
          "data folder, so each case of its Table I is simulated from `data/paper/case<n>.json` (`pushpred simulate "
          "--case N`), with sensor noise and clock jitter measured on the real recordings (docs/simulator.md). The "
          "recordings used are in `cases/`. Numbers for these cases therefore test the method on a known physics, "
          "not the paper's data; the real-data study follows in the second part.\n\n";
}

/// Table I (the cases, the paper's and as measured here) and Table II (the measurements).
void write_tables(std::ostream& md, const std::vector<SynchronisedPush>& pushes, bool simulated) {
  md << "## Table I: push data cases\n\n| case | acceleration [m/s^2] (paper) | velocity [m/s] (paper) | acceleration "
        "[m/s^2] (here) | velocity [m/s] (here) | peak tip speed [mm/s] (measured) | duration [s] | object travel [mm] "
        "| object rotation [deg] |\n|---|---|---|---|---|---|---|---|---|\n";
  for (int n = 1; n <= 6; ++n) {
    const SynchronisedPush& p = pushes[n - 1];
    const Eigen::Index last = p.size() - 1;
    md << "| " << n << " | " << kPaperTableI[n - 1].acceleration_m_s2 << " | " << kPaperTableI[n - 1].velocity_m_s
       << " | " << p.push.acceleration_m_s2 << " | " << p.push.speed_m_s << " | "
       << fmt("%.1f", kMm * peak_tip_speed_m_s(p)) << " | " << fmt("%.2f", p.duration_s()) << " | "
       << fmt("%.1f", kMm * (p.pose.row(last).head<2>() - p.pose.row(0).head<2>()).norm()) << " | "
       << fmt("%.1f", kDeg * (p.pose(last, 2) - p.pose(0, 2))) << " |\n";
  }
  md << "\nAcceleration and velocity (here) are the pusher's commanded motion: "
     << (simulated ? "the scenario's (`data/paper/case<n>.json`)" : "from each file's name")
     << "; as in the paper and the dataset's file names, velocity -0.001 marks an acceleration push. The peak tip "
        "speed is measured on the recording: the largest tip displacement over "
     << tip_speed_step(pushes[0]) << " grid samples (" << fmt("%.0f", 1e3 * tip_speed_step(pushes[0]) / pushes[0].rate_hz)
     << " ms) divided by their time. Duration, travel (start to end of the recording) and rotation are measured on "
        "the recording too.\n";
  md << "\n## Table II: measurements\n\n| measurement | definition | here |\n|---|---|---|\n"
     << "| r_C^{rbt} | the tip position in {rbt} | `tip_pose` x, y, rotated by C(theta_tip) into {R} |\n"
     << "| theta_tip | the tip orientation with respect to {R} | `tip_pose` yaw |\n"
     << "| r_O'^{R} | the object centre position in {R} | `object_pose` x, y |\n"
     << "| theta | the object orientation with respect to {R} | `object_pose` yaw, unwrapped |\n"
     << "| -f_C^{rbt} | the reaction force measured at the tip in {rbt} | `ft_wrench` fx, fy; f_C is its negative |\n"
     << "| -T_C^{rbt} | the reaction torque measured at the tip in {rbt} | `ft_wrench` tz; T_C is its negative |\n\n";
}

/// Figures 2 and 4: the observer against the PID reconstruction on case 1.
void write_figures_2_and_4(std::ostream& md, const Observation& obs, const StagedOutput& out,
                           std::vector<std::string>& notes) {
  for (const auto& f : observation_files(obs)) write_text_atomically(out.path("fig2_4/" + f.name), f.text);
  for (const auto& s : observation_plot_scripts()) {
    const PlotRun run = run_gnuplot(out.path("fig2_4/" + s));
    if (!run.drawn) notes.push_back("fig2_4/" + s + ": " + run.note);
  }
  md << "## Figures 2 and 4: the disturbance observer against the PID reconstruction (case 1)\n\n"
     << "![DOB and PID force and torque](fig2_4/forces.png)\n\n![pose re-simulated from the estimated total force]"
        "(fig2_4/trajectory.png)\n\n```\n"
     << observation_summary(obs) << "```\n\n";
}

/// Figure 5: u against d_hat over all cases, with the least-squares lines and each case's RLS fit.
void write_figure_5(std::ostream& md, const std::vector<DisturbanceEstimate>& estimates, const RelationParameters& all,
                    const std::vector<PushStudy>& cases, const StagedOutput& out, std::vector<std::string>& notes) {
  std::ostringstream dat;
  dat << "# case u_x d_x u_y d_y u_rot d_rot  [N, N, N, N, N m, N m]\n";
  for (int n = 1; n <= 6; ++n) {
    const DisturbanceEstimate& e = estimates[n - 1];
    for (Eigen::Index k = 0; k < e.t_s.size(); k += 2)
      dat << n << " " << e.u(k, 0) << " " << e.d_hat(k, 0) << " " << e.u(k, 1) << " " << e.d_hat(k, 1) << " "
          << e.u(k, 2) << " " << e.d_hat(k, 2) << "\n";
  }
  write_text_atomically(out.path("fig5.dat"), dat.str());
  std::ostringstream gp;
  gp << png_terminal("fig5.png", 1500, 560) << "set multiplot layout 1,3\nset key below horizontal maxcols 4\n";
  const char* titles[3] = {"x force", "y force", "torque about the centre"};
  const char* xlabels[3] = {"applied input u_x [N]", "applied input u_y [N]", "applied input u_rot [N m]"};
  const char* ylabels[3] = {"estimated disturbance d_x [N]", "estimated disturbance d_y [N]",
                            "estimated disturbance d_rot [N m]"};
  gp << "set termoption noenhanced\n";
  for (int c = 0; c < 3; ++c)
    gp << "set title " << gnuplot_quoted(titles[c]) << "\nset xlabel " << gnuplot_quoted(xlabels[c]) << "\nset ylabel "
       << gnuplot_quoted(ylabels[c]) << "\n"
       << "plot for [n=1:6] 'fig5.dat' using ($1==n ? $" << 2 + 2 * c << " : 1/0):" << 3 + 2 * c
       << " with points pt 7 ps 0.3 title sprintf('case %d', n), " << all.beta(c) << "*x + " << all.eps(c)
       << " with lines lw 2 lc 'black' title 'fit over all cases'\n";
  gp << "unset multiplot\n";
  draw(out, "fig5.gp", gp.str(), notes);
  md << "## Figure 5: applied input against estimated disturbance\n\n![u against d_hat](fig5.png)\n\n"
     << "Least-squares lines over all six cases (every observer sample), and the RLS fit of each case after its "
        "last identification interval:\n\n| | beta x | eps x [N] | beta y | eps y [N] | beta rot | eps rot [N m] |\n"
        "|---|---|---|---|---|---|---|\n"
     << "| all cases | " << fmt("%.3f", all.beta(0)) << " | " << fmt("%.3f", all.eps(0)) << " | "
     << fmt("%.3f", all.beta(1)) << " | " << fmt("%.3f", all.eps(1)) << " | " << fmt("%.3f", all.beta(2)) << " | "
     << fmt("%.5f", all.eps(2)) << " |\n";
  for (int n = 1; n <= 6; ++n) {
    const RelationParameters& p = cases[n - 1].phases.back().relation;
    md << "| case " << n << " | " << fmt("%.3f", p.beta(0)) << " | " << fmt("%.3f", p.eps(0)) << " | "
       << fmt("%.3f", p.beta(1)) << " | " << fmt("%.3f", p.eps(1)) << " | " << fmt("%.3f", p.beta(2)) << " | "
       << fmt("%.5f", p.eps(2)) << " |\n";
  }
  md << "\nThe paper finds beta near -1 (the unknown force cancels most of the applied one, as it must for "
        "pushes at constant velocity) and the same lines for all cases, with the accelerating cases 5 and 6 "
        "spreading away from the main cluster.\n\n";
}

/// Figure 6: the switching between identification and prediction (case 1, x channel).
void write_figure_6(std::ostream& md, const PushStudy& s, const SynchronisedPush& p,
                    const std::vector<PlannedForce>& plans, const StagedOutput& out, std::vector<std::string>& notes) {
  std::ostringstream dat;
  dat << "# t_s measured_fx_N planned_fx_N dhat_x_N (planned only in prediction phases, d_hat in identification)\n";
  const Eigen::MatrixX3d u = p.applied_input();
  for (Eigen::Index k = 0; k < p.size(); ++k) {
    const double t = p.t_s(k);
    std::string planned = "NaN", dhat = "NaN";
    for (const auto& plan : plans)
      if (t >= plan.t0_s && t < plan.t1_s) planned = std::to_string(plan.signal(t)(0));
    for (const auto& id : s.identification)
      if (id.t_s.size() && t >= id.t_s(0) && t <= id.t_s(id.t_s.size() - 1))
        dhat = std::to_string(id.d_hat(std::min<Eigen::Index>(id.t_s.size() - 1, p.index_at(t) - p.index_at(id.t_s(0))), 0));
    dat << t << " " << u(k, 0) << " " << planned << " " << dhat << "\n";
  }
  write_text_atomically(out.path("fig6.dat"), dat.str());
  std::ostringstream gp;
  gp << png_terminal("fig6.png", 1200, 500) << "set xlabel 'time [s]'\nset ylabel 'x force [N]'\nset key outside\n";
  for (const auto& iv : s.intervals) gp << "set arrow from " << iv.t0_s << ", graph 0 to " << iv.t0_s << ", graph 1 nohead dt 3\n";
  gp << "plot 'fig6.dat' using 1:2 with lines lc 'blue' title 'measured f_x', '' using 1:3 with steps lw 2 lc "
        "'magenta' title 'planned f_x (10 Hz, held)', '' using 1:4 with lines dt 2 lw 2 lc 'red' title 'd hat "
        "(identification)'\n";
  draw(out, "fig6.gp", gp.str(), notes);
  md << "## Figure 6: identification and prediction alternate (case 1)\n\n![switching](fig6.png)\n\n";
}

/// Figures 7 and 8: the prediction errors of dob and simple per case and per phase.
void write_figures_7_and_8(std::ostream& md, const std::vector<PushStudy>& cases, const StagedOutput& out,
                           std::vector<std::string>& notes) {
  md << "## Figure 7: mean and standard deviation of the prediction errors per case\n\n"
     << "Means over the three prediction phases of each case.\n\n";
  std::ostringstream dat;
  dat << "# case dob_x dob_x_std simple_x simple_x_std dob_y dob_y_std simple_y simple_y_std dob_th dob_th_std "
         "simple_th simple_th_std\n";
  for (const std::string method : {"dob", "simple"}) {
    md << "**" << method << "**\n\n" << kErrorsHeader;
    for (int n = 1; n <= 6; ++n) md << errors_row("case " + std::to_string(n), phase_mean(cases[n - 1], method));
    md << "\n";
  }
  for (int n = 1; n <= 6; ++n) {
    const PredictionErrors d = phase_mean(cases[n - 1], "dob"), s = phase_mean(cases[n - 1], "simple");
    dat << n << " " << d.x_mm_mean << " " << d.x_mm_std << " " << s.x_mm_mean << " " << s.x_mm_std << " " << d.y_mm_mean
        << " " << d.y_mm_std << " " << s.y_mm_mean << " " << s.y_mm_std << " " << d.theta_deg_mean << " "
        << d.theta_deg_std << " " << s.theta_deg_mean << " " << s.theta_deg_std << "\n";
  }
  write_text_atomically(out.path("fig7.dat"), dat.str());
  std::ostringstream gp;
  gp << png_terminal("fig7.png", 1500, 500)
     << "set multiplot layout 1,3\nset style data histogram\nset style histogram errorbars gap 2 lw 1\nset style "
        "fill solid 0.6\nset logscale y\nset xlabel 'case'\n";
  const char* labels[3] = {"x error [mm]", "y error [mm]", "yaw error [deg]"};
  for (int c = 0; c < 3; ++c)
    gp << "set ylabel " << gnuplot_quoted(labels[c]) << "\nplot 'fig7.dat' using " << 2 + 4 * c << ":" << 3 + 4 * c
       << ":xtic(1) title 'proposed (dob)', '' using " << 4 + 4 * c << ":" << 5 + 4 * c << " title 'simple'\n";
  gp << "unset multiplot\n";
  draw(out, "fig7.gp", gp.str(), notes);
  md << "![errors per case](fig7.png)\n\n## Figure 8: prediction errors in every phase\n\n"
     << "| case | phase | dob x [mm] | dob y [mm] | dob yaw [deg] | simple x [mm] | simple y [mm] | simple yaw [deg] |\n"
        "|---|---|---|---|---|---|---|---|\n";
  std::ostringstream dat8;
  dat8 << "# case phase dob_pos_mm simple_pos_mm dob_th simple_th\n";
  for (int n = 1; n <= 6; ++n)
    for (const auto& ph : cases[n - 1].phases) {
      const auto& d = ph.errors.at("dob");
      const auto& s = ph.errors.at("simple");
      md << "| " << n << " | " << ph.phase << " | " << fmt("%.2f", d.x_mm_mean) << " | " << fmt("%.2f", d.y_mm_mean)
         << " | " << fmt("%.2f", d.theta_deg_mean) << " | " << fmt("%.2f", s.x_mm_mean) << " | "
         << fmt("%.2f", s.y_mm_mean) << " | " << fmt("%.2f", s.theta_deg_mean) << " |\n";
      dat8 << n << " " << ph.phase << " " << mean_position_error(d) << " " << mean_position_error(s) << " "
           << d.theta_deg_mean << " " << s.theta_deg_mean << "\n";
    }
  write_text_atomically(out.path("fig8.dat"), dat8.str());
  std::ostringstream gp8;
  gp8 << png_terminal("fig8.png", 1200, 500)
      << "set multiplot layout 1,2\nset logscale y\nset xlabel 'prediction phase'\nset xtics 1\nset key outside\n"
      << "set ylabel 'mean position error [mm]'\nplot for [n=1:6] 'fig8.dat' using ($1==n ? $2 : 1/0):3 with "
         "linespoints title sprintf('dob, case %d', n), for [n=1:6] '' using ($1==n ? $2 : 1/0):4 with linespoints "
         "dt 2 title sprintf('simple, case %d', n)\n"
      << "set ylabel 'mean yaw error [deg]'\nplot for [n=1:6] 'fig8.dat' using ($1==n ? $2 : 1/0):5 with linespoints "
         "title sprintf('dob, case %d', n), for [n=1:6] '' using ($1==n ? $2 : 1/0):6 with linespoints dt 2 title "
         "sprintf('simple, case %d', n)\nunset multiplot\n";
  draw(out, "fig8.gp", gp8.str(), notes);
  md << "\n![errors per phase](fig8.png)\n\n";
}

/// Figure 9: dob's best prediction among the phases in which the object moves.
void write_figure_9(std::ostream& md, const std::vector<PushStudy>& cases, const StagedOutput& out,
                    std::vector<std::string>& notes) {
  int best_case = 1;
  const PhaseResult* best = nullptr;
  // Among phases in which the object moves (at least 5 mm): a phase at rest is trivially "predicted".
  for (int n = 1; n <= 6; ++n)
    for (const auto& ph : cases[n - 1].phases) {
      const Eigen::Index last = ph.measured.rows() - 1;
      const double travel_mm = kMm * (ph.measured.row(last).head<2>() - ph.measured.row(0).head<2>()).norm();
      if (travel_mm < 5.0) continue;
      if (!best || mean_position_error(ph.errors.at("dob")) < mean_position_error(best->errors.at("dob"))) {
        best = &ph;
        best_case = n;
      }
    }
  if (!best) throw InputError("reproduce: no prediction phase of the six cases moves the object");
  std::ostringstream dat;
  dat << "# t_s measured_x_mm measured_y_mm measured_theta_deg dob_x dob_y dob_theta simple_x simple_y simple_theta\n";
  for (Eigen::Index j = 0; j < best->t_s.size(); ++j) {
    dat << best->t_s(j);
    for (const Eigen::MatrixX3d* m : {&best->measured, &best->predicted.at("dob"), &best->predicted.at("simple")})
      dat << " " << kMm * (*m)(j, 0) << " " << kMm * (*m)(j, 1) << " " << kDeg * (*m)(j, 2);
    dat << "\n";
  }
  write_text_atomically(out.path("fig9.dat"), dat.str());
  // The axes are set by the measured and the dob curves; a curve that leaves them (simple's often diverges by
  // metres) is clipped at the frame, and its key says how far it goes, so that it cannot flatten the others.
  const FigureRange x = figure_range({&best->measured, &best->predicted.at("dob")}, 0, kMm),
                    y = figure_range({&best->measured, &best->predicted.at("dob")}, 1, kMm),
                    yaw = figure_range({&best->measured, &best->predicted.at("dob")}, 2, kDeg);
  const FigureRange ranges[3] = {x, y, yaw};
  const Eigen::MatrixX3d& simple = best->predicted.at("simple");
  std::ostringstream gp;
  gp << png_terminal("fig9.png", 1500, 450)
     << "set termoption noenhanced\nset multiplot layout 1,3\nset xlabel 'time [s]'\nset key bottom\n";
  const char* labels[3] = {"x [mm]", "y [mm]", "yaw [deg]"};
  const char* units[3] = {"mm", "mm", "deg"};
  const double scale[3] = {kMm, kMm, kDeg};
  for (int c = 0; c < 3; ++c) {
    const double lo = scale[c] * simple.col(c).minCoeff(), hi = scale[c] * simple.col(c).maxCoeff();
    std::string simple_title = "simple";
    if (lo < ranges[c].lo || hi > ranges[c].hi)
      simple_title += " (clipped; it spans " + fmt("%.0f", lo) + " to " + fmt("%.0f", hi) + " " + units[c] + ")";
    gp << "set ylabel " << gnuplot_quoted(labels[c]) << "\nset yrange [" << ranges[c].lo << ":" << ranges[c].hi
       << "]\nplot 'fig9.dat' using 1:" << 2 + c << " with lines lw 2 lc 'black' title 'measured', '' using 1:" << 5 + c
       << " with lines lw 2 lc 'red' title 'proposed (dob)', '' using 1:" << 8 + c
       << " with lines dt 2 lc 'blue' title " << gnuplot_quoted(simple_title) << "\n";
  }
  gp << "unset multiplot\n";
  draw(out, "fig9.gp", gp.str(), notes);
  md << "## Figure 9: the best prediction\n\nAmong the phases in which the object moves at least 5 mm: case " << best_case << ", phase " << best->phase << " (mean x/y error "
     << fmt("%.2f", best->errors.at("dob").x_mm_mean) << "/" << fmt("%.2f", best->errors.at("dob").y_mm_mean)
     << " mm; the paper's best is the first phase of case 3).\n\n![best prediction](fig9.png)\n\n";
}

/// The paper's claims against the six cases' numbers, and the errors of every method over all their phases.
void write_claims(std::ostream& md, const std::vector<PushStudy>& cases) {
  const auto agg = aggregate_errors(cases);
  const PredictionErrors& d = agg.at("dob");
  const PredictionErrors& s = agg.at("simple");
  double worst_pos = 0, worst_theta = 0;
  for (const auto& st : cases)
    for (const auto& ph : st.phases) {
      worst_pos = std::max({worst_pos, ph.errors.at("dob").x_mm_mean, ph.errors.at("dob").y_mm_mean});
      worst_theta = std::max(worst_theta, ph.errors.at("dob").theta_deg_mean);
    }
  md << "## The paper's claims, checked on these cases\n\n"
     << "| claim | here |\n|---|---|\n"
     << "| the proposed errors are up to 10 times smaller than the simple algorithm's | simple / dob mean error: x "
     << fmt("%.1f", s.x_mm_mean / d.x_mm_mean) << "x, y " << fmt("%.1f", s.y_mm_mean / d.y_mm_mean) << "x, yaw "
     << fmt("%.1f", s.theta_deg_mean / d.theta_deg_mean) << "x |\n"
     << "| mean x and y errors well below 10 mm in every phase | worst phase mean " << fmt("%.2f", worst_pos)
     << " mm |\n"
     << "| mean yaw errors below 20 degrees | worst phase mean " << fmt("%.2f", worst_theta) << " deg |\n\n"
     << "Over all phases of the six cases:\n\n"
     << kErrorsHeader;
  for (const auto& name : cases.front().methods) md << errors_row(name, agg.at(name));
  md << "\n";
}

/// The section of the same study over every real ABS push, `files` of them.
void write_real_pushes(std::ostream& md, const Batch<PushStudy>& real, std::size_t files) {
  md << "# The same study over every real ABS push\n\n"
     << real.results.size() << " of " << files << " pushes predicted; the others are listed below with "
     << "the reason. Means over all phases of the pushes of each shape.\n\n";
  std::map<std::string, std::vector<PushStudy>> by_shape;
  for (const auto& s : real.results) by_shape[shape_of(s.source)].push_back(s);
  by_shape["all"] = real.results;
  md << "| shape | pushes | method | x [mm] | y [mm] | yaw [deg] | final position [mm] | final yaw [deg] |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const auto& [shape, studies] : by_shape) {
    if (studies.empty()) continue;
    const auto agg = aggregate_errors(studies);
    for (const auto& name : studies.front().methods) {
      const auto& e = agg.at(name);
      md << "| " << markdown_cell(shape) << " | " << studies.size() << " | " << markdown_cell(name) << " | "
         << fmt("%.2f", e.x_mm_mean) << " | " << fmt("%.2f", e.y_mm_mean) << " | " << fmt("%.2f", e.theta_deg_mean)
         << " | " << fmt("%.2f", e.final_pos_mm) << " | " << fmt("%.2f", e.final_theta_deg) << " |\n";
    }
  }
  md << "\nMean over phases of each phase's mean position error [mm] / yaw error [deg], per object and per pusher "
        "speed:\n\n"
     << grouped_errors_markdown(real.results);
  if (!real.failures.empty()) {
    md << "\nPushes left out:\n\n";
    for (const auto& f : real.failures)
      md << "- `" << std::filesystem::path(f.source).filename().string() << "`: " << f.reason << "\n";
  }
  md << "\n";
}

/// The best method on real data, on the push typical_real_push() chooses. Figure 10: x, y and yaw over time,
/// measured and predicted by quasi_static, dob and const_velocity in every phase; figure 11: the object's outline
/// seen from above at the start and end of every phase, measured and as each method predicts it.
void write_real_push_figures(std::ostream& md, const PaperReproduction& r, const StagedOutput& out,
                             std::vector<std::string>& notes) {
  const TypicalRealPush typical = typical_real_push(r.real);
  if (!typical.study || !r.typical_real_push) return;  // quasi_static not run (--methods), or no real push studied
  const std::string best_method = kTypicalPushMethod;
  const PushStudy& study = *typical.study;
  const std::string file = std::filesystem::path(study.source).filename().string();
  std::vector<std::string> methods;
  for (const std::string& m : {best_method, std::string("dob"), std::string("const_velocity")})
    if (std::find(study.methods.begin(), study.methods.end(), m) != study.methods.end()) methods.push_back(m);

  // Figure 10: one block per phase (blank lines between, so that no line joins two phases).
  std::ostringstream dat;
  dat << "# " << file << ": t_s, then x_mm y_mm yaw_deg measured and per method:";
  for (const auto& m : methods) dat << " " << m;
  dat << "\n";
  for (const PhaseResult& ph : study.phases) {
    for (Eigen::Index j = 0; j < ph.t_s.size(); ++j) {
      dat << ph.t_s(j);
      for (int c = 0; c < 3; ++c) dat << " " << (c < 2 ? kMm : kDeg) * ph.measured(j, c);
      for (const auto& m : methods)
        for (int c = 0; c < 3; ++c) dat << " " << (c < 2 ? kMm : kDeg) * ph.predicted.at(m)(j, c);
      dat << "\n";
    }
    dat << "\n\n";
  }
  write_text_atomically(out.path("fig10.dat"), dat.str());
  const char* colours[3] = {"'red'", "'blue'", "'dark-green'"};
  std::ostringstream gp;
  gp << png_terminal("fig10.png", 1500, 450) << "set termoption noenhanced\nset multiplot layout 1,3 title "
     << gnuplot_quoted(file) << "\nset xlabel 'time [s]'\nset key bottom\n";
  const char* labels[3] = {"x [mm]", "y [mm]", "yaw [deg]"};
  for (int c = 0; c < 3; ++c) {
    gp << "set ylabel " << gnuplot_quoted(labels[c]) << "\nplot 'fig10.dat' using 1:" << 2 + c
       << " with lines lw 2 lc 'black' title 'measured'";
    for (std::size_t m = 0; m < methods.size(); ++m)
      gp << ", '' using 1:" << 5 + 3 * m + static_cast<std::size_t>(c) << " with lines lw 1.5 lc " << colours[m]
         << " title " << gnuplot_quoted(methods[m]);
    gp << "\n";
  }
  gp << "unset multiplot\n";
  draw(out, "fig10.gp", gp.str(), notes);

  // Figure 11: the outline at the start and end of every phase; the predictions start from the measured pose.
  const SynchronisedPush& push = *r.typical_real_push;
  const std::vector<Eigen::Vector2d> outline = outline_polygon(push.shape, 36);
  std::ostringstream top;
  const auto outline_at = [&](const Eigen::MatrixX3d& pose, Eigen::Index j) {
    const double c = std::cos(pose(j, 2)), s = std::sin(pose(j, 2));
    for (std::size_t v = 0; v <= outline.size(); ++v) {
      const Eigen::Vector2d& q = outline[v % outline.size()];
      const Eigen::Vector2d p =
          pose.row(j).head<2>().transpose() + Eigen::Vector2d(c * q.x() - s * q.y(), s * q.x() + c * q.y());
      top << kMm * p.x() << " " << kMm * p.y() << "\n";
    }
    top << "\n\n";
  };
  top << "# " << file << ": the outline [mm] at the start and end of each phase; index 0 measured, then";
  for (const auto& m : methods) top << " " << m;
  top << " (ends of phases only)\n";
  for (const PhaseResult& ph : study.phases) outline_at(ph.measured, 0);  // index 0: measured, phase starts
  for (const PhaseResult& ph : study.phases) outline_at(ph.measured, ph.measured.rows() - 1);
  for (const auto& m : methods)
    for (const PhaseResult& ph : study.phases) outline_at(ph.predicted.at(m), ph.measured.rows() - 1);
  write_text_atomically(out.path("fig11.dat"), top.str());
  const std::size_t phases = study.phases.size();
  std::ostringstream gp11;
  gp11 << png_terminal("fig11.png", 1000, 900) << "set termoption noenhanced\nset size ratio -1\nset grid\n"
       << "set title " << gnuplot_quoted("from above: " + file) << "\nset xlabel 'x [mm]'\nset ylabel 'y [mm]'\n"
       << "set key outside right top\n"
       << "plot 'fig11.dat' index 0:" << phases - 1 << " with lines dt 3 lc 'gray' title 'measured, phase start', "
       << "'' index " << phases << ":" << 2 * phases - 1 << " with lines lw 2 lc 'black' title 'measured, phase end'";
  for (std::size_t m = 0; m < methods.size(); ++m)
    gp11 << ", '' index " << (2 + m) * phases << ":" << (3 + m) * phases - 1 << " with lines lw 1.5 lc " << colours[m]
         << " title " << gnuplot_quoted(methods[m] + ", phase end");
  gp11 << "\n";
  draw(out, "fig11.gp", gp11.str(), notes);

  md << "## Figures 10 and 11: the best method on a real push\n\n"
     << "The real push whose `" << best_method << "` error is the median of the " << typical.candidates
     << " studied pushes of objects with a listed outline (`" << file << "`, mean position error "
     << fmt("%.2f", typical.mean_position_error_mm)
     << " mm per phase): its pose over time, measured and predicted in every phase by";
  for (const auto& m : methods) md << " `" << m << "`";
  md << " (each prediction starts from the measured pose at its phase's start), and the object's outline seen from "
        "above at the start and end of each phase, measured and as each method predicts its end.\n\n"
     << "![the best method on a real push](fig10.png)\n\n![the outline from above](fig11.png)\n\n";
}

/// The plots gnuplot could not draw, and why.
void write_plot_notes(std::ostream& md, const std::vector<std::string>& notes) {
  if (!notes.empty()) {
    md << "## Plots not drawn\n\n";
    for (const auto& n : notes) md << "- " << n << "\n";
  }
}

/// summary.json: every study (the cases, then the real pushes), their errors by group.
void write_summary(const StagedOutput& out, const PaperReproduction& result) {
  const StudyOptions& study_options = result.study;
  Batch<PushStudy> all;
  all.results = result.cases;
  all.results.insert(all.results.end(), result.real.results.begin(), result.real.results.end());
  all.failures = result.real.failures;
  nlohmann::json summary = prediction_summary_json(all, study_options);
  nlohmann::json groups = nlohmann::json::object();
  for (const auto& [name, e] : aggregate_errors(result.cases)) groups["paper_cases"][name] = errors_json(e);
  for (const auto& [name, e] : aggregate_errors(result.real.results)) groups["real_abs"][name] = errors_json(e);
  summary["aggregate_by_group"] = groups;
  summary["paper_cases_simulated"] = result.simulated_cases;
  write_text_atomically(out.path("summary.json"), summary.dump(2) + "\n");
}

}  // namespace

TypicalRealPush typical_real_push(const Batch<PushStudy>& real) {
  std::vector<std::pair<double, const PushStudy*>> by_error;
  for (const PushStudy& s : real.results) {
    if (s.phases.empty() || std::find(s.methods.begin(), s.methods.end(), kTypicalPushMethod) == s.methods.end())
      continue;
    // Figure 11 draws the outline: among the objects whose outline the shape table lists (not butter).
    const std::string shape = shape_of(s.source);
    if (!ShapeTable::known().contains(shape) || !ShapeTable::known().find(shape).has_outline()) continue;
    double sum = 0;
    for (const PhaseResult& ph : s.phases) sum += mean_position_error(ph.errors.at(kTypicalPushMethod));
    by_error.emplace_back(sum / static_cast<double>(s.phases.size()), &s);
  }
  if (by_error.empty()) return {};
  std::sort(by_error.begin(), by_error.end(), [](const auto& a, const auto& b) {
    return a.first < b.first || (a.first == b.first && a.second->source < b.second->source);
  });
  const auto& median = by_error[(by_error.size() - 1) / 2];
  return {median.second, median.first, by_error.size()};
}

std::vector<std::string> write_reproduction_report(const PaperReproduction& r, const StagedOutput& out) {
  std::vector<std::string> notes;
  std::ostringstream md;
  write_introduction(md, r.study, r.simulated_cases);
  write_tables(md, r.case_pushes, r.simulated_cases);
  write_figures_2_and_4(md, r.case1_observation, out, notes);
  write_figure_5(md, r.case_disturbances, r.all_cases_relation, r.cases, out, notes);
  write_figure_6(md, r.cases[0], r.case_pushes[0], r.case1_plans, out, notes);
  write_figures_7_and_8(md, r.cases, out, notes);
  write_figure_9(md, r.cases, out, notes);
  write_claims(md, r.cases);
  if (r.real_studied) {
    write_real_pushes(md, r.real, r.real_files);
    write_real_push_figures(md, r, out, notes);
  }
  write_plot_notes(md, notes);
  write_text_atomically(out.path("report.md"), md.str());
  write_summary(out, r);
  return notes;
}

}  // namespace pushpred
