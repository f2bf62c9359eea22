#pragma once
// Helpers shared by the test suites: a temporary folder that removes itself, the message of an expected InputError,
// the real data files, the shell of a synthetic push, and a study of awkward numbers.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/prediction/prediction_study.hpp"
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

/// The message of the InputError `f()` throws; "" when it throws none.
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

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

/// Whether `a` and `b` are the same double to the bit (-0 is not 0; a NaN is itself).
inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// A study of one phase whose numbers are awkward to write and read back: NaN and infinities, -0, 1e-300, sums
/// with long expansions (0.1 + 0.2), a parameter that is NaN; for exact round trips and byte-for-byte texts.
inline PushStudy awkward_push_study() {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  PushStudy s;
  s.source = "shape=rect1_a=0_v=10_i=0.000_s=0.000_t=0.000.h5";
  s.span = "whole";
  s.methods = {"dob", "hold"};
  s.intervals = {{0.0, 0.1 + 0.2}, {1.0 / 3.0, 2.0 / 3.0}};
  PhaseResult r;
  r.phase = 1;
  r.interval = s.intervals[1];
  r.relation.estimator = "rls";
  r.relation.beta = {0.1, -0.0, 1e-300};
  r.relation.eps = {nan, inf, -inf};
  r.relation.covariance[1] << 1.0 / 7.0, 2e-17, 2e-17, 5e300;
  r.relation.samples = 25;
  r.relation.effective_samples = 24.999999999999996;
  r.relation.intervals = 1;
  r.note = "a note";
  r.predicted["dob"].resize(0, 3);
  r.predicted["hold"].resize(0, 3);
  r.errors["dob"] = {0.7000000000000001, 1, 2, 3, 4, 5, 6, 7, 8.123456789012345};
  r.errors["hold"] = {nan, 0, 0, 0, 0, 0, 0, 0, 0};
  r.method_notes["hold"] = "stays";
  r.method_parameters["dob"] = {{"mu_p", 0.35, 0.01, "", "identified"}, {"c", nan, 0, "m", "default: none"}};
  r.initial_velocity = {std::nextafter(1.0, 2.0), 0, -1e-9};
  s.phases.push_back(r);
  s.method_seconds["dob"] = 0.25;
  return s;
}

}  // namespace pushpred::testing
