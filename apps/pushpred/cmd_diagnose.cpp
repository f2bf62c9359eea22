// `pushpred diagnose FILE... --out DIR`: finds what the paper's method leaves unexplained on pushes of one object,
// tests a library of candidate physical effects against it, adds the selected ones and reports the prediction
// error before and after on held-out phases (DIR/diagnosis.json, DIR/report.md, plots). With --per-object, a batch
// of several objects or surfaces is diagnosed one object at a time: DIR/<shape>_on_<surface>/ each, and
// DIR/overview.md and DIR/overview.json side by side; `--shard I/N` then runs share I of N of the objects as a
// partial output for `pushpred merge`, and under mpirun the ranks split the objects (jobs/diagnosis_job.hpp).
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/jobs/diagnosis_job.hpp"
#include "pushpred/runtime/parallel_batch.hpp"
#include "study_arguments.hpp"

namespace pushpred::app {
namespace {

struct DiagnoseArgs {
  std::vector<std::string> files;
  std::string out, shape, shard;
  bool shard_given = false;  ///< --shard was given (an empty spec is an error, not the whole run)
  StudyArguments study;
  double bic_threshold = 10.0, rate_hz = 250.0;
  std::vector<std::string> exclude;
  bool per_object = false, no_plots = false, quick_base = false, measured_contact_compliance = false;
  double relevance_fraction = 0.05, floor_margin_std = 1.0, sensor_zero_spread_N = kSensorZeroSpread_N;
  int jobs = default_jobs();
};

int run_diagnose(const DiagnoseArgs& a) {
  DiagnoseRun run;
  if (a.shard_given) run.shard = parse_shard_spec(a.shard);
  run.options.study = a.study.options();
  run.options.bic_threshold = a.bic_threshold;
  run.options.relevance_fraction = a.relevance_fraction;
  run.options.floor_margin_std = a.floor_margin_std;
  run.options.sensor_zero_spread_N = a.sensor_zero_spread_N;
  run.options.measured_contact_compliance = a.measured_contact_compliance;
  run.options.fit_base_settings = !a.quick_base;
  run.exclude = a.exclude;
  run.preprocess.rate_hz = a.rate_hz;
  run.inputs = a.files;
  run.out = a.out;
  run.shape = a.shape;
  run.per_object = a.per_object;
  run.plots = !a.no_plots;
  run.jobs = a.jobs;
  run.mpi = mpi_session();
  return finish_outcome(pushpred::run_diagnose(run));
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<DiagnoseArgs>();
  auto* sub = app.add_subcommand(
      "diagnose", "Find the residual of the paper's method, test candidate effects, report the error before and after");
  add_recordings(*sub, a->files, "Recordings of one object on one surface (.h5 or .json), or folders of them");
  add_out_folder(*sub, a->out, "Output folder (diagnosis.json, report.md, plots)");
  add_shape(*sub, a->shape);
  a->study.add_to(*sub, {3, false, true, true});  // the diagnosis runs the paper's observer
  sub->add_option("--bic-threshold", a->bic_threshold, "BIC drop an effect needs to be selected (default 10)")
      ->check(kNonNegativeNumber);
  sub->add_option("--exclude", a->exclude, "Candidate effect kinds to leave out (repeatable)");
  sub->add_flag("--per-object", a->per_object,
                "Diagnose each object and surface of the batch on its own (DIR/<shape>_on_<surface>/, DIR/overview.md)");
  sub->add_option("--relevance", a->relevance_fraction,
                  "Share of the support friction force below which an effect is negligible (default 0.05)")
      ->check(CLI::Range(1e-6, 0.999999));
  add_floor_margin(*sub, a->floor_margin_std);
  add_sensor_zero_spread(*sub, a->sensor_zero_spread_N);
  add_measured_contact_compliance(*sub, a->measured_contact_compliance);
  sub->add_flag("--quick-base", a->quick_base,
                "Do not fit the base model's settings (quasi-static stop fraction) on the fit phases: faster");
  sub->add_flag("--no-plots", a->no_plots, "Do not draw plots");
  add_rate(*sub, a->rate_hz);
  add_jobs(*sub, a->jobs,
           "Files read, and with --per-object objects diagnosed, in parallel (default: all cores); the output does "
           "not depend on it");
  auto* shard = add_shard(*sub, a->shard,
                          "With --per-object only: only share I of N of the objects (the objects sorted by name, the "
                          "k-th goes to share k mod N + 1; every share reads every file); writes a partial output "
                          "folder that `pushpred merge` combines with the other shares' into what one run writes. "
                          "Under mpirun -np N (with --per-object) the ranks split the objects so, and rank 0 writes "
                          "the whole output");
  sub->callback([a, shard, &run] {
    a->shard_given = shard->count() > 0;
    run = [a] { return run_diagnose(*a); };
  });
});

}  // namespace
}  // namespace pushpred::app
