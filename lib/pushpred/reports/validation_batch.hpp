#pragma once
// `pushpred validate-diagnosis` as a batch of trials: the whole run, one shard of it (`--shard I/N`: trial k goes to
// shard k mod N + 1, a partial output), an MPI job (rank 0 writes), and the merge of the shards' partial outputs
// into what the whole run writes, byte for byte (runtime/shard.hpp has the partial format).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "pushpred/diagnosis/validation.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/shard.hpp"

namespace pushpred {

class MpiSession;

inline constexpr const char* kValidationCommand = "validate-diagnosis";

/// A trial as exact JSON (doubles read back to the same bits, non-finite ones by name), and back; the latter throws
/// InputError on a malformed document.
nlohmann::json validation_trial_exact_json(const ValidationTrial& trial);
ValidationTrial validation_trial_from_exact_json(const nlohmann::json& doc);

struct ValidateRun {
  ValidationOptions options;
  std::string out;
  std::optional<ShardSpec> shard;  ///< given: only that share of the trials, as a partial output
  bool progress = true;            ///< trials done on stderr
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
