#pragma once
// The MPI job a process runs in: `mpirun -np N pushpred predict ...` (validate-diagnosis, diagnose --per-object)
// splits the inputs over the N ranks as `--shard R+1/N` would (shard.hpp, batch_runner.hpp), and the ranks send their
// partial outputs to rank 0, which writes what one process writes. MPI is optional at build time (CMake's
// find_package(MPI COMPONENTS C)); mpi_built() says whether this build has it. MPI is initialised only in a process
// that a launcher started (mpirun, mpiexec, srun: one of OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK is set), so a plain
// run never touches it.
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pushpred/runtime/output_files.hpp"
#include "pushpred/runtime/shard.hpp"

namespace pushpred {

/// True when this build was made with MPI.
bool mpi_built();

/// True when a launcher started this process (one of OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK is set): a program
/// then makes its MpiSession. Reads the environment only.
bool mpi_launched();
/// The number of processes a launcher says this one is part of (OMPI_COMM_WORLD_SIZE or PMI_SIZE), 1 when not
/// launched by one. Reads the environment only; does not initialise MPI.
int mpi_launch_size();
/// This process's rank as the launcher states it (OMPI_COMM_WORLD_RANK or PMI_RANK), 0 when not launched by one.
/// Reads the environment only: for saying something once per job before MPI is initialised.
int mpi_launch_rank();

/// This process's place in its MPI job, for as long as the object lives: the program makes one (apps/pushpred's main,
/// when a launcher started it as one of several processes), which initialises MPI, and hands it to the commands that
/// split their work; its destruction finalises MPI. A library that is not such a program never initialises MPI.
class MpiSession {
 public:
  /// Initialises MPI when the process was launched by a launcher (and MPI is built); otherwise rank 0 of 1. Throws
  /// InputError when launched as one of several processes by a build without MPI (each would do the whole job and
  /// write the same output), or when MPI cannot be initialised.
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }

  /// Every rank's texts to rank 0, one text at a time: each rank pulls its texts from `next` (until it returns
  /// nothing), and rank 0 calls `take(r, text)` for each of rank r's texts in order, for r = 0, 1, ..., N-1 (its own
  /// first), receiving a text only once take has returned for the one before and dropping each when its take returns,
  /// so that rank 0 holds one text at a time and a rank one of its own (memory would otherwise grow with the whole
  /// job). The other ranks send theirs (waiting until rank 0 takes them) and never call take. Called by every rank
  /// alike. Texts may be longer than an MPI count (sent in pieces, point to point).
  void send_to_root(const std::function<std::optional<std::string>()>& next,
                    const std::function<void(int rank, const std::string& text)>& take) const;

  /// Stops every rank of the job with `code` (after an error on one rank that the others cannot know of); a process
  /// not in a job just exits with it.
  [[noreturn]] void abort(int code) const;

 private:
  int rank_ = 0, size_ = 1;
  bool initialised_ = false;
};

/// Opens a batch's output folder `out` into `staged`, first, so that a bad one fails before any work: on rank 0 only
/// under mpirun (`session` of several ranks; `staged` stays empty on the other ranks, which do not write), always in
/// a plain run (`session` null or of one rank). A bad folder throws (InputError) in a plain run; under mpirun it is
/// printed and stops every rank with exit code 2. (An output parameter: a StagedOutput cannot be moved.)
void open_output_at_root(const MpiSession* session, const std::string& out, std::optional<StagedOutput>& staged);

/// Ends a batch run under mpirun: every rank's partial output (its partial.json in its own folder `files_folder`,
/// and the `files` it wrote there, relative paths) goes to rank 0. Rank 0's folder is its part; every other rank
/// sends its partial.json and then its files one at a time (file_bundle_of), each read from disk when sent, and rank
/// 0 writes each as it arrives into a scratch folder under the temporary folder (ScratchFolder, laid out as `--shard`
/// writes a partial output), so that no rank holds more than one file at a time. Rank 0 then
/// reads the parts back from disk (read_partial_output, files read when written), checks them as one batch
/// (check_partial_outputs) and writes them with `write_merged`; the other ranks return a quiet outcome. The scratch
/// folder is removed on every way out. A failure of the check or the write is printed and stops every rank with
/// exit code 2.
BatchRunOutcome merge_at_root(const MpiSession& session, const std::filesystem::path& files_folder,
                              const std::vector<std::string>& files,
                              const std::function<BatchRunOutcome(const MergedParts&)>& write_merged);
/// The same for a rank whose partial.json is the text `manifest` (partial_manifest's), first written into its folder.
BatchRunOutcome merge_at_root(const MpiSession& session, std::string manifest,
                              const std::filesystem::path& files_folder, const std::vector<std::string>& files,
                              const std::function<BatchRunOutcome(const MergedParts&)>& write_merged);

}  // namespace pushpred
