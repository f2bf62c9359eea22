#pragma once
// Helpers shared by the test suites: a temporary folder that removes itself, the real data files, and the shell of
// a synthetic push.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/reading/shape_table.hpp"

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

/// A synthetic push of `shape` (published table) with `n` samples at `rate_hz` from t = 0: every stream sized, the
/// tip at the origin, contact over the whole push; the caller fills pose, force, torque and contact.
inline SynchronisedPush synthetic_push_shell(const std::string& shape, double rate_hz, Eigen::Index n) {
  SynchronisedPush p;
  p.source = "synthetic";
  p.shape = ShapeTable::published().find(shape);
  p.push.shape = p.shape.name;
  p.rate_hz = rate_hz;
  p.t_s = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / rate_hz);
  p.pose.resize(n, 3);
  p.force_N.resize(n, 2);
  p.torque_about_centre_Nm.resize(n);
  p.tip_torque_Nm = Eigen::VectorXd::Zero(n);
  p.lever_m = Eigen::MatrixX2d::Zero(n, 2);
  p.tip_m = Eigen::MatrixX2d::Zero(n, 2);
  p.tip_yaw_rad = Eigen::VectorXd::Zero(n);
  p.in_contact.assign(static_cast<std::size_t>(n), 1);
  p.has_contact = true;
  p.contact_end_s = p.duration_s();
  return p;
}

}  // namespace pushpred::testing
