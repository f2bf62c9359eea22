#pragma once
// `pushpred predict` as a batch of pushes (runtime/batch_runner.hpp runs it whole, as a shard or over MPI ranks): the
// item function that studies one push, the codec of a study in a partial output (partial_codecs.hpp), and the merge
// of the shards' partial outputs. reports/prediction_outputs.hpp makes the outputs from the studies in input order
// (summary.json, tables.md, predictions/NAME.csv), for a whole run and a merge alike. The apps only parse arguments
// and call these.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/shard.hpp"

namespace pushpred {

class MpiSession;

/// `pushpred predict FILE... --out DIR`.
struct PredictRun {
  std::vector<std::string> inputs;  ///< files or folders, as given
  std::string out;
  std::string shape;
  StudyOptions study;
  PreprocessOptions preprocess;
  int jobs = 1;
  std::optional<ShardSpec> shard;   ///< given (1/1 included): a partial output of that share; none: the whole run
  const MpiSession* mpi = nullptr;  ///< the program's MPI session: the ranks split the inputs when it has several
};

/// Runs the study on every input (or on the shard's, or on this MPI rank's) and writes the outputs: summary.json,
/// tables.md and predictions/NAME.csv for a whole run, or the partial output of a shard. Launched by mpirun as one
/// of N ranks: the ranks split the inputs as --shard R+1/N and rank 0 writes what one process would. Throws
/// InputError (nothing written) for a bad output folder, or --shard under mpirun.
BatchRunOutcome run_predict(const PredictRun& run);

/// The checked parts of a `predict` run (check_partial_outputs) written to `out` as the whole run writes them: each
/// item's files in input order, summary.json and tables.md; committed unless no input gave a result.
BatchRunOutcome write_merged_predictions(const MergedParts& merged, StagedOutput& out);

}  // namespace pushpred
