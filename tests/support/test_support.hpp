#pragma once
// Helpers shared by the test suites: a temporary folder that removes itself, and the real data files.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "pushpred/core/data_folder.hpp"

namespace pushpred::testing {

class TempFolder {
 public:
  TempFolder() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("pushpred-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

/// A real recording from the data folder: the first whose name contains `fragment`.
inline std::filesystem::path real_file(const std::string& fragment) {
  for (const auto& p : list_recordings(resolve_data_folder()))
    if (p.filename().string().find(fragment) != std::string::npos) return p;
  throw std::runtime_error("no real recording matches '" + fragment + "'");
}

}  // namespace pushpred::testing
