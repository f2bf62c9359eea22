// `pushpred predict FILE... --out DIR`: the paper's identification/prediction study on each push, with the
// prediction methods chosen by name (default: every built-in one, predictor.hpp); DIR/summary.json, DIR/tables.md
// (per object and per pusher speed) and per-push CSVs. `--shard I/N` writes share I of N as a partial output for
// `pushpred merge`; under `mpirun -np N` the ranks split the pushes and rank 0 writes (jobs/prediction_job.hpp).
#include <memory>

#include "commands.hpp"
#include "flags.hpp"
#include "pushpred/jobs/prediction_job.hpp"
#include "pushpred/runtime/parallel_batch.hpp"
#include "study_arguments.hpp"

namespace pushpred::app {
namespace {

struct PredictArgs {
  std::vector<std::string> files;
  std::string out, shape, shard;
  bool shard_given = false;  ///< --shard was given (an empty spec is an error, not the whole run)
  StudyArguments study;
  double rate_hz = 250.0;
  int jobs = default_jobs();
};

int run_predict(const PredictArgs& a) {
  PredictRun run;
  if (a.shard_given) run.shard = parse_shard_spec(a.shard);
  run.study = a.study.options();
  run.preprocess.rate_hz = a.rate_hz;
  run.inputs = a.files;
  run.out = a.out;
  run.shape = a.shape;
  run.jobs = a.jobs;
  run.mpi = mpi_session();
  return finish_outcome(pushpred::run_predict(run));
}

const CommandRegistration reg([](CLI::App& app, Runner& run) {
  auto a = std::make_shared<PredictArgs>();
  auto* sub = app.add_subcommand("predict", "Identify and predict on each push as in the paper; write summary.json");
  add_recordings(*sub, a->files);
  add_out_folder(*sub, a->out);
  add_shape(*sub, a->shape);
  a->study.add_to(*sub, {2, true, true, true, true});
  add_rate(*sub, a->rate_hz);
  add_jobs(*sub, a->jobs, "Pushes studied in parallel (default: all cores); the output does not depend on it");
  auto* shard = add_shard(*sub, a->shard,
                          std::string(kShardHelp) +
                              ". Under mpirun -np N the ranks split the pushes so, and rank 0 writes the whole output");
  sub->callback([a, shard, &run] {
    a->shard_given = shard->count() > 0;
    run = [a] { return run_predict(*a); };
  });
});

}  // namespace
}  // namespace pushpred::app
