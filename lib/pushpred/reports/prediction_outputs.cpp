#include "pushpred/reports/prediction_outputs.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/reports/prediction_summary.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

/// The folder of the predictions that wait for their names.
constexpr const char* kPendingFolder = "by-input";

/// Throws InputError naming `path` when a write to `stream` (its file) failed.
void require_written(const std::ostream& stream, const fs::path& path) {
  if (!stream) throw InputError(about(path.string(), "cannot be written (is the disk full?)"));
}

/// summary.json and tables.md of a whole run, given one studied push (or failure) at a time in input order. Nothing
/// of a study is kept but its file's stem (to name its predictions): its entry of summary.json goes to a file in the
/// staging folder as it comes, and its errors into the tables' sums, so that a run holds a few hundred bytes per
/// push rather than its study (docs/performance.md, memory).
class PredictionOutputs {
 public:
  PredictionOutputs(StagedOutput& out, nlohmann::json options)
      : out_(out),
        options_(std::move(options)),
        tables_("quasi_static", {"hold", "const_velocity"}),
        entries_path_(out.path(".summary-files")) {}
  ~PredictionOutputs() {
    std::error_code ec;
    std::filesystem::remove(entries_path_, ec);
  }
  PredictionOutputs(const PredictionOutputs&) = delete;
  PredictionOutputs& operator=(const PredictionOutputs&) = delete;

  void add(const PushStudy& study) {
    if (!entries_.is_open()) {
      entries_.open(entries_path_, std::ios::binary | std::ios::trunc);
      if (!entries_) throw InputError(about(entries_path_.string(), "cannot be written"));
    }
    entries_ << summary_file_entry(study, stems_.empty());
    require_written(entries_, entries_path_);
    tables_.add(study);
    stems_.push_back(fs::path(study.source).stem().string());
  }
  void add_failure(BatchFailure failure) { failures_.push_back(std::move(failure)); }

  /// The stems of the pushes' files studied, in input order.
  const std::vector<std::string>& stems() const { return stems_; }

  /// Writes summary.json and tables.md and commits the output, unless no input gave a result (then nothing is
  /// written); the report printed to the user.
  BatchRunOutcome finish() {
    BatchRunOutcome outcome;
    outcome.failures = failures_;
    outcome.used = stems_.size();
    if (stems_.empty()) return outcome;  // nothing written
    entries_.close();
    require_written(entries_, entries_path_);
    const std::map<std::string, PredictionErrors> aggregate = tables_.aggregate();
    write_file_atomically(out_.path("summary.json"), [&](std::ostream& file) {
      write_prediction_summary(file, aggregate, failures_, options_, stems_.size(), [&](std::ostream& files) {
        std::ifstream in(entries_path_, std::ios::binary);
        if (!in || !(files << in.rdbuf())) throw InputError(about(entries_path_.string(), "cannot be read back"));
      });
    });
    std::filesystem::remove(entries_path_);
    write_text_atomically(out_.path("tables.md"),
                          "Mean over phases of each phase's mean position error [mm] / yaw error [deg]\n\n" +
                              tables_.grouped_errors_markdown() + "\n" + tables_.losing_phases_markdown());
    out_.commit();

    std::ostringstream report;
    report << "predicted " << stems_.size() << " pushes (" << options_.at("intervals").get<int>()
           << " intervals over the " << options_.at("span").get<std::string>() << " span); summary in "
           << out_.destination().string() << "/summary.json\n";
    for (const auto& method : options_.at("methods")) {
      const std::string name = method.get<std::string>();
      const auto e = aggregate.find(name);
      if (e == aggregate.end()) continue;
      char line[256];
      std::snprintf(line, sizeof line, "  %-15s position %6.2f mm (x %6.2f, y %6.2f)  theta %6.2f deg\n", name.c_str(),
                    e->second.pos_mm_mean, e->second.x_mm_mean, e->second.y_mm_mean, e->second.theta_deg_mean);
      report << line;
    }
    outcome.report = report.str();
    return outcome;
  }

 private:
  StagedOutput& out_;
  nlohmann::json options_;
  PredictionTables tables_;
  std::vector<BatchFailure> failures_;
  std::vector<std::string> stems_;
  fs::path entries_path_;
  std::ofstream entries_;  ///< summary.json's "files" entries, as they come
};

/// predictions/NAME.csv for each studied push, in order: its file's stem, made distinct among the studied pushes
/// (distinct_names), so that an input that failed takes no name from one that was studied, and bounded in length
/// (bounded_file_name) so that a stem near the 255-byte limit still makes a file name.
std::vector<std::string> studied_file_names(const std::vector<std::string>& stems) {
  std::vector<std::string> names;
  for (const auto& stem : distinct_names(stems)) names.push_back("predictions/" + bounded_file_name(stem) + ".csv");
  return names;
}

/// The outputs of a whole run from its pushes in input order, as they finish or as a merge reads them back: each
/// push's summary entry and errors as it comes, its predictions file named at the end, among the pushes studied.
class PredictionRenderer final : public BatchRenderer<PushStudy> {
 public:
  PredictionRenderer(StagedOutput& out, nlohmann::json summary_options)
      : out_(out), outputs_(out, std::move(summary_options)) {}
  void add(std::size_t index, PushStudy&& study) override {
    pending_.push_back(pending_predictions_file(index));
    outputs_.add(study);
  }
  void add_failure(std::size_t, BatchFailure&& failure) override { outputs_.add_failure(std::move(failure)); }
  BatchRunOutcome finish() override {
    const std::vector<std::string> names = studied_file_names(outputs_.stems());
    for (std::size_t k = 0; k < names.size(); ++k) {
      std::error_code ec;
      fs::rename(out_.path(pending_[k]), out_.path(names[k]), ec);
      if (ec) throw InputError(about(names[k], "cannot be written: " + ec.message()));
    }
    std::error_code ec;
    fs::remove(out_.staging_folder() / kPendingFolder, ec);  // empty now; absent when nothing was studied
    return outputs_.finish();
  }

 private:
  StagedOutput& out_;
  PredictionOutputs outputs_;
  std::vector<std::string> pending_;
};

}  // namespace

std::string pending_predictions_file(std::size_t position) {
  return std::string(kPendingFolder) + "/" + std::to_string(position) + ".csv";
}

std::unique_ptr<BatchRenderer<PushStudy>> prediction_renderer(StagedOutput& out, nlohmann::json summary_options) {
  return std::make_unique<PredictionRenderer>(out, std::move(summary_options));
}

}  // namespace pushpred
