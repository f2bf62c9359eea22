#pragma once
// `pushpred diagnose` as a batch: one diagnosis of one object, or (--per-object) one diagnosis per object and
// surface, the whole run, one shard of it (`--shard I/N`, a partial output), an MPI job (`mpirun -np N`, rank 0
// writes), and `pushpred merge`, which turns the shards' partial outputs into what the whole run writes, byte for
// byte (runtime/shard.hpp has the partial format). reports/diagnosis_report.hpp writes each object's report and
// reports/diagnosis_overview.hpp the overview. The apps only parse arguments and call these.
//
// With --per-object the unit of work is one object group (PushGroup, sorted by name): the k-th group goes to shard
// k mod N + 1. Every shard (and every MPI rank) reads every input file, since which groups there are is known only
// once the files are read; reading is cheap next to a diagnosis. A diagnosis of one object is one unit and cannot
// be split: --shard (and mpirun) without --per-object are refused.
#include <optional>
#include <string>
#include <vector>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/shard.hpp"

namespace pushpred {

class MpiSession;

inline constexpr const char* kDiagnoseCommand = "diagnose";

/// `pushpred diagnose FILE... --out DIR`.
struct DiagnoseRun {
  std::vector<std::string> inputs;  ///< files or folders, as given
  std::string out;
  std::string shape;  ///< for files whose name does not carry it
  DiagnosisOptions options;
  std::vector<std::string> exclude;  ///< candidate effect kinds left out
  PreprocessOptions preprocess;
  bool per_object = false;
  bool plots = true;
  int jobs = 1;
  std::optional<ShardSpec> shard;   ///< given (1/1 included; --per-object only): a partial output of that share
  const MpiSession* mpi = nullptr;  ///< the program's MPI session: the ranks split the objects when it has several
};

/// Runs the diagnosis and writes its outputs: DIR/diagnosis.json, report.md, ... for one object; with --per-object
/// DIR/<shape>_on_<surface>/ per object and DIR/overview.md, overview.json, or the partial output of a shard.
/// Launched by mpirun as one of N ranks (--per-object only): the ranks split the objects as --shard R+1/N and rank 0
/// writes what one process would. Inputs that cannot be read are listed on stderr as soon as they are read. The
/// outcome carries the exit code: 0 all used, 1 something failed or was left out, 2 nothing written (no object
/// could be diagnosed). Throws InputError (nothing written) for bad options, --shard without --per-object, no
/// readable push, or a bad output folder.
BatchRunOutcome run_diagnose(const DiagnoseRun& run);

/// The checked parts of a `diagnose --per-object` run written to `out` as the whole run writes them: each object's
/// folder, overview.md and overview.json; the outcome prints what the whole run prints (the unreadable inputs
/// included). Nothing is committed when no object could be diagnosed.
BatchRunOutcome write_merged_diagnoses(const MergedParts& merged, StagedOutput& out);

}  // namespace pushpred
