#include "pushpred/core/data_folder.hpp"

#include <algorithm>
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

std::vector<fs::path> list_recordings(const fs::path& folder, const std::string& surface) {
  const fs::path root = surface.empty() ? folder : folder / surface;
  if (!fs::is_directory(root)) throw InputError(about(root.string(), "folder does not exist"));
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const auto ext = entry.path().extension();
    if (entry.is_regular_file() && (ext == ".h5" || ext == ".json")) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace pushpred
