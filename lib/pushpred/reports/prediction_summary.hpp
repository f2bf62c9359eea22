#pragma once
// The summary.json of `pushpred predict` and `pushpred reproduce`: for each file, phase and method the keys
// x_mm_mean, x_mm_std, y_mm_mean, y_mm_std, theta_deg_mean, theta_deg_std, final_pos_mm, final_theta_deg; and an
// `aggregate` object with the same keys per method, averaged over all phases of all files.
#include <functional>
#include <map>
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
/// The same text, for a batch whose studies are no longer held: `aggregate` is aggregate_errors of the `files`
/// studies, and `write_files` writes their entries (summary_file_entry of each, in order).
void write_prediction_summary(std::ostream& out, const std::map<std::string, PredictionErrors>& aggregate,
                              const std::vector<BatchFailure>& failures, const nlohmann::json& options,
                              std::size_t files, const std::function<void(std::ostream&)>& write_files);
/// One study's entry in summary.json's "files", indented as the whole document's dump indents it, after its
/// separator from the entry before (none when `first`).
std::string summary_file_entry(const PushStudy& study, bool first);

/// Markdown tables of the mean over phases of each method's per-phase mean position error [mm] / yaw error [deg]:
/// per object, per pusher speed (or acceleration), and over all phases, for `studies` (shape and speed from the
/// file names; "unknown" for other names). Every phase weighs alike. Empty for no studies.
std::string grouped_errors_markdown(const std::vector<PushStudy>& studies);

/// Markdown: the phases where `method` loses to the better of `references` (position or yaw error more than 2 %
/// and 0.05 mm / 0.05 deg above it), counted per object, and the `worst` of them by the sum of the excess position
/// [mm] and yaw [deg] error, worst first. Empty when a method is missing from the studies.
std::string losing_phases_markdown(const std::vector<PushStudy>& studies, const std::string& method,
                                   const std::vector<std::string>& references, int worst = 15);

/// aggregate_errors, grouped_errors_markdown and losing_phases_markdown of a batch, added to one study at a time in
/// input order, so that a run over many pushes keeps a few sums per group rather than every study: the same numbers,
/// summed in the same order, as the functions above over all the studies at once.
class PredictionTables {
 public:
  /// `losing_method`, `references`, `worst`: losing_phases_markdown's (none: no such table).
  explicit PredictionTables(std::string losing_method = "", std::vector<std::string> references = {}, int worst = 15);
  void add(const PushStudy& study);
  std::size_t pushes() const { return all_.pushes; }
  std::map<std::string, PredictionErrors> aggregate() const { return all_.mean(); }
  std::string grouped_errors_markdown() const;
  std::string losing_phases_markdown() const;

 private:
  struct Group {
    std::size_t pushes = 0, phases = 0;
    std::map<std::string, PredictionErrors> sums;  ///< per method, over the group's phases
    std::map<std::string, int> counts;             ///< per method, the phases it predicted
    void add(const PushStudy& study);
    std::map<std::string, PredictionErrors> mean() const;
  };
  struct Loss {
    std::string push;  ///< its file name
    int phase;
    double pos, yaw, best_pos, best_yaw;
    double excess() const;
  };
  /// Sorts `losses` worst first and keeps the first `count`.
  static void keep_worst(std::vector<Loss>& losses, std::size_t count);

  bool started_ = false;
  std::vector<std::string> methods_;  ///< the first study's: the tables' columns
  Group all_;
  std::map<std::string, Group> by_object_, by_pusher_;
  std::string losing_method_;
  std::vector<std::string> references_;
  int worst_;
  bool losing_table_ = false;  ///< the first study has the method and every reference
  std::map<std::string, std::pair<int, int>> lost_per_object_;  ///< phases lost, phases
  std::vector<Loss> losses_;  ///< at most a few times `worst_`, trimmed to the worst as they come
};

/// Method names for Markdown prose: "`a`, `b`, `c`" (empty for none).
std::string markdown_method_list(const std::vector<std::string>& methods);

/// Per-phase predictions of one push as CSV: phase, t_s, measured x, y [mm], theta [deg], then each method's.
std::string predictions_csv(const PushStudy& study);

}  // namespace pushpred
