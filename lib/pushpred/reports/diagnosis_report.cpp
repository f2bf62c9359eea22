#include "pushpred/reports/diagnosis_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <sstream>

#include "pushpred/core/error.hpp"
#include "pushpred/core/version.hpp"
#include "pushpred/reports/markdown_table.hpp"
#include "pushpred/reports/plotting.hpp"

namespace pushpred {
nlohmann::json error_summary_json(const ErrorSummary& e);

namespace {

constexpr double kDeg = 180.0 / M_PI;

std::string fixed(double v, int digits = 2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string general(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json effect_json(const EffectReport& r) {
  nlohmann::json parameters = nlohmann::json::object();
  for (std::size_t j = 0; j < r.parameter_info.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    parameters[r.parameter_info[j].name] = {
        {"value", J < r.theta.size() ? number_or_null(r.theta(J)) : nlohmann::json(nullptr)},
        {"std", J < r.theta_std.size() ? number_or_null(r.theta_std(J)) : nlohmann::json(nullptr)},
        {"unit", r.parameter_info[j].unit}};
  }
  nlohmann::json j = {{"kind", r.kind},
                      {"description", r.description},
                      {"test", effect_test_name(r.test)},
                      {"base_model", r.structural},
                      {"passed_test", r.passed_test},
                      {"negligible", r.negligible},
                      {"contradicted_by_motion", r.contradicted_by_motion},
                      {"stands_in_for_unexplained", r.stands_in_for_unexplained},
                      {"selected", r.selected},
                      {"score", number_or_null(r.score)},
                      {"parameters", parameters}};
  if (r.has_ablation) j["held_out_without"] = error_summary_json(r.held_out_without);
  if (r.has_fit_ablation) j["fit_without"] = error_summary_json(r.fit_without);
  if (!r.structural)
    j["amount"] = {{"value", number_or_null(r.amount)},
                   {"std", number_or_null(r.amount_std)},
                   {"unit", r.amount_unit},
                   {"floor", number_or_null(r.floor.amount)},
                   {"floor_basis", r.floor.basis}};
  if (r.has_setting) j["setting"] = {{"name", r.setting_info.name}, {"value", r.setting}, {"unit", r.setting_info.unit}};
  if (!r.derived.empty()) {
    nlohmann::json d = nlohmann::json::object();
    for (const auto& x : r.derived) d[x.name] = {{"value", number_or_null(x.value)}, {"unit", x.unit}};
    j["derived"] = d;
  }
  if (!r.note.empty()) j["note"] = r.note;
  return j;
}

std::string effect_parameters_text(const EffectReport& r) {
  std::string s;
  for (std::size_t j = 0; j < r.parameter_info.size(); ++j) {
    const auto J = static_cast<Eigen::Index>(j);
    if (J >= r.theta.size()) break;
    if (!s.empty()) s += ", ";
    s += r.parameter_info[j].name + " = " + general(r.theta(J));
    if (J < r.theta_std.size()) s += " ± " + general(r.theta_std(J));
    if (r.parameter_info[j].unit != "-") s += " " + r.parameter_info[j].unit;
  }
  if (r.has_setting) s += (s.empty() ? "" : "; ") + r.setting_info.name + " = " + general(r.setting) + " " + r.setting_info.unit;
  for (const auto& d : r.derived) s += "; " + d.name + " = " + general(d.value) + (d.unit == "-" ? "" : " " + d.unit);
  return s.empty() ? "—" : s;
}

std::string error_row(const std::string& name, const ErrorSummary& e) {
  return markdown_row({name, fixed(e.pos_mm_mean), fixed(e.x_mm_mean), fixed(e.y_mm_mean), fixed(e.theta_deg_mean),
                       fixed(e.final_pos_mm), fixed(e.final_theta_deg)});
}

/// Writes plots/NAME.gp and runs gnuplot on it (file names relative to the plots folder, so it can be rerun where
/// it lands); `note` gets why nothing was drawn.
std::vector<std::string> kinds_of(const DiagnosisResult& r, bool structural) {
  std::vector<std::string> out;
  for (const auto& e : r.effects)
    if (e.selected && e.structural == structural) out.push_back(e.kind);
  return out;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// Whether `after` is below both naive references, in position and in yaw.
struct BeatsReferences {
  bool pos = false, yaw = false;
  bool both() const { return pos && yaw; }
};
BeatsReferences beats_references(const ErrorSummary& after, const ErrorSummary& hold, const ErrorSummary& cv) {
  return {after.pos_mm_mean < std::min(hold.pos_mm_mean, cv.pos_mm_mean),
          after.theta_deg_mean < std::min(hold.theta_deg_mean, cv.theta_deg_mean)};
}
bool beats_both(const DiagnosisResult& r) { return beats_references(r.error_after, r.hold, r.const_velocity).both(); }

/// Mean position [mm] and yaw [deg] error of `method` over one traced phase.
std::pair<double, double> phase_means(const PhaseTrace& p, const std::string& method) {
  const Eigen::MatrixX3d& e = p.error.at(method);
  return {1e3 * e.leftCols<2>().rowwise().norm().mean(), kDeg * e.col(2).cwiseAbs().mean()};
}

/// The held-out phases one by one: how often the corrected model beats each reference, and the phases where it
/// loses to the better of the two (the start of tracing why), worst first.
std::string phase_by_phase(const DiagnosisResult& r) {
  if (r.test_phases.empty()) return "";
  int beats_hold = 0, beats_cv = 0, n = 0;
  struct Loss {
    const PhaseTrace* phase;
    double corrected_pos, corrected_yaw, best_pos, best_yaw, excess;
    std::string worse_in;
  };
  std::vector<Loss> losses;
  for (const auto& p : r.test_phases) {
    if (!p.error.count(kCorrectedMethod) || !p.error.count("hold") || !p.error.count("const_velocity")) continue;
    const auto [cp, cy] = phase_means(p, kCorrectedMethod);
    const auto [hp, hy] = phase_means(p, "hold");
    const auto [vp, vy] = phase_means(p, "const_velocity");
    ++n;
    beats_hold += cp < hp && cy < hy;
    beats_cv += cp < vp && cy < vy;
    const double bp = std::min(hp, vp), by = std::min(hy, vy);
    // Within 2 % (or 0.01 mm, 0.01 deg) of the reference is a tie: while the push goes on the corrected model and
    // const_velocity both keep the observer's velocity and differ only in the last digits.
    const bool worse_pos = cp > bp * 1.02 + 0.01, worse_yaw = cy > by * 1.02 + 0.01;
    if (worse_pos || worse_yaw) {
      std::string worse = worse_pos ? "position" : "";
      if (worse_yaw) worse += std::string(worse.empty() ? "" : " and ") + "yaw";
      // Excess in units of the phase's hold error, so millimetres and degrees weigh alike.
      const double excess = std::max(0.0, cp - bp) / std::max(hp, 1e-9) + std::max(0.0, cy - by) / std::max(hy, 1e-9);
      losses.push_back({&p, cp, cy, bp, by, excess, worse});
    }
  }
  std::ostringstream md;
  md << "## Phase by phase\n\n"
     << "Of the " << n << " held-out phases, the corrected model beats `hold` in both position and yaw in " << beats_hold
     << " and `const_velocity` in " << beats_cv << ".";
  if (losses.empty()) {
    md << " It loses to neither reference in any phase.\n\n";
    return md.str();
  }
  std::sort(losses.begin(), losses.end(), [](const Loss& a, const Loss& b) { return a.excess > b.excess; });
  md << " It loses to the better reference in " << losses.size()
     << " phase(s) by more than 2 %; the worst (mean errors over the phase, pos [mm] / yaw [deg]):\n\n"
     << markdown_header({"push", "phase", "starts at [s]", "corrected", "better reference", "worse in"});
  for (std::size_t k = 0; k < losses.size() && k < 10; ++k) {
    const Loss& l = losses[k];
    md << markdown_row({"`" + std::filesystem::path(l.phase->source).filename().string() + "`",
                        std::to_string(l.phase->phase), fixed(l.phase->t0_s),
                        fixed(l.corrected_pos) + " / " + fixed(l.corrected_yaw),
                        fixed(l.best_pos) + " / " + fixed(l.best_yaw), l.worse_in});
  }
  md << "\n";
  return md.str();
}

bool draw(const std::filesystem::path& folder, const std::string& name, const std::string& script, std::string& note) {
  const auto path = folder / "plots" / (name + ".gp");
  write_text_atomically(path, script);
  const PlotRun run = run_gnuplot(path);
  if (!run.drawn) note = run.note;
  return run.drawn;
}

/// Residual before/after of the first fit push: one panel per channel.
bool plot_residuals(const ResidualTrace& r, const std::filesystem::path& folder, const std::string& name, std::string& note) {
  std::ostringstream data;
  data.precision(8);
  for (Eigen::Index k = 0; k < r.t_s.size(); ++k) {
    data << r.t_s(k);
    for (int c = 0; c < 3; ++c)
      data << " " << r.before(k, c) << " " << r.after(k, c) << " " << (r.friction.rows() ? r.friction(k, c) : 0.0);
    data << "\n";
  }
  const auto data_path = folder / "plots" / (name + ".dat");
  write_text_atomically(data_path, data.str());
  std::ostringstream gp;
  gp << png_terminal(name + ".png", 900, 800)
     << "set multiplot layout 3,1 title "
     << gnuplot_quoted("Residual of the disturbance regression: " + std::filesystem::path(r.source).filename().string())
     << " noenhanced font 'sans,9'\n"
     << "set grid\nset key top right\n";
  const char* labels[3] = {"x [N]", "y [N]", "rotation [N m]"};
  for (int c = 0; c < 3; ++c) {
    gp << "set ylabel '" << labels[c] << "'\n" << (c == 2 ? "set xlabel 't [s]'\n" : "unset xlabel\n");
    gp << "plot " << gnuplot_quoted(name + ".dat") << " using 1:" << 2 + 3 * c
       << " with lines lw 1 title 'paper relation', " << gnuplot_quoted(name + ".dat") << " using 1:" << 3 + 3 * c
       << " with lines lw 1 title 'relation + effects'";
    if (r.friction.rows())
      gp << ", " << gnuplot_quoted(name + ".dat") << " using 1:" << 4 + 3 * c
         << " with lines lw 1 title 'friction law + effects'";
    gp << "\n";
  }
  gp << "unset multiplot\n";
  return draw(folder, name, gp.str(), note);
}

/// Prediction errors over time of the test phases of the first test push.
bool plot_test_errors(const std::vector<PhaseTrace>& phases, const std::filesystem::path& folder, const std::string& name,
                      std::string& note) {
  if (phases.empty()) return false;
  const std::string source = phases.front().source;
  const std::vector<std::string> methods{"dob", kCorrectedMethod, "hold", "const_velocity"};
  std::ostringstream data;
  data.precision(8);
  for (const auto& p : phases) {
    if (p.source != source) continue;
    for (Eigen::Index k = 0; k < p.t_s.size(); ++k) {
      data << p.t0_s + p.t_s(k);
      for (const auto& m : methods) {
        const auto& e = p.error.at(m);
        data << " " << 1e3 * e.row(k).head<2>().norm() << " " << kDeg * e(k, 2);
      }
      data << "\n";
    }
    data << "\n";  // a gap between phases
  }
  const auto data_path = folder / "plots" / (name + ".dat");
  write_text_atomically(data_path, data.str());
  std::ostringstream gp;
  gp << png_terminal(name + ".png", 900, 600)
     << "set multiplot layout 2,1 title "
     << gnuplot_quoted("Prediction error, test phases of " + std::filesystem::path(source).filename().string())
     << " noenhanced font 'sans,9'\n"
     << "set grid\nset key top left\n";
  for (int panel = 0; panel < 2; ++panel) {
    gp << "set ylabel '" << (panel == 0 ? "position error [mm]" : "yaw error [deg]") << "'\n"
       << (panel == 1 ? "set xlabel 't [s]'\n" : "unset xlabel\n") << "plot ";
    for (std::size_t m = 0; m < methods.size(); ++m)
      gp << (m ? ", " : "") << gnuplot_quoted(name + ".dat") << " using 1:" << 2 + 2 * m + panel << " with lines lw 1.5 title '"
         << methods[m] << "' noenhanced";
    gp << "\n";
  }
  gp << "unset multiplot\n";
  return draw(folder, name, gp.str(), note);
}

}  // namespace

std::vector<std::string> effects_found(const DiagnosisResult& r) { return kinds_of(r, false); }

namespace {
/// "force_offset 0.40 ± 0.01 N (held-out change +0.1 mm)": a found effect's amount and what it changes on the test
/// phases (the corrected model with it, less the model without it).
std::string found_effect_text(const DiagnosisResult& r, const EffectReport& e) {
  std::string s = e.kind + " " + general(e.amount) + (e.amount_unit == "-" ? "" : " " + e.amount_unit);
  if (e.theta_std.size() == 1) s += " ± " + general(e.theta_std(0)) + (e.amount_unit == "-" ? "" : " " + e.amount_unit);
  if (e.has_ablation) {
    const double change = r.error_after.pos_mm_mean - e.held_out_without.pos_mm_mean;
    s += " (held-out change " + std::string(change >= 0 ? "+" : "") + fixed(change) + " mm";
    s += change >= 0 ? ": found, but it does not help prediction)" : ")";
  }
  return s;
}
}  // namespace

std::string findings_text(const DiagnosisResult& r) {
  std::vector<std::string> found, negligible, contradicted, stand_ins;
  for (const auto& e : r.effects) {
    if (e.structural) continue;
    if (e.selected) found.push_back(found_effect_text(r, e));
    else if (e.negligible) negligible.push_back(e.kind);
    else if (e.contradicted_by_motion) contradicted.push_back(e.kind);
    else if (e.stands_in_for_unexplained)
      stand_ins.push_back(e.kind);
  }
  const ModelAdequacy& a = r.adequacy;
  const bool unexplained = a.tested && !a.explained;
  std::string s;
  if (found.empty())
    s = unexplained ? a.verdict() + "; no effect of the catalogue explains it"
        : a.tested  ? "nothing found, residual explained: no physical effect beyond the base model, and what is left "
                      "is what noise leaves"
                    : "nothing found: no physical effect beyond the base model explains the residual";
  else
    s = "found: " + joined(found) + (unexplained ? "; " + a.verdict() : a.tested ? "; residual explained" : "");
  if (!negligible.empty()) s += "; significant but negligible: " + joined(negligible);
  if (!contradicted.empty()) s += "; significant, but contradicted by the fit pushes' motion: " + joined(contradicted);
  if (!stand_ins.empty())
    s += "; significant, but standing in for the unexplained residual (not found beside it): " + joined(stand_ins);
  const auto fixes = kinds_of(r, true);
  if (!fixes.empty()) s += "; base model: " + joined(fixes);
  return s;
}

std::string test_phase_errors_csv(const DiagnosisResult& r) {
  static const char* const methods[] = {"dob", kCorrectedMethod, "hold", "const_velocity"};
  std::ostringstream csv;
  csv.precision(6);
  csv << "push,phase,t_s";
  for (const char* m : methods) csv << "," << m << "_x_mm," << m << "_y_mm," << m << "_theta_deg";
  csv << "\n";
  for (const auto& p : r.test_phases) {
    const std::string push = std::filesystem::path(p.source).filename().string();
    for (Eigen::Index k = 0; k < p.t_s.size(); ++k) {
      csv << push << "," << p.phase << "," << p.t0_s + p.t_s(k);
      for (const char* m : methods) {
        const auto it = p.error.find(m);
        if (it == p.error.end()) {
          csv << ",,,";
          continue;
        }
        csv << "," << 1e3 * it->second(k, 0) << "," << 1e3 * it->second(k, 1) << "," << kDeg * it->second(k, 2);
      }
      csv << "\n";
    }
  }
  return csv.str();
}

nlohmann::json error_summary_json(const ErrorSummary& e) {
  return {{"phases", e.phases},
          {"pos_mm_mean", e.pos_mm_mean},
          {"x_mm_mean", e.x_mm_mean},
          {"y_mm_mean", e.y_mm_mean},
          {"theta_deg_mean", e.theta_deg_mean},
          {"final_pos_mm", e.final_pos_mm},
          {"final_theta_deg", e.final_theta_deg}};
}

nlohmann::json adequacy_json(const ModelAdequacy& a) {
  return {
      {"tested", a.tested},
      {"explained", a.explained},
      {"verdict", a.verdict()},
      {"statistic", a.statistic},
      {"alpha", a.alpha},
      {"replicates", a.replicates},
      {"force",
       {{"tested", a.force_tested},
        {"pushes", a.force_pushes},
        {"unexplained", a.force_unexplained},
        {"statistic", a.force_statistic},
        {"threshold", a.force_threshold},
        {"share_of_all_signatures", a.force_share},
        {"p_value", a.force_p_value},
        {"force_N", a.force_N},
        {"torque_Nm", a.torque_Nm},
        {"force_floor_N", a.force_floor_N},
        {"torque_floor_Nm", a.torque_floor_Nm},
        {"structure_unexplained", a.structure_unexplained},
        {"sensor_zeros_projected_pushes", a.pushes_zero_projected},
        {"sensor_zeros_measured_pushes", a.zero_measured_pushes},
        {"sensor_zeros_spread_N", std::isfinite(a.zero_spread_N) ? nlohmann::json(a.zero_spread_N) : nlohmann::json()},
        {"shared_force",
         {{"force_N", a.shared_force_N},
          {"force_N_std", a.shared_force_N_std},
          {"p_value", a.shared_force_p_value},
          {"unexplained", a.shared_force_unexplained}}}}},
      {"rest",
       {{"tested", a.rest_tested},
        {"unexplained", a.rest_unexplained},
        {"pushes", a.rest_pushes},
        {"force_N", a.rest_force_N},
        {"force_N_std", a.rest_force_N_std},
        {"score", a.rest_tested ? nlohmann::json(a.rest_score) : nlohmann::json()},
        {"threshold", a.rest_threshold},
        {"force_floor_N", a.force_floor_N}}},
      {"contact",
       {{"tested", a.contact_tested},
        {"unexplained", a.contact_unexplained},
        {"pushes", a.contact_pushes},
        {"compliance_m_N", a.contact_compliance_m_N},
        {"compliance_m_N_std", a.contact_compliance_m_N_std},
        {"lag_mm", a.contact_lag_mm},
        {"lag_mm_std", a.contact_lag_mm_std},
        {"floor_mm", a.contact_floor_mm}}},
      {"motion",
       {{"tested", a.motion_tested},
        {"unexplained", a.motion_unexplained},
        {"phases", a.phases},
        {"t", a.motion_t},
        {"t_threshold", a.motion_t_threshold},
        {"p_value", a.motion_p_value},
        {"position_bias_mm", a.position_bias_mm},
        {"yaw_bias_deg", a.yaw_bias_deg},
        {"position_floor_mm", a.position_floor_mm},
        {"yaw_floor_deg", a.yaw_floor_deg}}},
      {"basis", a.basis},
      {"note", a.note}};
}

nlohmann::json hints_json(const DiagnosisResult& r) {
  nlohmann::json out = nlohmann::json::array();
  if (!r.adequacy.tested || r.adequacy.explained) return out;
  for (const auto& h : r.hints)
    out.push_back({{"signature", h.signature},
                   {"description", h.description},
                   {"share", h.share},
                   {"share_of_structure", h.share_of_structure}});
  return out;
}

std::vector<std::string> hint_lines(const DiagnosisResult& r, std::size_t at_most) {
  std::vector<std::string> out;
  if (!r.adequacy.tested || r.adequacy.explained) return out;
  for (const auto& h : r.hints) {
    if (out.size() >= at_most) break;
    out.push_back(h.signature + ": " + fixed(100 * h.share, 1) + " % of the residual (" +
                  fixed(100 * h.share_of_structure, 0) + " % of its structure) - " + h.description);
  }
  return out;
}

nlohmann::json diagnosis_json(const DiagnosisResult& r, const DiagnosisOptions& o) {
  const auto found = effects_found(r);
  nlohmann::json effects = nlohmann::json::array();
  for (const auto& e : r.effects) effects.push_back(effect_json(e));
  nlohmann::json failures = nlohmann::json::array();
  for (const auto& f : r.failures) failures.push_back({{"source", f.source}, {"reason", f.reason}});
  nlohmann::json step_failures = nlohmann::json::array();
  for (const auto& f : r.step_failures) step_failures.push_back({{"step", f.step}, {"what", f.what}});
  const auto channels = [](const Eigen::Vector3d& v) { return nlohmann::json{{"x_N", v(0)}, {"y_N", v(1)}, {"rotation_Nm", v(2)}}; };
  return {{"pushpred_version", kVersion},
          {"shape", r.shape},
          {"surface", r.surface},
          {"options",
           {{"intervals", o.study.schedule.intervals},
            {"span", schedule_span_name(o.study.schedule.span)},
            {"plan_rate_hz", o.study.plan_rate_hz},
            {"estimator", o.study.estimator},
            {"bic_threshold", o.bic_threshold},
            {"relevance_fraction", o.relevance_fraction},
            {"floor_margin_std", o.floor_margin_std},
            {"sensor_zero_spread_N", o.sensor_zero_spread_N},
            {"measured_contact_compliance", o.measured_contact_compliance},
            {"fit_base_settings", o.fit_base_settings},
            {"adequacy_replicates", o.adequacy_replicates},
            {"adequacy_alpha", o.adequacy_alpha}}},
          {"held_out", r.held_out},
          {"caution", r.caution},
          {"fit_pushes", r.fit_sources},
          {"test_pushes", r.test_sources},
          {"effects", effects},
          {"found", found},
          {"nothing_found", found.empty()},
          {"findings", findings_text(r)},
          {"adequacy", adequacy_json(r.adequacy)},
          {"hints", hints_json(r)},
          {"correction", r.correction.describe()},
          {"initial_velocity_from_observer", r.correction.initial_velocity},
          {"contact_compliance_m_N", r.correction.contact_compliance_m_N},
          {"error_before", error_summary_json(r.error_before)},
          {"error_base", error_summary_json(r.error_base)},
          {"error_after", error_summary_json(r.error_after)},
          {"error_references",
           {{"hold", error_summary_json(r.hold)},
            {"const_velocity", error_summary_json(r.const_velocity)},
            {"dob_velinit", error_summary_json(r.dob_velinit)},
            {"quasi_static", error_summary_json(r.quasi_static)}}},
          {"fit_phases",
           {{"before", error_summary_json(r.fit_before)},
            {"after", error_summary_json(r.fit_after)},
            {"hold", error_summary_json(r.fit_hold)},
            {"const_velocity", error_summary_json(r.fit_const_velocity)}}},
          {"regression",
           {{"samples", r.samples},
            {"effective_samples", r.effective_samples},
            {"residual_std_before", channels(r.residual_std_before)},
            {"residual_std_after", channels(r.residual_std_after)},
            {"friction_law_residual_std",
             r.friction_residual_std.allFinite() ? channels(r.friction_residual_std) : nlohmann::json(nullptr)}}},
          {"floor_context",
           {{"friction_coefficient", r.floor_context.friction_coefficient},
            {"friction_spread", r.floor_context.friction_spread},
            {"friction_force_N", r.floor_context.friction_force_N()},
            {"relevance_fraction", r.floor_context.relevance_fraction},
            {"sample_period_s", r.floor_context.sample_period_s},
            {"sliding_speed_m_s", r.floor_context.sliding_speed_m_s},
            {"acceleration_m_s2", r.floor_context.acceleration_m_s2},
            {"travel_m", r.floor_context.travel_m},
            {"radius_of_gyration_m", r.floor_context.radius_of_gyration_m}}},
          {"step_failures", step_failures},
          {"failures", failures},
          {"log", r.log}};
}

std::string diagnosis_summary_text(const DiagnosisResult& r) {
  std::ostringstream s;
  s << "diagnosis of " << r.fit_sources.size() << " fit and " << r.test_sources.size() << " test pushes (" << r.shape
    << " on " << r.surface << ")\n";
  s << "  " << findings_text(r) << "\n";
  for (const auto& h : hint_lines(r, 3)) s << "  hint (not a finding): " << h << "\n";
  if (!r.caution.empty()) s << "  caution: " << r.caution << "\n";
  for (const auto& e : r.effects)
    if (e.selected) s << "  " << (e.structural ? "base " : "found ") << e.kind << ": " << effect_parameters_text(e) << "\n";
  for (const auto& f : r.step_failures) s << "  step " << f.step << " failed: " << f.what << "\n";
  char line[256];
  s << "held-out phases (" << r.error_after.phases << "):      pos mm   yaw deg\n";
  const std::pair<const char*, const ErrorSummary*> rows[] = {{"before (paper dob)", &r.error_before},
                                                             {"base model", &r.error_base},
                                                             {"after (base + found)", &r.error_after},
                                                             {"hold", &r.hold},
                                                             {"const_velocity", &r.const_velocity}};
  for (const auto& [name, e] : rows) {
    std::snprintf(line, sizeof line, "  %-22s %8.2f %9.2f\n", name, e->pos_mm_mean, e->theta_deg_mean);
    s << line;
  }
  return s.str();
}

std::string adequacy_markdown(const DiagnosisResult& r) {
  const ModelAdequacy& a = r.adequacy;
  std::ostringstream md;
  md << "## Model adequacy\n\n";
  if (!a.tested) {
    md << "Not tested" << (a.note.empty() ? std::string(".") : ": " + a.note + ".") << "\n\n";
    return md.str();
  }
  md << "**" << a.verdict() << ".** " << a.statistic << ". Floors: " << a.basis << ".\n\n"
     << markdown_header({"part", "statistic", "null threshold", "p", "size", "floor", "verdict"});
  if (a.force_tested)
    md << markdown_row({"force residual (" + std::to_string(a.force_pushes) + " pushes)", "z " + fixed(a.force_statistic), fixed(a.force_threshold),
                        general(a.force_p_value), general(a.force_N) + " N, " + general(a.torque_Nm) + " N m",
                        general(a.force_floor_N) + " N, " + general(a.torque_floor_Nm) + " N m",
                        a.structure_unexplained ? "unexplained" : "explained"});
  if (a.force_tested && a.zero_measured_pushes >= 2)
    md << markdown_row(
        {"force shared by the " + std::to_string(a.zero_measured_pushes) + " pushes whose sensor zero is measured", "F",
         "-", general(a.shared_force_p_value),
         general(a.shared_force_N) + " +- " + general(a.shared_force_N_std) + " N", general(a.force_floor_N) + " N",
         a.shared_force_unexplained ? "unexplained" : "explained"});
  if (a.rest_tested)
    md << markdown_row({"force at rest, where nothing touches (" + std::to_string(a.rest_pushes) + " pushes)",
                        "Wald - 2 ln N_eff " + fixed(a.rest_score, 1), fixed(a.rest_threshold, 1), "-",
                        general(a.rest_force_N) + " +- " + general(a.rest_force_N_std) + " N",
                        general(a.force_floor_N) + " N", a.rest_unexplained ? "unexplained" : "explained"});
  if (a.contact_tested)
    md << markdown_row(
        {"contact: the rod's penetration against the force (" + std::to_string(a.contact_pushes) + " pushes)",
         "median slope " + general(1e3 * a.contact_compliance_m_N) + " mm/N", "-", "-",
         fixed(a.contact_lag_mm) + " +- " + fixed(a.contact_lag_mm_std) + " mm lag under mu m g",
         fixed(a.contact_floor_mm) + " mm", a.contact_unexplained ? "unexplained" : "explained"});
  if (a.motion_tested)
    md << markdown_row({"motion (" + std::to_string(a.phases) + " fit phases)", "max abs t " + fixed(a.motion_t),
                        fixed(a.motion_t_threshold), general(a.motion_p_value),
                        fixed(a.position_bias_mm) + " mm, " + fixed(a.yaw_bias_deg) + " deg",
                        fixed(a.position_floor_mm) + " mm, " + fixed(a.yaw_floor_deg) + " deg",
                        a.motion_unexplained ? "unexplained" : "explained"});
  md << "\n";
  if (!a.note.empty()) md << a.note << ".\n\n";
  const auto hints = hint_lines(r, r.hints.size());
  if (!hints.empty()) {
    md << "Hints, not findings: generic signatures ranked by the share of the force residual each accounts for alone "
          "(where to look for the missing physics; none of them is a tested effect):\n\n";
    for (const auto& h : hints) md << "- " << h << "\n";
    md << "\n";
  }
  return md.str();
}

std::string diagnosis_markdown(const DiagnosisResult& r, const DiagnosisOptions& o, const std::vector<std::string>& plots,
                               const std::string& plot_note) {
  std::ostringstream md;
  md << "# Diagnosis: " << r.shape << " on " << r.surface << "\n\n"
     << "pushpred " << kVersion << ". " << r.fit_sources.size() << " fit push(es), " << r.test_sources.size()
     << " test push(es); held out: " << r.held_out << ". Schedule: " << o.study.schedule.intervals
     << " intervals over the " << schedule_span_name(o.study.schedule.span) << " span, plan at "
     << general(o.study.plan_rate_hz) << " Hz, relation estimator `" << o.study.estimator
     << "`. An effect is found when its test passes (greedy BIC with the effective sample count, threshold "
     << general(o.bic_threshold) << ") and its amount exceeds its floor (" << fixed(100 * o.relevance_fraction, 0)
     << " % of the support friction, scaled per effect) by " << general(o.floor_margin_std)
     << " standard error(s) of the amount (docs/diagnosis.md).\n\n";
  if (!r.step_failures.empty()) {
    md << "**Steps that failed** (the diagnosis went on without them):\n\n";
    for (const auto& f : r.step_failures) md << "- " << f.step << ": " << f.what << "\n";
    md << "\n";
  }

  md << "**" << findings_text(r) << ".**\n\n";
  if (!r.caution.empty()) md << "> Caution: " << r.caution << ".\n\n";
  md << adequacy_markdown(r);
  md << "## Prediction error on the held-out phases\n\n"
     << "Mean over " << r.error_after.phases << " phases of the per-phase mean error. `before` is the paper's method "
     << "(`dob`: relation identified online, initial velocity zero); `base` is the corrected base model (initial "
     << "velocity from the observer, quasi-static push that ends when the pusher stops, friction that stops the "
     << "object); `after` is the base model plus the effects found.\n\n"
     << markdown_header({"method", "pos [mm]", "x [mm]", "y [mm]", "yaw [deg]", "final pos [mm]", "final yaw [deg]"})
     << error_row("before (paper `dob`)", r.error_before) << error_row("base model", r.error_base)
     << error_row("after (base + found)", r.error_after) << error_row("`hold`", r.hold)
     << error_row("`const_velocity`", r.const_velocity) << error_row("`dob_velinit`", r.dob_velinit)
     << error_row("`quasi_static` (pushing model)", r.quasi_static) << "\n";
  const BeatsReferences beats = beats_references(r.error_after, r.hold, r.const_velocity);
  const bool beats_pos = beats.pos, beats_yaw = beats.yaw;
  if (beats_pos && beats_yaw) {
    md << "The corrected model beats both naive references in position and yaw on these phases.\n\n";
  } else {
    md << "**The corrected model does not beat both naive references:** "
       << (beats_pos ? "" : "its position error is not below both references") << (!beats_pos && !beats_yaw ? "; " : "")
       << (beats_yaw ? "" : "its yaw error is not below both references") << ".\n\n";
  }

  md << "## Candidate effects\n\n"
     << markdown_header({"effect", "test", "significant", "amount / floor", "in the model", "score",
                         "parameters (± 1 std)", "held-out pos / yaw without it", "note"});
  for (const auto& e : r.effects)
    md << markdown_row({e.kind, effect_test_name(e.test),
                        e.structural    ? "—"
                        : e.passed_test ? "yes"
                                        : "no",
                        e.structural ? std::string("base model")
                                     : general(e.amount) + " / " + general(e.floor.amount) + " " + e.amount_unit +
                                           (e.negligible                  ? " (negligible)"
                                            : e.contradicted_by_motion    ? " (contradicted)"
                                            : e.stands_in_for_unexplained ? " (stand-in)"
                                                                          : ""),
                        e.selected ? (e.structural ? "base" : "**found**") : "no",
                        std::isfinite(e.score) ? general(e.score) : std::string("—"), effect_parameters_text(e),
                        e.has_ablation ? fixed(e.held_out_without.pos_mm_mean) + " mm / " +
                                             fixed(e.held_out_without.theta_deg_mean) + " deg"
                                       : std::string("—"),
                        e.note});
  md << "\nScore: for regression and direct effects the drop of the BIC when the effect joins (robust Wald "
        "statistic minus k ln N_eff; direct effects: their own likelihood ratio), for prediction effects the relative "
        "drop of the fit phases' normalised prediction error. Significant: its own test passed; found: significant, "
        "its amount above its floor (the smallest amount that matters; its basis is in diagnosis.json) by the margin "
        "of standard errors asked, and, for an effect that changes how the pushing model moves the object (the "
        "mass-centre offset), predicting the fit pushes' phases better with it than without it. "
        "Uncertainty: the larger of the Newey-West and the "
        "push-clustered standard errors (direct effects: their own). The held-out column is the corrected model "
        "without that one effect, on the test phases (reported, never used to select).\n\n";
  md << "Correction applied:\n\n";
  const auto lines = r.correction.describe();
  if (lines.empty()) md << "- none\n";
  for (const auto& l : lines) md << "- " << l << "\n";

  md << "\n## Residual of the disturbance regression (fit data)\n\n"
     << "Samples " << r.samples / 3 << " (x 3 channels), effective " << fixed(r.effective_samples, 1) << ".\n\n"
     << markdown_header({"channel", "std before", "std after"})
     << markdown_row({"x [N]", general(r.residual_std_before(0)), general(r.residual_std_after(0))})
     << markdown_row({"y [N]", general(r.residual_std_before(1)), general(r.residual_std_after(1))})
     << markdown_row({"rotation [N m]", general(r.residual_std_before(2)), general(r.residual_std_after(2))}) << "\n"
     << "Before: d_hat less the paper's relation beta Q u + eps per push; after: with the data corrections and the "
        "effects tested against that relation.";
  if (r.friction_residual_std.allFinite())
    md << " Against the selected friction law and its refinements instead of the relation: x "
       << general(r.friction_residual_std(0)) << " N, y " << general(r.friction_residual_std(1)) << " N, rotation "
       << general(r.friction_residual_std(2)) << " N m (samples near a stuck-sliding change left out).";
  md << "\n\n";

  md << phase_by_phase(r);

  md << "## In-sample: the fit pushes' phases\n\n"
     << markdown_header({"method", "pos [mm]", "x [mm]", "y [mm]", "yaw [deg]", "final pos [mm]", "final yaw [deg]"})
     << error_row("before (paper `dob`)", r.fit_before) << error_row("after (corrected)", r.fit_after)
     << error_row("`hold`", r.fit_hold) << error_row("`const_velocity`", r.fit_const_velocity) << "\n";

  md << "## Plots\n\n";
  if (plots.empty()) md << plot_note << "\n\n";
  for (const auto& p : plots) md << "![" << p << "](" << p << ")\n\n";

  md << "## Selection log\n\n";
  for (const auto& l : r.log) md << "    " << l << "\n";
  md << "\n## Pushes\n\nFit: ";
  for (std::size_t k = 0; k < r.fit_sources.size(); ++k)
    md << (k ? ", " : "") << "`" << std::filesystem::path(r.fit_sources[k]).filename().string() << "`";
  md << "\n\nTest: ";
  for (std::size_t k = 0; k < r.test_sources.size(); ++k)
    md << (k ? ", " : "") << "`" << std::filesystem::path(r.test_sources[k]).filename().string() << "`";
  md << "\n";
  if (!r.failures.empty()) {
    md << "\nLeft out:\n\n";
    for (const auto& f : r.failures)
      md << "- `" << std::filesystem::path(f.source).filename().string() << "`: " << f.reason << "\n";
  }
  return md.str();
}

void write_diagnosis_report(const DiagnosisResult& r, const DiagnosisOptions& o, const StagedOutput& out, bool plots) {
  write_diagnosis_report(r, o, out.path("."), plots);
}

void write_diagnosis_report(const DiagnosisResult& r, const DiagnosisOptions& o, const std::filesystem::path& folder,
                            bool plots) {
  // One level at a time, never create_directories: inside a staging folder, its parent must not be made again.
  std::error_code ec;
  for (const auto& f : plots ? std::vector<std::filesystem::path>{folder, folder / "plots"}
                             : std::vector<std::filesystem::path>{folder}) {
    std::filesystem::create_directory(f, ec);
    if (ec) throw InputError(about(f.string(), "cannot create folder: " + ec.message()));
  }
  write_text_atomically(folder / "diagnosis.json", diagnosis_json(r, o).dump(2) + "\n");
  write_text_atomically(folder / "test_phase_errors.csv", test_phase_errors_csv(r));
  std::vector<std::string> drawn;
  std::string note;
  if (!plots) {
    note = "Plots were not asked for (--no-plots).";
  } else {
    if (!r.residuals.empty() && plot_residuals(r.residuals.front(), folder, "residuals", note))
      drawn.push_back("plots/residuals.png");
    if (plot_test_errors(r.test_phases, folder, "test_errors", note)) drawn.push_back("plots/test_errors.png");
    if (drawn.empty()) note = "Plots left out: " + note;
  }
  write_text_atomically(folder / "report.md", diagnosis_markdown(r, o, drawn, note));
}

namespace {
const char* adequacy_word(const ModelAdequacy& a) {
  return !a.tested ? "not tested" : a.explained ? "explained" : "**unexplained**";
}
}  // namespace

std::string diagnosis_overview_markdown(const std::vector<DiagnosisGroupOutcome>& groups) {
  std::ostringstream md;
  md << "# Diagnosis per object\n\n"
     << "pushpred " << kVersion << ". One diagnosis per object and surface; each has its own report in the folder "
     << "named in the first column. Errors: mean over the held-out phases of the per-phase mean position error [mm] "
     << "/ yaw error [deg].\n\n"
     << markdown_header({"object", "pushes", "held-out phases", "found", "residual", "before (paper `dob`)",
                         "base model", "after (base + found)", "`hold`", "`const_velocity`", "after beats both",
                         "`quasi_static` (pushing model)"});
  const auto pair = [](const ErrorSummary& e) { return fixed(e.pos_mm_mean) + " / " + fixed(e.theta_deg_mean); };
  for (const auto& g : groups) {
    if (!g.result) continue;
    const DiagnosisResult& r = *g.result;
    const auto found = effects_found(r);
    md << markdown_row({"[" + g.name + "](" + g.name + "/report.md)", std::to_string(g.pushes),
                        std::to_string(r.error_after.phases), found.empty() ? std::string("nothing") : joined(found),
                        adequacy_word(r.adequacy), pair(r.error_before), pair(r.error_base), pair(r.error_after),
                        pair(r.hold), pair(r.const_velocity), beats_both(r) ? "yes" : "**no**", pair(r.quasi_static)});
  }
  // All objects: every held-out phase weighs alike.
  ErrorSummary all[6];
  const auto add = [](ErrorSummary& to, const ErrorSummary& e) {
    to.pos_mm_mean += e.phases * e.pos_mm_mean;
    to.theta_deg_mean += e.phases * e.theta_deg_mean;
    to.phases += e.phases;
  };
  int objects = 0;
  for (const auto& g : groups)
    if (g.result) {
      ++objects;
      add(all[0], g.result->error_before);
      add(all[1], g.result->error_after);
      add(all[2], g.result->hold);
      add(all[3], g.result->const_velocity);
      add(all[4], g.result->error_base);
      add(all[5], g.result->quasi_static);
    }
  if (objects > 1 && all[1].phases > 0) {
    for (auto& e : all) {
      e.pos_mm_mean /= e.phases;
      e.theta_deg_mean /= e.phases;
    }
    md << markdown_row({"all " + std::to_string(objects) + " objects (phases weighed alike)", "",
                        std::to_string(all[1].phases), "", "", pair(all[0]), pair(all[4]), pair(all[1]), pair(all[2]),
                        pair(all[3]), beats_references(all[1], all[2], all[3]).both() ? "yes" : "**no**",
                        pair(all[5])});
  }
  md << "\nThe base model, in every corrected model:\n\n";
  for (const auto& g : groups)
    if (g.result) {
      const auto fixes = kinds_of(*g.result, true);
      md << "- " << g.name << ": " << (fixes.empty() ? std::string("none") : joined(fixes)) << "\n";
    }
  bool failed = false;
  for (const auto& g : groups) failed = failed || !g.result;
  if (failed) {
    md << "\nNot diagnosed:\n\n";
    for (const auto& g : groups)
      if (!g.result) md << "- " << g.name << " (" << g.pushes << " pushes): " << g.error << "\n";
  }
  return md.str();
}

nlohmann::json diagnosis_overview_json(const std::vector<DiagnosisGroupOutcome>& groups) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& g : groups) {
    nlohmann::json j = {{"name", g.name}, {"pushes", g.pushes}};
    if (g.result) {
      const DiagnosisResult& r = *g.result;
      j["shape"] = r.shape;
      j["surface"] = r.surface;
      const auto found = effects_found(r);
      j["found"] = found;
      j["nothing_found"] = found.empty();
      j["adequacy"] = {{"tested", r.adequacy.tested}, {"explained", r.adequacy.explained}};
      j["structure_fixes"] = kinds_of(r, true);
      j["error_before"] = error_summary_json(r.error_before);
      j["error_base"] = error_summary_json(r.error_base);
      j["error_after"] = error_summary_json(r.error_after);
      j["error_references"] = {{"hold", error_summary_json(r.hold)},
                               {"const_velocity", error_summary_json(r.const_velocity)}};
      j["after_beats_both_references"] = beats_both(r);
    } else {
      j["error"] = g.error;
    }
    out.push_back(j);
  }
  return {{"pushpred_version", kVersion}, {"objects", out}};
}

}  // namespace pushpred
