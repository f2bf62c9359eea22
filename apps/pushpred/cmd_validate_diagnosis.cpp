// `pushpred validate-diagnosis --trials N --seed S --out DIR`: the diagnosis tried blind on randomized simulated
// physics (diagnosis/validation.hpp); writes DIR/validation.md and DIR/validation.json. `--shard I/N` runs share I of
// N of the trials as a partial output for `pushpred merge`; under mpirun the ranks split the trials
// (jobs/validation_job.hpp).
#include <memory>
#include <thread>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/jobs/validation_job.hpp"

namespace pushpred::app {
namespace {

struct ValidateArgs {
  ValidationOptions options;
  std::string out, shard;
  bool shard_given = false;
};

int run_validate(const ValidateArgs& a) {
  ValidateRun run;
  run.options = a.options;
  run.out = a.out;
  run.mpi = mpi_session();
  if (a.shard_given) run.shard = parse_shard_spec(a.shard);
  return finish_outcome(run_validation(run));
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<ValidateArgs>();
  a->options.jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  auto* sub = app.add_subcommand("validate-diagnosis",
                                 "Try the diagnosis blind on randomized simulated pushes, one hidden effect or none "
                                 "per trial: confusion matrix, detection rate, false findings, errors");
  sub->add_option("--trials", a->options.trials_per_kind, "Trials per kind (default 20)")->check(kPositiveNumber);
  sub->add_option("--seed", a->options.seed, "Seed of the first trial; trial k uses seed + k (default 1)")
      ->check(kSeed);
  add_out_folder(*sub, a->out, "Output folder (validation.md, validation.json)");
  sub->add_option("--kinds", a->options.kinds, "Kinds to draw: none and simulator effect names (default: all)")
      ->delimiter(',');
  sub->add_option("--hide", a->options.hide,
                  "Kinds left out of the diagnosis's catalogue but simulated: the honesty test (\"unexplained "
                  "residual\", no other kind named); with no --kinds the kinds drawn are none and these")
      ->delimiter(',');
  sub->add_flag(
      "--no-preloads", [a](std::int64_t) { a->options.draw_preloads = false; },
      "No preloads: every push starts 1 mm away from the object");
  sub->add_flag(
      "--no-sensor-offsets", [a](std::int64_t) { a->options.draw_sensor_offsets = false; },
      "No per-push force-sensor offsets: the sensor zeroed on every push");
  sub->add_option("--sensor-offset-spread", a->options.sensor_offset_spread_N,
                  "Push-to-push spread of the force sensor's zero, sd per axis in N (default 0.06: with the "
                  "simulated sensor's noise the rests spread as the real rig's do, 0.10 N; 0.6 is a pessimistic "
                  "bound; at most 2)")
      ->check(kNonNegativeNumber);
  sub->add_option("--min-pushes", a->options.min_pushes, "Fewest pushes per trial (default 4)");
  sub->add_option("--max-pushes", a->options.max_pushes, "Most pushes per trial (default 8, at most 100)");
  sub->add_option("--relevance", a->options.diagnosis.relevance_fraction,
                  "Share of the support friction below which an effect is negligible (default 0.05)")
      ->check(CLI::Range(1e-6, 0.999999));
  sub->add_option("--bic-threshold", a->options.diagnosis.bic_threshold, "BIC drop a test needs (default 10)")
      ->check(kNonNegativeNumber);
  add_floor_margin(*sub, a->options.diagnosis.floor_margin_std);
  add_sensor_zero_spread(*sub, a->options.diagnosis.sensor_zero_spread_N);
  add_measured_contact_compliance(*sub, a->options.diagnosis.measured_contact_compliance);
  add_jobs(*sub, a->options.jobs, "Trials run in parallel (default: all cores)");
  sub->add_flag("--quick-base", [a](std::int64_t) { a->options.diagnosis.fit_base_settings = false; },
                "Do not fit the base model's settings on the fit phases: faster");
  auto* shard = add_shard(*sub, a->shard,
                          "Only share I of N of the trials (trial k goes to share k mod N + 1); writes a partial "
                          "output folder that `pushpred merge` combines with the other shares' into what one run "
                          "writes. Under mpirun -np N the ranks split the trials so, and rank 0 writes the whole "
                          "output");
  sub->callback([a, shard, &run] {
    a->shard_given = shard->count() > 0;
    run = [a] { return run_validate(*a); };  // options checked before any work: exit 2, nothing written
  });
});

}  // namespace
}  // namespace pushpred::app
