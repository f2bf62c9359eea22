#pragma once
// `pushpred predict` as a batch: the whole run over every input, one shard of it (`--shard I/N`, a partial output),
// an MPI job (`mpirun -np N`, rank 0 writes), and `pushpred merge`, which turns the shards' partial outputs into
// what the whole run writes, byte for byte (core/shard.hpp has the split and the partial format). The apps only
// parse arguments and call these.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/core/batch.hpp"
#include "pushpred/core/output_files.hpp"
#include "pushpred/core/shard.hpp"
#include "pushpred/prediction/prediction_study.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"

namespace pushpred {

/// What a batch command did: the failures to list, how many inputs gave results, and what it prints on stdout.
/// `partial`: a shard's partial output was written (its failures are listed, but a merge decides the exit code).
/// `quiet`: an MPI rank other than 0 (rank 0 lists and prints everything).
struct BatchRunOutcome {
  std::vector<BatchFailure> failures;
  std::size_t used = 0;
  std::string report;
  bool partial = false;
  bool quiet = false;
};

/// A study as exact JSON, for a partial output: every field drop_samples keeps, doubles written so that they read
/// back to the same bits (non-finite ones as "nan", "inf", "-inf").
nlohmann::json push_study_exact_json(const PushStudy& study);
/// The study push_study_exact_json wrote (without samples, as drop_samples leaves it); throws InputError on a
/// malformed document.
PushStudy push_study_from_exact_json(const nlohmann::json& doc);

/// `pushpred predict FILE... --out DIR`.
struct PredictRun {
  std::vector<std::string> inputs;  ///< files or folders, as given
  std::string out;
  std::string shape;
  StudyOptions study;
  PreprocessOptions preprocess;
  int jobs = 1;
  std::optional<ShardSpec> shard;  ///< given (1/1 included): a partial output of that share; none: the whole run
};

/// Runs the study on every input (or on the shard's, or on this MPI rank's) and writes the outputs: summary.json,
/// tables.md and predictions/NAME.csv for a whole run, or the partial output of a shard. Launched by mpirun as one
/// of N ranks: the ranks split the inputs as --shard R+1/N and rank 0 writes what one process would. Throws
/// InputError (nothing written) for a bad output folder, or --shard under mpirun.
BatchRunOutcome run_predict(const PredictRun& run);

/// `pushpred merge --out DIR PART...`: the partial outputs `parts` (folders written with --shard) combined into what
/// one run over every input writes. Throws InputError naming the part and the problem (nothing written) when the
/// parts are not every shard of one run.
BatchRunOutcome merge_partial_outputs(const std::vector<std::string>& parts, const std::string& out);

}  // namespace pushpred
