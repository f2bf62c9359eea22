#include "pushpred/reports/pid_fit_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "pushpred/core/version.hpp"
#include "pushpred/reports/markdown_table.hpp"

namespace pushpred {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

std::string short_name(const std::string& source) {
  const std::string name = std::filesystem::path(source).filename().string();
  return name.empty() ? source : name;
}

nlohmann::json gains_json(const PidGains& g) {
  return {{"kp_N_per_m", g.kp},          {"ki_N_per_m_s", g.ki},          {"kd_N_s_per_m", g.kd},
          {"lp_N_m_per_rad", g.lp},      {"li_N_m_per_rad_s", g.li},      {"ld_N_m_s_per_rad", g.ld}};
}

nlohmann::json solve_json(const PidFitSolve& s) {
  if (!s.fitted) return {{"fitted", false}};
  return {{"fitted", true},         {"cost_at_given_gains", s.given_cost}, {"start", s.start},
          {"start_cost", s.start_cost}, {"final_cost", s.final_cost},       {"iterations", s.iterations},
          {"termination", s.termination}};
}

nlohmann::json fit_json(const PidGainFit& f) {
  return {{"gains", gains_json(f.gains)},
          {"pushes", f.pushes},
          {"translation", solve_json(f.translation)},
          {"rotation", solve_json(f.rotation)}};
}

/// Per channel x, y, rotation: values in report units (mm, mm, deg or N, N, N mm).
nlohmann::json channels_json(const Eigen::Vector3d& v, double translation_scale, double rotation_scale) {
  return {{"x", v(0) * translation_scale}, {"y", v(1) * translation_scale}, {"rotation", v(2) * rotation_scale}};
}

nlohmann::json quality_json(const PidGainQuality& q) {
  const double n = static_cast<double>(q.samples), steps = static_cast<double>(std::max<long>(q.samples - 1, 1));
  return {{"samples", q.samples},
          {"tracking_mean_square", channels_json(q.tracking_sum / n, 1, 1)},
          {"roughness_mean_square", channels_json(q.roughness_sum / steps, 1, 1)},
          {"tracking_rms_mm_deg", channels_json(q.tracking_rms, 1e3, kRadToDeg)},
          {"roughness_rms_N_Nmm", channels_json(q.roughness_rms, 1, 1e3)},
          {"dob_difference_rms_N_Nmm", channels_json(q.dob_rms, 1, 1e3)},
          {"measured_input_roughness_rms_N_Nmm", channels_json(q.input_roughness_rms, 1, 1e3)}};
}

Eigen::Vector3d mean_of(const std::vector<const PidGainQuality*>& qs, Eigen::Vector3d PidGainQuality::*field) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (const PidGainQuality* q : qs) s += q->*field;
  return qs.empty() ? s : Eigen::Vector3d(s / static_cast<double>(qs.size()));
}

std::string fmt(const char* format, double v) { return table_number(format, v); }

}  // namespace

std::string pid_fit_forces_csv(const PidFitForces& forces) {
  const DisturbanceEstimate &paper = forces.paper, &fit = forces.fitted, &dob = forces.dob;
  std::ostringstream csv;
  csv << "t_s";
  for (const char* c : {"x_N", "y_N", "rot_Nm"})
    csv << ",u_" << c << ",d_hat_dob_" << c << ",d_hat_pid_paper_" << c << ",d_hat_pid_fitted_" << c;
  csv << "\n";
  char buf[64];
  for (Eigen::Index k = 0; k < paper.t_s.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%.6f", paper.t_s(k));
    csv << buf;
    for (int c = 0; c < 3; ++c)
      for (const double v : {paper.u(k, c), dob.d_hat(k, c), paper.d_hat(k, c), fit.d_hat(k, c)}) {
        std::snprintf(buf, sizeof buf, ",%.9g", v);
        csv << buf;
      }
    csv << "\n";
  }
  return csv.str();
}

nlohmann::json pid_fit_json(const PidFitStudy& s) {
  std::vector<const PidGainQuality*> paper, joint, own_paper, own;
  for (const auto& r : s.pushes) {
    paper.push_back(&r.paper);
    joint.push_back(&r.joint);
    if (r.own_quality) {
      own_paper.push_back(&r.paper);
      own.push_back(&*r.own_quality);
    }
  }
  const auto objective = [&](const std::vector<const PidGainQuality*>& qs) {
    nlohmann::json o = nlohmann::json::object();
    for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
      const PidObjectiveTerms t = pid_objective_terms(qs, problem);
      o[pid_fit_problem_name(problem)] = {{"tracking", t.tracking},
                                          {"roughness", t.roughness},
                                          {"objective", 0.5 * (t.tracking + s.roughness_weight * t.roughness)}};
    }
    return o;
  };
  nlohmann::json pushes = nlohmann::json::array();
  for (const auto& r : s.pushes) {
    nlohmann::json j = {{"source", r.source},
                        {"noise",
                         {{"pose_sigma_mm_deg", channels_json(r.noise.pose, 1e3, kRadToDeg)},
                          {"force_step_sigma_N_Nmm", channels_json(r.noise.force_step, 1, 1e3)},
                          {"rest_start_s", r.noise.rest_start_s},
                          {"rest_end_s", r.noise.rest_end_s},
                          {"rest_samples", r.noise.rest_samples}}},
                        {"paper", quality_json(r.paper)},
                        {"joint", quality_json(r.joint)}};
    if (r.own) {
      j["per_push_fit"] = fit_json(*r.own);
      j["per_push"] = quality_json(*r.own_quality);
    }
    pushes.push_back(j);
  }
  const auto listed = [](const std::vector<BatchFailure>& v) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& f : v) a.push_back({{"source", f.source}, {"reason", f.reason}});
    return a;
  };
  nlohmann::json out = {
      {"pushpred_version", kVersion},
      {"objective",
       {{"lambda", s.roughness_weight},
        {"definition", "1/2 sum_k,c [((r_meas - r_sim) / sigma_pose_c)^2 + lambda ((f_hat(k+1) - f_hat(k)) / "
                       "sigma_df_c)^2]; translation over x and y, rotation separately; see docs/pid_gains.md"}}},
      {"paper_gains", gains_json(PidGains{})},
      {"joint_fit", fit_json(s.joint)},
      {"objective_summed_over_pushes", {{"paper_gains", objective(paper)}, {"joint_gains", objective(joint)}}},
      {"pushes", pushes},
      {"skipped", listed(s.skipped)},
      {"failed", listed(s.failed)}};
  if (!own.empty()) {
    out["objective_summed_over_pushes"]["per_push_gains"] = objective(own);
    out["objective_summed_over_pushes"]["paper_gains_same_pushes"] = objective(own_paper);
  }
  return out;
}

// --- The Markdown report's sections, in the order it writes them.

namespace {

/// One row of the gains table; a gain at its lower clamp reads "floor".
void write_gain_row(std::ostringstream& md, const std::string& label, const PidGains& g) {
  md << "| " << markdown_cell(label);
  for (double v : {g.kp, g.ki, g.kd, g.lp, g.li, g.ld})
    md << " | " << (v <= kPidGainFloor * (1 + 1e-9) ? std::string("floor") : fmt("%.4g", v));
  md << " |\n";
}

/// The nearest-rank order statistic at `fraction` of each gain over the per-push fits (not empty).
PidGains gain_order_statistic(const std::vector<PidGains>& own_gains, double fraction) {
  PidGains g;
  for (double PidGains::*field :
       {&PidGains::kp, &PidGains::ki, &PidGains::kd, &PidGains::lp, &PidGains::li, &PidGains::ld}) {
    std::vector<double> v;
    for (const PidGains& o : own_gains) v.push_back(o.*field);
    std::sort(v.begin(), v.end());
    g.*field = v[static_cast<std::size_t>(fraction * static_cast<double>(v.size() - 1) + 0.5)];
  }
  return g;
}

void write_introduction(std::ostringstream& md, const PidFitStudy& s) {
  md << "# PID gains fitted by Ceres\n\n";
  md << "Objective (docs/pid_gains.md): 1/2 sum over samples and channels of ((r_meas - r_sim) / sigma_pose)^2 + "
        "lambda ((f_hat(k+1) - f_hat(k)) / sigma_df)^2, lambda = "
     << fmt("%g", s.roughness_weight)
     << "; sigma_pose and sigma_df measured on each push while the object rests at the start. "
     << s.pushes.size() << " push(es) fitted";
  if (!s.skipped.empty()) md << ", " << s.skipped.size() << " skipped";
  if (!s.failed.empty()) md << ", " << s.failed.size() << " failed";
  md << ".\n\n";
}

/// The paper's gains, the joint fit's, and the per-push fits' quartiles and each of them.
void write_gains_table(std::ostringstream& md, const PidFitStudy& s) {
  md << "## Gains\n\n";
  md << "| gains | kp [N/m] | ki [N/(m s)] | kd [N s/m] | lp [N m/rad] | li [N m/(rad s)] | ld [N m s/rad] |\n";
  md << "|---|---:|---:|---:|---:|---:|---:|\n";
  write_gain_row(md, "paper (trial and error)", PidGains{});
  write_gain_row(md, "joint fit over " + std::to_string(s.joint.pushes) + " push(es)", s.joint.gains);
  std::vector<PidGains> own_gains;
  for (const auto& r : s.pushes)
    if (r.own) own_gains.push_back(r.own->gains);
  if (!own_gains.empty()) {
    write_gain_row(md, "per push: lower quartile", gain_order_statistic(own_gains, 0.25));
    write_gain_row(md, "per push: median", gain_order_statistic(own_gains, 0.5));
    write_gain_row(md, "per push: upper quartile", gain_order_statistic(own_gains, 0.75));
  }
  for (const auto& r : s.pushes)
    if (r.own) write_gain_row(md, "per push: " + short_name(r.source), r.own->gains);
  md << "\n\"floor\": the gain ran to its lower clamp, 1e-6; the objective has no use for it there and its value is "
        "undetermined.\n";
}

/// The joint gains' PD part as poles and damping with the set's mean inertia, beside the paper's.
void write_pd_poles(std::ostringstream& md, const PidFitStudy& s) {
  const PidGains paper;
  const PidGains& g = s.joint.gains;
  const double m = s.mean_inertia(0), I = s.mean_inertia(2);
  md << "\nThe joint gains' PD part with the set's mean mass " << fmt("%.4g", m) << " kg and moment of inertia "
     << fmt("%.4g", I) << " kg m^2: translation poles at " << fmt("%.3g", std::sqrt(g.kp / m)) << " rad/s with damping "
     << fmt("%.2g", g.kd / (2 * std::sqrt(g.kp * m))) << ", rotation poles at " << fmt("%.3g", std::sqrt(g.lp / I))
     << " rad/s with damping " << fmt("%.2g", g.ld / (2 * std::sqrt(g.lp * I)))
     << " (the paper's: " << fmt("%.3g", std::sqrt(paper.kp / m)) << " rad/s, "
     << fmt("%.2g", paper.kd / (2 * std::sqrt(paper.kp * m))) << "; ld / I = " << fmt("%.3g", paper.ld / I)
     << " 1/s).\n";
}

void write_joint_solves(std::ostringstream& md, const PidFitStudy& s) {
  md << "\nCeres, joint fit:\n\n";
  for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
    const PidFitSolve& f = problem == PidFitProblem::Translation ? s.joint.translation : s.joint.rotation;
    if (!f.fitted) {
      md << "- " << pid_fit_problem_name(problem) << ": not fitted\n";
      continue;
    }
    md << "- " << pid_fit_problem_name(problem) << ": cost " << fmt("%.6g", f.given_cost) << " at the paper's gains; "
       << "started from the " << f.start << " (cost " << fmt("%.6g", f.start_cost) << "); " << f.iterations
       << " iterations to " << fmt("%.6g", f.final_cost) << " (" << f.termination << ")\n";
  }
}

/// Each push's quality with the paper's gains, the joint gains and (where fitted) its own.
struct QualitiesByGains {
  std::vector<const PidGainQuality*> paper, joint, own;
};

QualitiesByGains qualities_by_gains(const PidFitStudy& s) {
  QualitiesByGains q;
  for (const auto& r : s.pushes) {
    q.paper.push_back(&r.paper);
    q.joint.push_back(&r.joint);
    if (r.own_quality) q.own.push_back(&*r.own_quality);
  }
  return q;
}

void write_objective_row(std::ostringstream& md, const PidFitStudy& s, PidFitProblem problem, const std::string& label,
                         const std::vector<const PidGainQuality*>& qs) {
  if (qs.empty()) return;
  const PidObjectiveTerms t = pid_objective_terms(qs, problem);
  double samples = 0, steps = 0;
  for (const PidGainQuality* q : qs) {
    samples += static_cast<double>(pid_fit_channels(problem).count * q->samples);
    steps += static_cast<double>(pid_fit_channels(problem).count * (q->samples - 1));
  }
  md << "| " << markdown_cell(pid_fit_problem_name(problem)) << " | " << markdown_cell(label) << " | "
     << fmt("%.4g", t.tracking) << " | " << fmt("%.4g", t.tracking / samples) << " | " << fmt("%.4g", t.roughness)
     << " | " << fmt("%.4g", t.roughness / steps) << " | "
     << fmt("%.4g", 0.5 * (t.tracking + s.roughness_weight * t.roughness)) << " |\n";
}

void write_objective_table(std::ostringstream& md, const PidFitStudy& s, const QualitiesByGains& q) {
  md << "\n## Objective, summed over the pushes\n\n"
        "tracking = sum of ((r_meas - r_sim) / sigma_pose)^2, roughness = sum of ((f_hat(k+1) - f_hat(k)) / "
        "sigma_df)^2; per sample (per step): divided by the channel-samples (channel-steps), 1 when the PID "
        "tracks at the pose noise and f_hat is as rough as the force noise.\n\n";
  md << "| problem | gains | tracking | per sample | roughness | per step | objective |\n"
        "|---|---|---:|---:|---:|---:|---:|\n";
  for (const PidFitProblem problem : {PidFitProblem::Translation, PidFitProblem::Rotation}) {
    write_objective_row(md, s, problem, "paper", q.paper);
    write_objective_row(md, s, problem, "joint fit", q.joint);
    if (q.own.size() == s.pushes.size()) write_objective_row(md, s, problem, "per-push fits", q.own);
  }
}

/// The tracking, roughness and d_hat-vs-dob cells of a row of the force tables, in mm, deg, N and N mm.
void write_quality_cells(std::ostringstream& md, const Eigen::Vector3d& track, const Eigen::Vector3d& rough,
                         const Eigen::Vector3d& dob) {
  md << " | " << fmt("%.3f", 1e3 * track(0)) << " | " << fmt("%.3f", 1e3 * track(1)) << " | "
     << fmt("%.3f", kRadToDeg * track(2)) << " | " << fmt("%.4f", rough(0)) << " | " << fmt("%.4f", rough(1)) << " | "
     << fmt("%.3f", 1e3 * rough(2)) << " | " << fmt("%.4f", dob(0)) << " | " << fmt("%.4f", dob(1)) << " | "
     << fmt("%.3f", 1e3 * dob(2)) << " |\n";
}

void write_mean_quality_row(std::ostringstream& md, const std::string& label,
                            const std::vector<const PidGainQuality*>& qs) {
  if (qs.empty()) return;
  md << "| " << markdown_cell(label);
  write_quality_cells(md, mean_of(qs, &PidGainQuality::tracking_rms), mean_of(qs, &PidGainQuality::roughness_rms),
                      mean_of(qs, &PidGainQuality::dob_rms));
}

/// How many pushes' d_hat is closer to the observer's in channel c with the joint (or their own) gains than with
/// the paper's.
std::string closer_to_observer(const PidFitStudy& s, bool own, int c) {
  int n = 0;
  for (const auto& r : s.pushes) {
    const PidGainQuality* q = own ? (r.own_quality ? &*r.own_quality : nullptr) : &r.joint;
    if (q && q->dob_rms(c) < r.paper.dob_rms(c)) ++n;
  }
  return std::to_string(n);
}

/// The median over the pushes of the measured input's step RMS over sigma_df, per channel.
void write_input_roughness_ratio(std::ostringstream& md, const PidFitStudy& s) {
  std::vector<double> ratio[3];
  for (const auto& r : s.pushes)
    for (int c = 0; c < 3; ++c) ratio[c].push_back(r.paper.input_roughness_rms(c) / r.noise.force_step(c));
  md << "Median over the pushes of the measured input's step RMS over sigma_df (x, y, rotation):";
  for (int c = 0; c < 3; ++c) {
    std::sort(ratio[c].begin(), ratio[c].end());
    md << (c ? ", " : " ") << fmt("%.3g", ratio[c][ratio[c].size() / 2]);
  }
  md << ".\n";
}

void write_force_changes(std::ostringstream& md, const PidFitStudy& s, const QualitiesByGains& q) {
  md << "\n## What changes in the reconstructed force (mean over the pushes)\n\n"
        "Tracking: RMS of r_meas - r_sim. Roughness: RMS of f_hat(k+1) - f_hat(k) (one 4 ms grid step). "
        "d_hat vs dob: RMS of the PID's d_hat minus the disturbance observer's.\n\n";
  md << "| gains | tracking x [mm] | y [mm] | theta [deg] | roughness x [N] | y [N] | rot [N mm] | d_hat vs dob x [N] "
        "| y [N] | rot [N mm] |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  write_mean_quality_row(md, "paper", q.paper);
  write_mean_quality_row(md, "joint fit", q.joint);
  if (q.own.size() == s.pushes.size()) write_mean_quality_row(md, "per-push fits", q.own);
  const Eigen::Vector3d u_rough = mean_of(q.paper, &PidGainQuality::input_roughness_rms);
  md << "| measured input u, for comparison | | | | " << fmt("%.4f", u_rough(0)) << " | " << fmt("%.4f", u_rough(1))
     << " | " << fmt("%.3f", 1e3 * u_rough(2)) << " | | | |\n";
  md << "\nPushes whose d_hat is closer to the observer's than with the paper's gains (x, y, rotation): joint gains "
     << closer_to_observer(s, false, 0) << ", " << closer_to_observer(s, false, 1) << ", "
     << closer_to_observer(s, false, 2) << " of " << s.pushes.size();
  if (!q.own.empty())
    md << "; per-push gains " << closer_to_observer(s, true, 0) << ", " << closer_to_observer(s, true, 1) << ", "
       << closer_to_observer(s, true, 2);
  md << ".\n";
  write_input_roughness_ratio(md, s);
}

/// Each push's rest noise, then its quality with each set of gains.
void write_per_push(std::ostringstream& md, const PidFitStudy& s) {
  md << "\n## Per push\n\n";
  md << "Noise during the rest at the start: sigma_pose x, y [mm], theta [deg]; sigma_df x, y [N], rot [N mm].\n\n";
  md << "| push | sigma_pose | sigma_df |\n|---|---|---|\n";
  for (const auto& r : s.pushes)
    md << "| " << markdown_cell(short_name(r.source)) << " | " << fmt("%.4f", 1e3 * r.noise.pose(0)) << ", "
       << fmt("%.4f", 1e3 * r.noise.pose(1)) << ", " << fmt("%.4f", kRadToDeg * r.noise.pose(2)) << " | "
       << fmt("%.4f", r.noise.force_step(0)) << ", " << fmt("%.4f", r.noise.force_step(1)) << ", "
       << fmt("%.3f", 1e3 * r.noise.force_step(2)) << " |\n";
  md << "\n| push | gains | tracking x [mm] | y [mm] | theta [deg] | roughness x [N] | y [N] | rot [N mm] | d_hat vs "
        "dob x [N] | y [N] | rot [N mm] |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : s.pushes) {
    const std::string name = short_name(r.source);
    const auto row = [&](const std::string& label, const PidGainQuality& q) {
      md << "| " << markdown_cell(name) << " | " << markdown_cell(label);
      write_quality_cells(md, q.tracking_rms, q.roughness_rms, q.dob_rms);
    };
    row("paper", r.paper);
    row("joint", r.joint);
    if (r.own_quality) row("own", *r.own_quality);
  }
}

void write_failure_list(std::ostringstream& md, const char* heading, const std::vector<BatchFailure>& failures) {
  if (failures.empty()) return;
  md << "\n## " << heading << "\n\n";
  for (const auto& f : failures) md << "- " << short_name(f.source) << ": " << f.reason << "\n";
}

}  // namespace

std::string pid_fit_markdown(const PidFitStudy& s) {
  std::ostringstream md;
  const QualitiesByGains q = qualities_by_gains(s);
  write_introduction(md, s);
  write_gains_table(md, s);
  write_pd_poles(md, s);
  write_joint_solves(md, s);
  write_objective_table(md, s, q);
  write_force_changes(md, s, q);
  write_per_push(md, s);
  write_failure_list(md, "Skipped", s.skipped);
  write_failure_list(md, "Failed", s.failed);
  return md.str();
}

}  // namespace pushpred
