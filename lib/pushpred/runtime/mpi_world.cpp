#include "pushpred/runtime/mpi_world.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/core/error.hpp"

#ifdef PUSHPRED_HAVE_MPI
// The C interface only: Open MPI's and MPICH's C++ bindings (deprecated) do not compile cleanly with -Wextra.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace pushpred {
namespace {

int env_count(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return 0;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  return (*end == '\0' && n > 0 && n < 1000000000) ? static_cast<int>(n) : 0;
}

#ifdef PUSHPRED_HAVE_MPI
// Texts go in pieces of at most this many bytes (an MPI count is an int).
constexpr std::uint64_t kPiece = 1u << 30;
#endif

}  // namespace

bool mpi_built() {
#ifdef PUSHPRED_HAVE_MPI
  return true;
#else
  return false;
#endif
}

bool mpi_launched() {
  return env_count("OMPI_COMM_WORLD_SIZE") > 0 || env_count("PMI_SIZE") > 0 || std::getenv("PMIX_RANK") != nullptr;
}

int mpi_launch_size() {
  const int n = std::max(env_count("OMPI_COMM_WORLD_SIZE"), env_count("PMI_SIZE"));
  return n > 0 ? n : 1;
}

int mpi_launch_rank() { return std::max(env_count("OMPI_COMM_WORLD_RANK"), env_count("PMI_RANK")); }

MpiSession::MpiSession() {
#ifdef PUSHPRED_HAVE_MPI
  if (!mpi_launched()) return;
  int provided = 0;
  // Only the main thread calls MPI; worker threads (--jobs) never do.
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
    throw InputError("MPI could not be initialised (launched by mpirun, but MPI_Init_thread failed)");
  initialised_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
#else
  if (mpi_launch_size() > 1)
    throw InputError("started as one of " + std::to_string(mpi_launch_size()) +
                     " processes by an MPI launcher, but this pushpred was built without MPI: every process would do "
                     "the whole job; rebuild with MPI (libopenmpi-dev), or use --shard I/N and pushpred merge");
#endif
}

MpiSession::~MpiSession() {
#ifdef PUSHPRED_HAVE_MPI
  if (!initialised_) return;
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (!finalised) MPI_Finalize();
#endif
}

void MpiSession::send_to_root(const std::function<std::optional<std::string>()>& next,
                              const std::function<void(int rank, const std::string& text)>& take) const {
  if (root())
    while (auto text = next()) take(0, *text);
  if (size_ == 1) return;
#ifdef PUSHPRED_HAVE_MPI
  // A text is its length, then its pieces; a rank's last message is the length kEnd.
  constexpr std::uint64_t kEnd = ~std::uint64_t{0};
  if (!root()) {
    while (auto text = next()) {
      const std::uint64_t length = text->size();
      MPI_Send(&length, 1, MPI_UINT64_T, 0, 0, MPI_COMM_WORLD);
      for (std::uint64_t at = 0; at < length; at += kPiece)
        MPI_Send(text->data() + at, static_cast<int>(std::min(kPiece, length - at)), MPI_CHAR, 0, 0, MPI_COMM_WORLD);
    }
    MPI_Send(&kEnd, 1, MPI_UINT64_T, 0, 0, MPI_COMM_WORLD);
    return;
  }
  for (int r = 1; r < size_; ++r) {
    // One sender's messages arrive in the order sent.
    for (;;) {
      std::uint64_t length = 0;
      MPI_Recv(&length, 1, MPI_UINT64_T, r, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      if (length == kEnd) break;
      std::string t(length, '\0');
      for (std::uint64_t at = 0; at < length; at += kPiece)
        MPI_Recv(&t[at], static_cast<int>(std::min(kPiece, length - at)), MPI_CHAR, r, 0, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
      take(r, t);
    }
  }
#endif
}

void MpiSession::abort(int code) const {
#ifdef PUSHPRED_HAVE_MPI
  if (initialised_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

void open_output_at_root(const MpiSession* session, const std::string& out, std::optional<StagedOutput>& staged) {
  const bool mpi = session && session->size() > 1;
  if (mpi && !session->root()) return;
  try {
    staged.emplace(out);
  } catch (const std::exception& e) {
    if (!mpi) throw;
    std::cerr << "pushpred: error: " << plain_text(e.what()) << "\n";
    session->abort(2);
  }
}

BatchRunOutcome merge_at_root(const MpiSession& world, std::string manifest, const std::filesystem::path& files_folder,
                              const std::vector<std::string>& files,
                              const std::function<BatchRunOutcome(const MergedParts&)>& write_merged) {
  try {
    write_text_atomically(files_folder / kPartialManifestName, manifest);
  } catch (const std::exception& e) {
    // Rank 0 waits for this rank's messages (or the others for rank 0's merge): only stopping the job ends the wait.
    std::cerr << "pushpred: error: " << plain_text(e.what()) << "\n";
    world.abort(2);
  }
  std::string().swap(manifest);
  return merge_at_root(world, files_folder, files, write_merged);
}

BatchRunOutcome merge_at_root(const MpiSession& world, const std::filesystem::path& files_folder,
                              const std::vector<std::string>& files,
                              const std::function<BatchRunOutcome(const MergedParts&)>& write_merged) {
  if (!world.root()) {
    // partial.json first, then each file, each read from disk as it is sent: one file in memory at a time.
    std::size_t sent = 0;
    bool manifest_sent = false;
    try {
      world.send_to_root(
          [&]() -> std::optional<std::string> {
            if (!manifest_sent) {
              manifest_sent = true;
              return file_bundle_of(kPartialManifestName, files_folder / kPartialManifestName);
            }
            if (sent == files.size()) return std::nullopt;
            const std::string& name = files[sent++];
            return file_bundle_of(name, files_folder / name);
          },
          nullptr);
    } catch (const std::exception& e) {
      // Rank 0 is waiting for this rank's next message: only stopping the job ends the wait.
      std::cerr << "pushpred: error: " << plain_text(e.what()) << "\n";
      world.abort(2);
    }
    BatchRunOutcome quiet;
    quiet.quiet = true;
    return quiet;
  }
  try {
    // Destroyed (the folder removed) before the handler below runs: MPI_Abort would not unwind the stack.
    const ScratchFolder scratch("merge");
    const auto folder_of = [&](int r) { return r == 0 ? files_folder : scratch.path() / ("rank" + std::to_string(r)); };
    const auto name_of = [](int r) { return "rank " + std::to_string(r); };
    world.send_to_root([] { return std::optional<std::string>(); },
                       [&](int r, const std::string& text) { unpack_file_bundle(name_of(r), text, folder_of(r)); });
    std::vector<PartialOutput> parts;
    for (int r = 0; r < world.size(); ++r) parts.push_back(read_partial_output(folder_of(r), name_of(r)));
    return write_merged(check_partial_outputs(std::move(parts)));
  } catch (const std::exception& e) {
    std::cerr << "pushpred: error: " << plain_text(e.what()) << "\n";
    world.abort(2);
  }
}

}  // namespace pushpred
