#pragma once
// The outputs of `pushpred diagnose`:
// - diagnosis.json: `adequacy` (the model-adequacy test: verdict, statistics, sizes, floors), `hints` (generic
//   signatures with their share of an unexplained residual), `effects` (every candidate: kind, test, selected, score,
//   parameters with value, std and unit, setting, derived amounts, note), `error_before` (the paper's `dob`),
//   `error_after` (the corrected model), `error_references` (`hold`, `const_velocity`), each with pos_mm_mean,
//   x_mm_mean, y_mm_mean, theta_deg_mean, final_pos_mm, final_theta_deg and phases, all on the same held-out phases;
//   the fit-phase (in-sample) errors; the regression's sample counts and residual spread; the correction; the pushes
//   used and left out; the log.
// - test_phase_errors.csv: the prediction error over time in every held-out phase, per method.
// - report.md: the same as tables, with residual and error plots before and after (gnuplot, PNG; left out with a
//   note when gnuplot is not installed).
// Millimetres and degrees here only; the library is SI.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/runtime/output_files.hpp"

namespace pushpred {

nlohmann::json error_summary_json(const ErrorSummary& e);
/// The selected effects that are physical effects found in the data, not fixes of the model's structure
/// (EffectReport::structural); empty: nothing found.
std::vector<std::string> effects_found(const DiagnosisResult& result);
/// The prediction error over time of every held-out phase, one row per sample: push, phase, t_s (the push's
/// clock), then per method (dob, corrected, hold, const_velocity) predicted - measured x, y [mm] and yaw [deg].
/// Written as test_phase_errors.csv beside report.md.
std::string test_phase_errors_csv(const DiagnosisResult& result);
/// One line: what was found and whether the residual is explained (model_adequacy.hpp): "nothing found, residual
/// explained: ..." only when the adequacy test says so; "unexplained residual: <size>" when it does not, whatever
/// was found; and the structure fixes applied. Also diagnosis.json's `findings`, beside `found` and
/// `nothing_found`.
std::string findings_text(const DiagnosisResult& result);
nlohmann::json diagnosis_json(const DiagnosisResult& result, const DiagnosisOptions& options);
/// diagnosis.json's `adequacy`: the verdict, statistics, thresholds, p-values, sizes and floors of both parts.
nlohmann::json adequacy_json(const ModelAdequacy& adequacy);
/// diagnosis.json's `hints`: the signatures with their shares, only when the residual is unexplained (else empty).
nlohmann::json hints_json(const DiagnosisResult& result);
/// Up to `at_most` hints as lines ("world_force: 42.0 % of the residual ..."), only when the residual is
/// unexplained.
std::vector<std::string> hint_lines(const DiagnosisResult& result, std::size_t at_most);
/// report.md's "Model adequacy" section.
std::string adequacy_markdown(const DiagnosisResult& result);
/// report.md; `plots` lists the plot files written beside it (empty: plots were not drawn), `plot_note` why not.
std::string diagnosis_markdown(const DiagnosisResult& result, const DiagnosisOptions& options,
                               const std::vector<std::string>& plots, const std::string& plot_note);
/// A few lines for the terminal: selected effects and the before/after table.
std::string diagnosis_summary_text(const DiagnosisResult& result);

/// Writes diagnosis.json, report.md and (when `plots` and gnuplot is found) the plots into `out`.
void write_diagnosis_report(const DiagnosisResult& result, const DiagnosisOptions& options, const StagedOutput& out,
                            bool plots = true);
/// The same into `folder` (e.g. a subfolder of a staged output).
void write_diagnosis_report(const DiagnosisResult& result, const DiagnosisOptions& options,
                            const std::filesystem::path& folder, bool plots = true);

/// One object's diagnosis in a run over several (`pushpred diagnose --per-object`): its result, or why it failed.
struct DiagnosisGroupOutcome {
  std::string name;  ///< PushGroup::name(), the subfolder of its report
  std::size_t pushes = 0;
  std::optional<DiagnosisResult> result;
  std::string error;
};
/// overview.md: one row per object (findings, held-out errors before and after next to hold and const_velocity,
/// whether the corrected model beats both) and the objects that failed.
std::string diagnosis_overview_markdown(const std::vector<DiagnosisGroupOutcome>& groups);
/// overview.json: per object its `found`, `error_before`, `error_after` and `error_references`, or its `error`.
nlohmann::json diagnosis_overview_json(const std::vector<DiagnosisGroupOutcome>& groups);

}  // namespace pushpred
