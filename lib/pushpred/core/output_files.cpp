#include "pushpred/core/output_files.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>
#include <system_error>

#include "pushpred/core/error.hpp"

namespace fs = std::filesystem;

namespace pushpred {
namespace {

std::string unique_suffix() {
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  return std::to_string(rd()) + "-" + std::to_string(counter++);
}

// --- The staging folders a signal handler must remove. Plain arrays and atomics: the handler may only read them.
constexpr int kSlots = 16;
constexpr std::size_t kMaxPath = 4096;
std::atomic<bool> slot_used[kSlots];
char slot_path[kSlots][kMaxPath];

int claim_slot(const fs::path& staging) {
  const std::string s = staging.string();
  if (s.size() >= kMaxPath) return -1;
  for (int i = 0; i < kSlots; ++i) {
    bool expected = false;
    if (slot_used[i].load() || !slot_used[i].compare_exchange_strong(expected, true)) continue;
    // Mark busy with an empty path first, then publish the path.
    slot_path[i][0] = '\0';
    std::memcpy(slot_path[i], s.c_str(), s.size() + 1);
    std::atomic_signal_fence(std::memory_order_seq_cst);
    return i;
  }
  return -1;  // more than kSlots live outputs: the folder is still removed on normal exit and by the next run
}

void release_slot(int i) {
  if (i < 0) return;
  slot_path[i][0] = '\0';
  std::atomic_signal_fence(std::memory_order_seq_cst);
  slot_used[i].store(false);
}

/// Removes the tree `name` below the open folder `parent_fd` with async-signal-safe system calls only (openat,
/// getdents64, unlinkat, close), for the signal handler. Depth-bounded; never follows links.
void remove_tree_at(int parent_fd, const char* name, int depth) {
  if (unlinkat(parent_fd, name, 0) == 0 || depth > 16) return;
  const int fd = openat(parent_fd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buffer[2048];
  for (;;) {
    const long n = syscall(SYS_getdents64, fd, buffer, sizeof buffer);
    if (n <= 0) break;
    bool removed_any = false;
    for (long off = 0; off < n;) {
      struct Entry {
        unsigned long long ino;
        long long off;
        unsigned short reclen;
        unsigned char type;
        char name[1];
      };
      const Entry* e = reinterpret_cast<const Entry*>(buffer + off);
      off += e->reclen;
      if (std::strcmp(e->name, ".") == 0 || std::strcmp(e->name, "..") == 0) continue;
      if (e->type == DT_DIR) remove_tree_at(fd, e->name, depth + 1);
      else unlinkat(fd, e->name, 0);
      removed_any = true;
    }
    if (!removed_any) break;
    lseek(fd, 0, SEEK_SET);  // entries were removed: list again from the start
  }
  close(fd);
  unlinkat(parent_fd, name, AT_REMOVEDIR);
}

extern "C" void remove_staging_and_reraise(int sig) {
  for (int i = 0; i < kSlots; ++i)
    if (slot_used[i].load() && slot_path[i][0] != '\0') remove_tree_at(AT_FDCWD, slot_path[i], 0);
  signal(sig, SIG_DFL);
  raise(sig);  // delivered when the handler returns: the process ends by the signal, as without the handler
}

bool process_alive(long pid) { return pid > 0 && (kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

/// Removes `.NAME.staging-PID-*` and `.NAME.replaced-PID-*` folders beside `target` whose process is gone and that
/// hold the marker (so only folders pushpred made).
void remove_stale_staging(const fs::path& target) {
  const std::string name = target.filename().string();
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(target.parent_path(), ec)) {
    const std::string other = entry.path().filename().string();
    for (const char* kind : {".staging-", ".replaced-"}) {
      const std::string prefix = "." + name + kind;
      if (other.rfind(prefix, 0) != 0) continue;
      const long pid = std::strtol(other.c_str() + prefix.size(), nullptr, 10);
      std::error_code ec2;
      if (!process_alive(pid) && fs::exists(entry.path() / kOutputMarker, ec2)) fs::remove_all(entry.path(), ec2);
    }
  }
}

bool is_empty_folder(const fs::path& p) {
  std::error_code ec;
  return fs::directory_iterator(p, ec) == fs::directory_iterator() && !ec;
}

}  // namespace

void write_text_atomically(const fs::path& path, const std::string& text) {
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw InputError(about(folder.string(), "cannot create folder: " + ec.message()));
  const fs::path tmp = folder / ("." + path.filename().string() + ".tmp-" + unique_suffix());
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw InputError(about(path.string(), "cannot open for writing"));
    out << text;
    out.close();
    if (!out) {
      fs::remove(tmp, ec);
      throw InputError(about(path.string(), "write failed"));
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(about(path.string(), "cannot move into place"));
  }
}

StagedOutput::StagedOutput(fs::path destination) : destination_(std::move(destination)) {
  if (destination_.empty()) throw InputError("output folder: empty path");
  const std::string shown = destination_.string();
  std::error_code ec;
  target_ = fs::absolute(destination_, ec).lexically_normal();
  if (!target_.has_filename()) target_ = target_.parent_path();  // "out/" and "." name the folder itself
  if (ec || target_.parent_path() == target_) throw InputError(about(shown, "cannot be used as an output folder"));
  if (fs::is_symlink(fs::symlink_status(target_, ec))) {
    target_ = fs::canonical(target_, ec);  // the folder the link names is the one replaced
    if (ec) throw InputError(about(shown, "is a link that cannot be followed: " + ec.message()));
  }
  const fs::file_status status = fs::status(target_, ec);
  if (fs::exists(status)) {
    if (!fs::is_directory(status)) throw InputError(about(shown, "exists and is not a folder"));
    if (!fs::exists(target_ / kOutputMarker, ec) && !is_empty_folder(target_))
      throw InputError(about(shown, "exists, is not empty and was not written by pushpred (no " +
                                        std::string(kOutputMarker) +
                                        " in it): its contents would be replaced; give a new or empty folder"));
  }
  const fs::path parent = target_.parent_path();
  fs::create_directories(parent, ec);
  if (ec) throw InputError(about(parent.string(), "cannot create folder: " + ec.message()));
  remove_stale_staging(target_);
  staging_ = parent / ("." + target_.filename().string() + ".staging-" + std::to_string(getpid()) + "-" +
                       unique_suffix());
  fs::create_directory(staging_, ec);
  if (ec) throw InputError(about(shown, "cannot create a staging folder beside it: " + ec.message()));
  slot_ = claim_slot(staging_);
  std::ofstream(staging_ / kOutputMarker) << "written by pushpred; replaced as a whole by the next run into it\n";
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  if (!committed_) fs::remove_all(staging_, ec);
  release_slot(slot_);
}

fs::path StagedOutput::path(const std::string& name) const {
  const fs::path p = staging_ / name;
  fs::create_directories(p.parent_path());
  return p;
}

void StagedOutput::commit() {
  if (committed_) return;
  const std::string shown = destination_.string();
  std::error_code ec;
  if (!fs::exists(target_, ec)) {
    fs::rename(staging_, target_, ec);
    if (ec) throw InputError(about(shown, "cannot move output into place: " + ec.message()));
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
    // Swapped in one step: the staging path now holds the earlier contents.
    fs::remove_all(staging_, ec);
  } else {
    // A file system without RENAME_EXCHANGE: move the old folder aside, the new one in, then remove the old.
    const fs::path old = target_.parent_path() / ("." + target_.filename().string() + ".replaced-" +
                                                  std::to_string(getpid()) + "-" + unique_suffix());
    fs::rename(target_, old, ec);
    if (ec) throw InputError(about(shown, "cannot replace the earlier output: " + ec.message()));
    fs::rename(staging_, target_, ec);
    if (ec) {
      std::error_code ignored;
      fs::rename(old, target_, ignored);
      throw InputError(about(shown, "cannot move output into place: " + ec.message()));
    }
    fs::remove_all(old, ec);
  }
  committed_ = true;
  release_slot(slot_);
  slot_ = -1;
}

void install_output_cleanup_on_signals() {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction current {};
    if (sigaction(sig, nullptr, &current) != 0 || current.sa_handler == SIG_IGN) continue;  // e.g. nohup
    struct sigaction action {};
    action.sa_handler = remove_staging_and_reraise;
    sigemptyset(&action.sa_mask);
    for (const int other : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&action.sa_mask, other);
    action.sa_flags = SA_RESETHAND;
    sigaction(sig, &action, nullptr);
  }
}

}  // namespace pushpred
