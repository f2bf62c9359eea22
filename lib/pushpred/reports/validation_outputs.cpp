#include "pushpred/reports/validation_outputs.hpp"

#include <sstream>
#include <string>
#include <utility>

#include "pushpred/core/error.hpp"
#include "pushpred/reports/validation_report.hpp"

namespace pushpred {
namespace {

/// Writes validation.json and validation.md, commits `out`, and says what the whole run says.
BatchRunOutcome write_validation_outputs(const ValidationResult& r, StagedOutput& out) {
  write_text_atomically(out.path("validation.json"), validation_json(r).dump(2) + "\n");
  write_text_atomically(out.path("validation.md"), validation_markdown(r));
  out.commit();
  const ValidationSummary s = summarise_validation(r);
  std::ostringstream report;
  report << "right kind named at >= 2 floors: " << s.named_at_twice_floor << " / " << s.effect_trials_at_twice_floor
         << "; nothing named on clean: " << s.clean_nothing_named << " / " << s.clean_trials
         << "; corrected below the paper: " << s.after_below_paper << " / " << s.compared
         << ", below const_velocity: " << s.after_below_const_velocity << " / " << s.compared << "\n";
  if (s.hidden_trials_at_twice_floor > 0 || s.clean_adequacy_tested > 0)
    report << "hidden kinds at >= 2 floors: unexplained " << s.hidden_unexplained << " / " << s.hidden_adequacy_tested
           << " tested (" << s.hidden_trials_at_twice_floor << " trials), no kind named " << s.hidden_none_named
           << " / " << s.hidden_trials_at_twice_floor << "; clean explained " << s.clean_explained << " / "
           << s.clean_adequacy_tested << " tested\n";
  report << "report in " << out.destination().string() << "/validation.md\n";
  BatchRunOutcome outcome;
  outcome.report = report.str();
  if (s.failed > 0)
    outcome.notes = std::to_string(s.failed) + " trial(s) could not be diagnosed (listed in validation.md)\n";
  outcome.exit_code = s.failed > 0 ? 1 : 0;
  return outcome;
}

/// The trials of a run, in order, made into validation.json and validation.md.
class ValidationRenderer final : public BatchRenderer<ValidationTrial> {
 public:
  ValidationRenderer(StagedOutput& out, ValidationOptions options) : out_(out) { result_.options = std::move(options); }
  void add(std::size_t index, ValidationTrial&& trial) override {
    if (trial.index != static_cast<int>(index))
      throw InputError("trial " + std::to_string(index) + ": its index differs");
    result_.trials.push_back(std::move(trial));
  }
  void add_failure(std::size_t index, BatchFailure&& failure) override {
    ValidationTrial trial;  // a trial catches what a diagnosis throws: only the unexpected reaches here
    trial.index = static_cast<int>(index);
    trial.failure = failure.reason;
    result_.trials.push_back(std::move(trial));
  }
  BatchRunOutcome finish() override { return write_validation_outputs(result_, out_); }

 private:
  StagedOutput& out_;
  ValidationResult result_;
};

}  // namespace

std::unique_ptr<BatchRenderer<ValidationTrial>> validation_renderer(StagedOutput& out, ValidationOptions options) {
  return std::make_unique<ValidationRenderer>(out, std::move(options));
}

}  // namespace pushpred
