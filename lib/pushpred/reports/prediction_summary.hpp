#pragma once
// The summary.json of `pushpred predict` and `pushpred reproduce`: for each file, phase and method the keys
// x_mm_mean, x_mm_std, y_mm_mean, y_mm_std, theta_deg_mean, theta_deg_std, final_pos_mm, final_theta_deg; and an
// `aggregate` object with the same keys per method, averaged over all phases of all files.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/prediction/prediction_study.hpp"

namespace pushpred {

nlohmann::json errors_json(const PredictionErrors& e);
nlohmann::json relation_json(const RelationParameters& p);
nlohmann::json study_json(const PushStudy& study);

/// Mean of every error key per method over all phases of `studies`.
std::map<std::string, PredictionErrors> aggregate_errors(const std::vector<PushStudy>& studies);
std::map<std::string, PredictionErrors> aggregate_errors(const std::vector<const PushStudy*>& studies);

nlohmann::json prediction_summary_json(const Batch<PushStudy>& batch, const StudyOptions& options);
/// The summary's "options" object for `options`.
nlohmann::json prediction_options_json(const StudyOptions& options);
/// prediction_summary_json with the "options" object given (a merge of partial outputs has it, not the options).
nlohmann::json prediction_summary_json(const Batch<PushStudy>& batch, const nlohmann::json& options);
/// Writes the text of summary.json (json_file_text of prediction_summary_json, byte for byte) to `out`, one push at
/// a time, without building the whole document: memory stays that of the studies, whatever the number of pushes.
void write_prediction_summary(std::ostream& out, const Batch<PushStudy>& batch, const nlohmann::json& options);

/// Markdown tables of the mean over phases of each method's per-phase mean position error [mm] / yaw error [deg]:
/// per object, per pusher speed (or acceleration), and over all phases, for `studies` (shape and speed from the
/// file names; "unknown" for other names). Every phase weighs alike. Empty for no studies.
std::string grouped_errors_markdown(const std::vector<PushStudy>& studies);

/// Markdown: the phases where `method` loses to the better of `references` (position or yaw error more than 2 %
/// and 0.05 mm / 0.05 deg above it), counted per object, and the `worst` of them by the sum of the excess position
/// [mm] and yaw [deg] error, worst first. Empty when a method is missing from the studies.
std::string losing_phases_markdown(const std::vector<PushStudy>& studies, const std::string& method,
                                   const std::vector<std::string>& references, int worst = 15);

/// Method names for Markdown prose: "`a`, `b`, `c`" (empty for none).
std::string markdown_method_list(const std::vector<std::string>& methods);

/// Per-phase predictions of one push as CSV: phase, t_s, measured x, y [mm], theta [deg], then each method's.
std::string predictions_csv(const PushStudy& study);

}  // namespace pushpred
