#include "pushpred/core/data_folder.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "pushpred/core/error.hpp"

namespace fs = std::filesystem;

namespace pushpred {

fs::path resolve_data_folder(const std::optional<std::string>& explicit_folder) {
  std::vector<fs::path> tried;
  if (explicit_folder && !explicit_folder->empty()) {
    const fs::path p(*explicit_folder);
    if (fs::is_directory(p)) return p;
    throw InputError(about(p.string(), "data folder does not exist"));
  }
  if (const char* env = std::getenv("PUSHPRED_DATA"); env && *env) {
    const fs::path p(env);
    if (fs::is_directory(p)) return p;
    throw InputError(about(p.string(), "data folder named by PUSHPRED_DATA does not exist"));
  }
  for (const fs::path& p : {fs::path(PUSHPRED_DEFAULT_DATA_DIR), fs::path("../shared/data/mcube")}) {
    if (fs::is_directory(p)) return fs::weakly_canonical(p);
    tried.push_back(p);
  }
  std::string list;
  for (const auto& p : tried) list += (list.empty() ? "" : ", ") + p.string();
  throw InputError("no data folder found (tried " + list + "); give one with --data or PUSHPRED_DATA");
}

fs::path data_folder_if_any(const std::optional<std::string>& explicit_folder) {
  if (explicit_folder && !explicit_folder->empty()) return resolve_data_folder(explicit_folder);
  try {
    return resolve_data_folder();
  } catch (const InputError&) {
    return {};
  }
}

bool has_recording_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".h5" || ext == ".json";
}

std::string file_identity(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) return "inode " + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  std::error_code ec;
  fs::path identity = fs::weakly_canonical(path, ec);
  if (ec) identity = path.lexically_normal();
  return "path " + identity.string();
}

namespace {

/// Recordings below `folder`, by hand rather than by recursive_directory_iterator so that one unreadable
/// subfolder does not hide the rest: it is listed itself and fails by name when read. Symbolic links to folders
/// are not followed (no loops); anything else named *.h5 or *.json is listed, regular or not, so that a FIFO, a
/// broken link or a link loop is a named failure rather than silently skipped.
void collect_recordings(const fs::path& folder, std::vector<fs::path>& files, int depth) {
  std::error_code ec;
  fs::directory_iterator it(folder, ec);
  if (ec || depth > 32) {
    files.push_back(folder);
    return;
  }
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) {
      files.push_back(folder);
      return;
    }
    std::error_code ec_status;
    const fs::file_status link = it->symlink_status(ec_status);
    if (fs::is_directory(link)) collect_recordings(it->path(), files, depth + 1);
    else if (has_recording_extension(it->path()))
      files.push_back(it->path());
  }
}

}  // namespace

std::vector<fs::path> list_recordings(const fs::path& folder, const std::string& surface) {
  const fs::path root = surface.empty() ? folder : folder / surface;
  std::error_code ec;
  if (!fs::is_directory(root, ec)) throw InputError(about(root.string(), "folder does not exist"));
  std::vector<fs::path> files;
  collect_recordings(root, files, 0);
  std::sort(files.begin(), files.end());
  files.erase(std::unique(files.begin(), files.end()), files.end());
  return files;
}

}  // namespace pushpred
