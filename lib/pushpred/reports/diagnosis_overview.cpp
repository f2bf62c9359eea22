#include "pushpred/reports/diagnosis_overview.hpp"

#include <utility>

namespace pushpred {
namespace {

std::string failure_lines(const std::vector<BatchFailure>& failures) {
  std::string s;
  for (const auto& f : failures) s += "FAILED " + f.source + ": " + f.reason + "\n";
  return s;
}

/// The end of a per-object run (a whole run's, or the merged parts'): overview.md and overview.json written and
/// `out` committed, and what the run prints: each object's report in order, then the count; on stderr
/// `read_failures` (the unreadable inputs, when not listed already), each object's complaints, the failed count.
/// When no object could be diagnosed nothing is written and the exit code is 2.
BatchRunOutcome finish_per_object(std::vector<DiagnosedObject> objects, std::size_t pushes_read, bool read_failed,
                                  const std::string& read_failures, StagedOutput& out) {
  BatchRunOutcome outcome;
  outcome.notes = read_failures;
  std::vector<DiagnosisGroupOutcome> outcomes;
  std::size_t left_out = 0, failed = 0;
  for (auto& d : objects) {
    outcome.report += d.printed;
    outcome.notes += d.complaints;
    left_out += d.left_out;
    failed += d.outcome.result ? 0 : 1;
    outcomes.push_back(std::move(d.outcome));
  }
  if (failed == outcomes.size()) {
    outcome.notes += "pushpred: error: no object could be diagnosed; nothing written\n";
    outcome.exit_code = 2;
    return outcome;
  }
  write_text_atomically(out.path("overview.md"), diagnosis_overview_markdown(outcomes));
  write_text_atomically(out.path("overview.json"), json_file_text(diagnosis_overview_json(outcomes)));
  out.commit();
  outcome.report += std::to_string(outcomes.size() - failed) + " of " + std::to_string(outcomes.size()) +
                    " objects diagnosed (" + std::to_string(pushes_read) + " pushes read); overview in " +
                    out.destination().string() + "/overview.md\n";
  if (failed > 0)
    outcome.notes += std::to_string(failed) + " of " + std::to_string(outcomes.size()) + " objects failed\n";
  outcome.exit_code = failed == 0 && left_out == 0 && !read_failed ? 0 : 1;
  return outcome;
}

/// The objects of a per-object run, in order, made into its overview (diagnosis_overview_renderer).
class DiagnosisRenderer final : public BatchRenderer<DiagnosedObject> {
 public:
  DiagnosisRenderer(StagedOutput& out, std::size_t pushes_read, std::vector<BatchFailure> read_failures, bool list)
      : out_(out), pushes_read_(pushes_read), read_failures_(std::move(read_failures)), list_(list) {}
  void add(std::size_t, DiagnosedObject&& done) override { objects_.push_back(std::move(done)); }
  void add_failure(std::size_t, BatchFailure&& failure) override {
    DiagnosedObject d;  // an object's diagnosis catches its input errors: only the unexpected reaches here
    d.outcome.name = failure.source;
    d.outcome.error = failure.reason;
    d.complaints = "FAILED " + failure.source + ": " + failure.reason + "\n";
    objects_.push_back(std::move(d));
  }
  BatchRunOutcome finish() override {
    return finish_per_object(std::move(objects_), pushes_read_, !read_failures_.empty(),
                             list_ ? failure_lines(read_failures_) : std::string(), out_);
  }

 private:
  StagedOutput& out_;
  std::size_t pushes_read_;
  std::vector<BatchFailure> read_failures_;
  bool list_;
  std::vector<DiagnosedObject> objects_;
};

}  // namespace

std::unique_ptr<BatchRenderer<DiagnosedObject>> diagnosis_overview_renderer(StagedOutput& out, std::size_t pushes_read,
                                                                            std::vector<BatchFailure> read_failures,
                                                                            bool list_read_failures) {
  return std::make_unique<DiagnosisRenderer>(out, pushes_read, std::move(read_failures), list_read_failures);
}

}  // namespace pushpred
