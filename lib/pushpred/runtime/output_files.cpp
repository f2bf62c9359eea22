#include "pushpred/runtime/output_files.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
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

// --- The staging (and scratch) folders a signal handler must remove. Plain arrays and atomics: the handler may only
// read them.
constexpr int kSlots = 16;
constexpr std::size_t kMaxPath = 4096;
std::atomic<bool> slot_used[kSlots];
char slot_path[kSlots][kMaxPath];
// Where the handler moves a staging folder before removing it: the same name with ".stopped" appended (still a
// ".staging-PID-" name, so a later run's stale clean-up recognises it if the removal cannot finish).
char slot_stopped[kSlots][kMaxPath];
constexpr char kStoppedSuffix[] = ".stopped";

int claim_slot(const fs::path& staging) {
  const std::string s = staging.string();
  if (s.size() + sizeof kStoppedSuffix >= kMaxPath) return -1;
  for (int i = 0; i < kSlots; ++i) {
    bool expected = false;
    if (slot_used[i].load() || !slot_used[i].compare_exchange_strong(expected, true)) continue;
    // Mark busy with an empty path first, then publish the path.
    slot_path[i][0] = '\0';
    std::memcpy(slot_stopped[i], s.c_str(), s.size());
    std::memcpy(slot_stopped[i] + s.size(), kStoppedSuffix, sizeof kStoppedSuffix);
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
/// getdents64, unlinkat, close), for the signal handler; true if it is gone. Depth-bounded; never follows links.
/// Each entry is first unlinked as a file and only then opened as a folder, so file systems that do not report
/// entry types (DT_UNKNOWN) are handled too; a pass that removes nothing ends the loop, so an entry that cannot be
/// removed cannot make it spin.
bool remove_tree_at(int parent_fd, const char* name, int depth) {
  if (unlinkat(parent_fd, name, 0) == 0) return true;
  if (depth > 16) return false;
  const int fd = openat(parent_fd, name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return false;
  alignas(8) char buffer[2048];
  for (bool removed_any = true; removed_any;) {  // passes over the whole folder until one removes nothing
    removed_any = false;
    lseek(fd, 0, SEEK_SET);
    for (long n; (n = syscall(SYS_getdents64, fd, buffer, sizeof buffer)) > 0;) {
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
        if (remove_tree_at(fd, e->name, depth + 1)) removed_any = true;
      }
    }
  }
  close(fd);
  return unlinkat(parent_fd, name, AT_REMOVEDIR) == 0;
}

// The process that installed the handler: only it removes its staging folders. A child made by fork inherits the
// handler until it resets it or calls exec, and must never remove its parent's output.
std::atomic<pid_t> cleanup_owner{0};
// The first stop signal the owner takes removes the folders, once. `timeout` sends its signal twice (to the
// process, then to its group), and a second stop signal may be of another kind or reach another thread: it waits
// until the removal is done, then ends the process as the first one does.
std::atomic<bool> cleanup_started{false}, cleanup_done{false};
static_assert(std::atomic<pid_t>::is_always_lock_free && std::atomic<bool>::is_always_lock_free,
              "read in a signal handler");

extern "C" void remove_staging_and_reraise(int sig) {
  const int saved_errno = errno;
  if (getpid() == cleanup_owner.load()) {
    if (!cleanup_started.exchange(true)) {
      // Moved aside first, then removed: other threads (--jobs) may still be writing into the staging folder, and a
      // file they created between the removal's listing and its final rmdir left the folder behind (2 of 60 stopped
      // runs with two jobs, none with one). After the rename their new files fail by path; nothing can appear in the
      // moved tree but what was already there.
      for (int i = 0; i < kSlots; ++i) {
        if (!slot_used[i].load() || slot_path[i][0] == '\0') continue;
        const char* doomed = rename(slot_path[i], slot_stopped[i]) == 0 ? slot_stopped[i] : slot_path[i];
        for (int attempt = 0; attempt < 3 && !remove_tree_at(AT_FDCWD, doomed, 0); ++attempt) {
        }
      }
      cleanup_done.store(true);
    }
    const timespec millisecond{0, 1000000};
    while (!cleanup_done.load()) nanosleep(&millisecond, nullptr);  // another thread is removing them
  }
  signal(sig, SIG_DFL);
  raise(sig);  // delivered when the handler returns: the process ends by the signal, as without the handler
  errno = saved_errno;
}

bool process_alive(long pid) { return pid > 0 && (kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

/// Removes `.NAME.staging-PID-*` and `.NAME.replaced-PID-*` folders beside `target` whose process is gone and that
/// hold the marker (so only folders pushpred made).
void remove_stale_staging(const fs::path& target) {
  const std::string name = bounded_file_name(target.filename().string());
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

/// Removes `pushpred-NAME-PID` scratch folders in `temp` (ScratchFolder) of this user whose process is gone: a rank
/// killed outright (kill -9) leaves its scratch folder, and the next run on the machine removes it.
void remove_stale_scratch(const fs::path& temp) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(temp, ec)) {
    const std::string name = entry.path().filename().string();
    const std::size_t dash = name.rfind('-');
    if (name.rfind("pushpred-", 0) != 0 || dash == std::string::npos || dash + 1 >= name.size()) continue;
    char* end = nullptr;
    const long pid = std::strtol(name.c_str() + dash + 1, &end, 10);
    struct stat st {};
    if (*end != '\0' || pid <= 0 || process_alive(pid) || ::lstat(entry.path().c_str(), &st) != 0 ||
        !S_ISDIR(st.st_mode) || st.st_uid != ::geteuid())
      continue;
    std::error_code ignored;
    fs::remove_all(entry.path(), ignored);
  }
}

bool is_empty_folder(const fs::path& p) {
  std::error_code ec;
  return fs::directory_iterator(p, ec) == fs::directory_iterator() && !ec;
}

// The marker's first line; the lines after kMarkerList list what the run wrote, one relative path a line.
constexpr const char* kMarkerHeading = "written by pushpred; replaced as a whole by the next run into it\n";
constexpr const char* kMarkerList = "files and folders written:\n";

/// Every file and folder below `folder`, as relative paths (sorted), the marker itself left out. A link is listed
/// as itself and not followed.
std::vector<std::string> entries_below(const fs::path& folder) {
  std::vector<std::string> entries;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder, fs::directory_options::none, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    const std::string relative = it->path().lexically_relative(folder).generic_string();
    if (relative != kOutputMarker) entries.push_back(relative);
  }
  std::sort(entries.begin(), entries.end());
  return entries;
}

std::string marker_text(const fs::path& staging) {
  std::string text = std::string(kMarkerHeading) + kMarkerList;
  for (const auto& entry : entries_below(staging)) {
    // A name holding a line break cannot be listed one a line: its first line is listed, so the check below finds
    // the entry unlisted and refuses the folder rather than deleting something it cannot name.
    text += entry.substr(0, entry.find('\n')) + "\n";
  }
  return text;
}

/// The first entry of a pushpred output folder its marker does not list, or "" when there is none. A marker without
/// a list (written before markers listed their files) lists nothing, and its folder is taken as pushpred's whole.
std::string entry_not_written_by_pushpred(const fs::path& folder) {
  std::string marker;
  try {
    marker = read_file_bytes(folder / kOutputMarker);
  } catch (const std::exception&) {
    return kOutputMarker;
  }
  const std::size_t list = marker.find(kMarkerList);
  if (list == std::string::npos) return "";
  std::set<std::string> written;
  std::istringstream lines(marker.substr(list + std::strlen(kMarkerList)));
  for (std::string line; std::getline(lines, line);) written.insert(line);
  for (const auto& entry : entries_below(folder))
    if (!written.count(entry)) return entry;
  return "";
}

}  // namespace

std::string bounded_file_name(const std::string& name, std::size_t max_bytes) {
  if (name.size() <= max_bytes) return name;
  std::uint64_t hash = 14695981039346656037ull;  // FNV-1a, 64 bits: stable across runs and builds
  for (unsigned char c : name) hash = (hash ^ c) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(hash));
  const std::size_t keep = max_bytes > 17 ? max_bytes - 17 : 0;
  return name.substr(0, keep) + "-" + hex;
}

std::string read_file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(about(plain_text(path.string()), "cannot be read"));
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw InputError(about(plain_text(path.string()), "cannot be read"));
  return s.str();
}

std::string json_file_text(const nlohmann::json& doc) {
  return doc.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

JsonTextAround json_file_text_around(nlohmann::json doc, const std::string& key) {
  // The document is dumped with a marker as the key's value, and split where the marker stands.
  if (!doc.is_object()) throw std::logic_error("json_file_text_around: not an object");
  const std::string marker = "pushpred: this value is written here";
  doc[key] = marker;
  const std::string text = json_file_text(doc);
  const std::string name = nlohmann::json(key).dump() + ": ";
  const std::string slot = name + nlohmann::json(marker).dump();
  const std::size_t at = text.find(slot);
  if (at == std::string::npos) throw std::logic_error("json_file_text_around: the value's place was not found");
  return {text.substr(0, at + name.size()), text.substr(at + slot.size())};
}

void write_text_atomically(const fs::path& path, const std::string& text) {
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  // The folder is never created here: a stop signal's clean-up may have just removed the staging folder this path
  // lies in, and making it again from a worker thread left it behind (CI, one of 20 stopped runs). Folders below a
  // staging folder come from StagedOutput::path, one level at a time.
  if (!fs::is_directory(folder, ec))
    throw InputError(about(path.string(), "cannot be written: its folder " + folder.string() + " does not exist"));
  const fs::path tmp = folder / ("." + bounded_file_name(path.filename().string()) + ".tmp-" + unique_suffix());
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw InputError(about(path.string(), "cannot open for writing"));
    try {
      write(out);
    } catch (...) {
      out.close();
      fs::remove(tmp, ec);
      throw;
    }
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
    struct stat owner {};
    if (::stat(target_.c_str(), &owner) == 0 && owner.st_uid != ::geteuid())
      throw InputError(about(shown, "is owned by another user (uid " + std::to_string(owner.st_uid) +
                                        "): pushpred replaces only its own output folders; give another folder"));
    if (!is_empty_folder(target_)) {
      if (!fs::exists(target_ / kOutputMarker, ec))
        throw InputError(about(shown, "exists, is not empty and was not written by pushpred (no " +
                                          std::string(kOutputMarker) +
                                          " in it): its contents would be replaced; give a new or empty folder"));
      if (const std::string foreign = entry_not_written_by_pushpred(target_); !foreign.empty())
        throw InputError(about(shown, "holds '" + plain_text(foreign) +
                                          "', which pushpred did not write there: replacing the folder would delete "
                                          "it; move it out or give another folder"));
    }
  }
  const fs::path parent = target_.parent_path();
  fs::create_directories(parent, ec);
  if (ec) throw InputError(about(parent.string(), "cannot create folder: " + ec.message()));
  remove_stale_staging(target_);
  staging_ = parent / ("." + bounded_file_name(target_.filename().string()) + ".staging-" + std::to_string(getpid()) +
                       "-" + unique_suffix());
  // Registered before it exists, so that a stop signal at any moment after this finds it (removing a folder that
  // is not there yet is harmless).
  slot_ = claim_slot(staging_);
  fs::create_directory(staging_, ec);
  if (ec) {
    release_slot(slot_);
    slot_ = -1;
    throw InputError(about(shown, "cannot create a staging folder beside it: " + ec.message()));
  }
  std::ofstream(staging_ / kOutputMarker) << kMarkerHeading;
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  if (!committed_) fs::remove_all(staging_, ec);
  release_slot(slot_);
}

fs::path StagedOutput::path(const std::string& name) const {
  // Subfolders are made one level at a time below the staging folder, never the staging folder itself: once a
  // stop signal's clean-up has removed it, nothing may bring it back.
  fs::path folder = staging_;
  const fs::path relative = fs::path(name).parent_path();
  for (const auto& part : relative) {
    folder /= part;
    std::error_code ec;
    fs::create_directory(folder, ec);
    if (ec) throw InputError(about(folder.string(), "cannot create folder: " + ec.message()));
  }
  return staging_ / name;
}

void StagedOutput::commit() {
  if (committed_) return;
  const std::string shown = destination_.string();
  std::error_code ec;
  write_text_atomically(staging_ / kOutputMarker, marker_text(staging_));
  if (!fs::exists(target_, ec)) {
    fs::rename(staging_, target_, ec);
    if (ec) throw InputError(about(shown, "cannot move output into place: " + ec.message()));
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
    // Swapped in one step: the staging path now holds the earlier contents.
    fs::remove_all(staging_, ec);
  } else {
    // A file system without RENAME_EXCHANGE: move the old folder aside, the new one in, then remove the old.
    const fs::path old = target_.parent_path() / ("." + bounded_file_name(target_.filename().string()) + ".replaced-" +
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

ScratchFolder::ScratchFolder(const std::string& name) {
  std::error_code ec;
  const fs::path temp = fs::temp_directory_path(ec);
  if (ec) throw InputError("no temporary folder for scratch files (TMPDIR): " + ec.message());
  remove_stale_scratch(temp);
  path_ = temp / ("pushpred-" + name + "-" + std::to_string(getpid()));
  fs::remove_all(path_, ec);  // a dead process's, whose id this one has now
  slot_ = claim_slot(path_);  // before it exists, as a staging folder
  fs::create_directories(path_, ec);
  if (ec) {
    release_slot(slot_);
    throw InputError(about(path_.string(), "cannot create a scratch folder: " + ec.message()));
  }
}

ScratchFolder::~ScratchFolder() {
  std::error_code ec;
  fs::remove_all(path_, ec);
  release_slot(slot_);
}

void install_output_cleanup_on_signals() {
  cleanup_owner.store(getpid());
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction current {};
    if (sigaction(sig, nullptr, &current) != 0 || current.sa_handler == SIG_IGN) continue;  // e.g. nohup
    struct sigaction action {};
    action.sa_handler = remove_staging_and_reraise;
    sigemptyset(&action.sa_mask);
    for (const int other : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&action.sa_mask, other);
    // No SA_RESETHAND: timeout sends its signal twice, microseconds apart. With it the kernel restores the default
    // action as it takes the first signal, a moment before it blocks the signal for the handler, and a second one
    // in between ended the process before the handler ran (the staging folders left behind in issue 13).
    action.sa_flags = 0;
    sigaction(sig, &action, nullptr);
  }
}

}  // namespace pushpred
