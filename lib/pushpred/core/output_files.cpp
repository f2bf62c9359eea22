#include "pushpred/core/output_files.hpp"

#include <atomic>
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
  if (fs::exists(destination_) && !fs::is_directory(destination_))
    throw InputError(about(destination_.string(), "exists and is not a folder"));
  const fs::path parent = fs::absolute(destination_).parent_path();
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw InputError(about(parent.string(), "cannot create folder: " + ec.message()));
  staging_ = parent / ("." + destination_.filename().string() + ".staging-" + unique_suffix());
  fs::create_directories(staging_, ec);
  if (ec) throw InputError(about(staging_.string(), "cannot create staging folder: " + ec.message()));
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

fs::path StagedOutput::path(const std::string& name) const {
  const fs::path p = staging_ / name;
  fs::create_directories(p.parent_path());
  return p;
}

void StagedOutput::commit() {
  if (committed_) return;
  std::error_code ec;
  fs::create_directories(destination_, ec);
  if (ec) throw InputError(about(destination_.string(), "cannot create folder: " + ec.message()));
  for (auto it = fs::recursive_directory_iterator(staging_); it != fs::recursive_directory_iterator(); ++it) {
    const fs::path rel = fs::relative(it->path(), staging_);
    const fs::path target = destination_ / rel;
    if (it->is_directory()) {
      fs::create_directories(target, ec);
    } else {
      fs::create_directories(target.parent_path(), ec);
      fs::rename(it->path(), target, ec);
      if (ec) {  // across file systems: copy instead
        fs::copy_file(it->path(), target, fs::copy_options::overwrite_existing, ec);
        if (ec) throw InputError(about(target.string(), "cannot move output into place: " + ec.message()));
      }
    }
  }
  committed_ = true;
}

}  // namespace pushpred
