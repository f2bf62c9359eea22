#pragma once
// `pushpred validate-diagnosis` as a batch of trials (runtime/batch_runner.hpp runs it whole, as a shard or over MPI
// ranks; trial k goes to shard k mod N + 1): the item function that runs one trial, the codec of a trial in a partial
// output (partial_codecs.hpp), and the merge of the shards' partial outputs into what the whole run writes, byte for
// byte. reports/validation_outputs.hpp writes the outputs. The apps only parse arguments and call these.
#include <optional>
#include <string>

#include "pushpred/diagnosis/validation.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/shard.hpp"

namespace pushpred {

class MpiSession;

inline constexpr const char* kValidationCommand = "validate-diagnosis";

/// `pushpred validate-diagnosis --out DIR`.
struct ValidateRun {
  ValidationOptions options;
  std::string out;
  std::optional<ShardSpec> shard;   ///< given: only that share of the trials, as a partial output
  bool progress = true;             ///< trials done on stderr
  const MpiSession* mpi = nullptr;  ///< the program's MPI session: the ranks split the trials when it has several
};

/// Runs the trials (all, the shard's, or this MPI rank's: launched by mpirun as one of N ranks, rank R runs the
/// share R+1/N and rank 0 writes) and writes validation.json and validation.md, or the shard's partial output. The
/// outcome's exit code is 1 when some trial could not be diagnosed, 0 otherwise. Throws InputError (nothing
/// written) for bad options or a bad output folder.
BatchRunOutcome run_validation(const ValidateRun& run);

/// The checked parts of a validate-diagnosis run written to `out` as the whole run writes them.
BatchRunOutcome write_merged_validation(const MergedParts& merged, StagedOutput& out);

}  // namespace pushpred
