// `pushpred validate-diagnosis --trials N --seed S --out DIR`: the diagnosis tried blind on randomized simulated
// physics (diagnosis/validation.hpp); writes DIR/validation.md and DIR/validation.json.
#include <iostream>
#include <memory>
#include <thread>
#include <unistd.h>

#include "commands.hpp"
#include "pushpred/core/output_files.hpp"
#include "pushpred/diagnosis/validation.hpp"
#include "pushpred/reports/validation_report.hpp"

namespace pushpred::app {
namespace {

struct ValidateArgs {
  ValidationOptions options;
  std::string out;
};

int run_validate(const ValidateArgs& a) {
  StagedOutput out(a.out);  // checks the destination before the long run
  const bool terminal = isatty(STDERR_FILENO) != 0;
  const ValidationResult r = validate_diagnosis(a.options, [&](int done, int total) {
    if (terminal)
      std::cerr << "\rtrials " << done << " / " << total << std::flush;
    else if (done == total || done % 10 == 0)
      std::cerr << "trials " << done << " / " << total << "\n";
  });
  if (terminal) std::cerr << "\n";
  write_text_atomically(out.path("validation.json"), validation_json(r).dump(2) + "\n");
  write_text_atomically(out.path("validation.md"), validation_markdown(r));
  out.commit();
  const ValidationSummary s = summarise_validation(r);
  std::cout << "right kind named at >= 2 floors: " << s.named_at_twice_floor << " / " << s.effect_trials_at_twice_floor
            << "; nothing named on clean: " << s.clean_nothing_named << " / " << s.clean_trials
            << "; corrected below the paper: " << s.after_below_paper << " / " << s.compared
            << ", below const_velocity: " << s.after_below_const_velocity << " / " << s.compared << "\n"
            << "report in " << a.out << "/validation.md\n";
  if (s.failed > 0) std::cerr << s.failed << " trial(s) could not be diagnosed (listed in validation.md)\n";
  return s.failed > 0 ? 1 : 0;
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<ValidateArgs>();
  a->options.jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  auto* sub = app.add_subcommand("validate-diagnosis",
                                 "Try the diagnosis blind on randomized simulated pushes, one hidden effect or none "
                                 "per trial: confusion matrix, detection rate, false findings, errors");
  sub->add_option("--trials", a->options.trials_per_kind, "Trials per kind (default 20)")->check(CLI::PositiveNumber);
  sub->add_option("--seed", a->options.seed, "Seed of the first trial; trial k uses seed + k (default 1)");
  sub->add_option("--out", a->out, "Output folder (validation.md, validation.json)")->required();
  sub->add_option("--kinds", a->options.kinds, "Kinds to draw: none and simulator effect names (default: all)")
      ->delimiter(',');
  sub->add_option("--min-pushes", a->options.min_pushes, "Fewest pushes per trial (default 4)");
  sub->add_option("--max-pushes", a->options.max_pushes, "Most pushes per trial (default 8)");
  sub->add_option("--relevance", a->options.diagnosis.relevance_fraction,
                  "Share of the support friction below which an effect is negligible (default 0.05)")
      ->check(CLI::Range(1e-6, 0.999999));
  sub->add_option("--bic-threshold", a->options.diagnosis.bic_threshold, "BIC drop a test needs (default 10)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--jobs", a->options.jobs, "Trials run in parallel (default: all cores)")->check(CLI::PositiveNumber);
  sub->add_flag("--quick-base", [a](std::int64_t) { a->options.diagnosis.fit_base_settings = false; },
                "Do not fit the base model's settings on the fit phases: faster");
  add_shard_refusal(*sub);
  sub->callback([a, &run] {
    run = [a] {
      a->options.validate();  // before any work: a bad kind or range is an input error (exit 2), nothing written
      return run_validate(*a);
    };
  });
});

}  // namespace
}  // namespace pushpred::app
