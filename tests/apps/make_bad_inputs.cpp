// Writes a corpus of bad inputs into a folder, each derived from a real recording (read here, never
// copied into the repository) or synthesized: what a hostile but fair user might hand pushpred. The CLI test
// tests/apps/cli_bad_input.sh runs the commands on them. Usage: make_bad_inputs REAL.h5 OUT_FOLDER
//
// Each file lands in OUT_FOLDER/<class>/ under the real file's name (so the shape is known from it).
#include <hdf5.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <numeric>
#include <random>
#include <string>

#include "pushpred/reading/recording.hpp"

namespace fs = std::filesystem;
using namespace pushpred;

namespace {

using Rows = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;

Rows rows_of(const TimedStream& s) {
  Rows m(s.size(), 4);
  m.col(0) = s.t_s;
  m.rightCols<3>() = s.values;
  return m;
}

std::map<std::string, Rows> arrays_of(const Recording& r) {
  return {{"tip_pose", rows_of(r.tip_pose)}, {"object_pose", rows_of(r.object_pose)}, {"ft_wrench", rows_of(r.ft_wrench)}};
}

/// Writes arrays with the raw HDF5 API; `integer_arrays` are stored as 64-bit integers (truncated, as a careless
/// writer would), and `declared_rows` > 0 declares that many rows in a chunked, unwritten tip_pose.
/// `float_bits` 32 stores every array as 32-bit floats; `user_block` > 0 puts a user block of that many bytes (a
/// power of two from 512) before the HDF5 data, as h5py's userblock_size does.
void write_h5(const fs::path& path, const std::map<std::string, Rows>& arrays,
              const std::vector<std::string>& integer_arrays = {}, hsize_t declared_rows = 0, int float_bits = 64,
              hsize_t user_block = 0) {
  const hid_t create = H5Pcreate(H5P_FILE_CREATE);
  if (user_block > 0) H5Pset_userblock(create, user_block);
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, create, H5P_DEFAULT);
  H5Pclose(create);
  for (const auto& [name, m] : arrays) {
    const bool as_int = std::find(integer_arrays.begin(), integer_arrays.end(), name) != integer_arrays.end();
    if (declared_rows > 0 && name == "tip_pose") {
      const hsize_t dims[2] = {declared_rows, 4}, chunk[2] = {1024, 4};
      const hid_t s = H5Screate_simple(2, dims, nullptr);
      const hid_t p = H5Pcreate(H5P_DATASET_CREATE);
      H5Pset_chunk(p, 2, chunk);
      const hid_t d = H5Dcreate2(f, name.c_str(), H5T_IEEE_F64LE, s, H5P_DEFAULT, p, H5P_DEFAULT);
      H5Dclose(d);
      H5Pclose(p);
      H5Sclose(s);
      continue;
    }
    const hsize_t dims[2] = {static_cast<hsize_t>(m.rows()), 4};
    const hid_t s = H5Screate_simple(2, dims, nullptr);
    const hid_t d =
        H5Dcreate2(f, name.c_str(), as_int ? H5T_STD_I64LE : (float_bits == 32 ? H5T_IEEE_F32LE : H5T_IEEE_F64LE), s,
                   H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (as_int) {
      Eigen::Matrix<long long, Eigen::Dynamic, 4, Eigen::RowMajor> ints = m.cast<long long>();
      H5Dwrite(d, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, ints.data());
    } else {
      H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.data());
    }
    H5Dclose(d);
    H5Sclose(s);
  }
  H5Fclose(f);
}

std::string json_of(const std::map<std::string, Rows>& arrays) {
  std::string out = "{";
  bool first_array = true;
  char number[64];
  for (const auto& [name, m] : arrays) {
    out += std::string(first_array ? "" : ",") + "\n\"" + name + "\": [";
    first_array = false;
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
      out += i ? ",[" : "[";
      for (int j = 0; j < 4; ++j) {
        std::snprintf(number, sizeof number, "%.17g", m(i, j));
        out += std::string(j ? "," : "") + number;
      }
      out += "]";
    }
    out += "]";
  }
  return out + "}\n";
}

void write_bytes(const fs::path& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: make_bad_inputs REAL.h5 OUT_FOLDER\n";
    return 2;
  }
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const Recording real = read_recording(argv[1]);
  const fs::path out = argv[2];
  fs::create_directories(out);
  const std::string name = fs::path(argv[1]).stem().string();  // motion_surface=..._t=...
  const auto file = [&](const std::string& kind, const std::string& ext) {
    fs::create_directories(out / kind);
    return out / kind / (name + ext);
  };
  const std::map<std::string, Rows> good = arrays_of(real);

  // JSON: "{" then random bytes, invalid UTF-8 among them (once a batch-killer).
  std::mt19937 rng(13);
  std::string garbage = "{";
  for (int i = 0; i < 64; ++i) garbage += static_cast<char>(rng() % 256);
  write_bytes(file("garbage", ".json"), garbage);
  // JSON with a number a double cannot hold.
  write_bytes(file("overflow", ".json"), "{\"tip_pose\": [[1e400, 0, 0, 0]]}\n");
  // NaN as Python's json.dump writes it (not JSON).
  write_bytes(file("nan_literal", ".json"), "{\"tip_pose\": [[1.5e9, NaN, 0, 0]]}\n");
  // A top-level JSON array.
  write_bytes(file("array", ".json"), "[[1.5e9, 0.1, 0.2, 0.3], [1.5e9, 0.1, 0.2, 0.3]]\n");
  // Time stamps in milliseconds.
  {
    auto a = good;
    for (auto& [n, m] : a) m.col(0) *= 1e3;
    write_h5(file("milliseconds", ".h5"), a);
  }
  // Time stamps relative and in milliseconds (no Unix offset): only the rate gives it away.
  {
    auto a = good;
    const double t0 = a["object_pose"](0, 0);
    for (auto& [n, m] : a) m.col(0) = (m.col(0).array() - t0) * 1e3;
    write_h5(file("relative_milliseconds", ".h5"), a);
  }
  // The last stamp of each stream 1e5 s late.
  {
    auto a = good;
    for (auto& [n, m] : a) m(m.rows() - 1, 0) += 1e5;
    write_h5(file("late_stamp", ".h5"), a);
  }
  // A file declaring 1e8 rows it does not hold.
  write_h5(file("declared_rows", ".h5"), good, {}, 100'000'000);
  // object_pose stored as integers: x and y truncated to 0.
  write_h5(file("integer_pose", ".h5"), good, {"object_pose"});
  // Forces of 1e300 N.
  {
    auto a = good;
    a["ft_wrench"].col(1).setConstant(1e300);  // fx (column 0 is time)
    write_h5(file("huge_force", ".h5"), a);
  }
  // Positions of a kilometre.
  {
    auto a = good;
    a["object_pose"].col(1).array() += 1e3;  // x
    write_h5(file("far_away", ".h5"), a);
  }
  // Motion no pushed object makes (docs/robustness.md, plausibility of the motion): the object 1 m away for two
  // samples, a permanent 1 m step, twenty turns of yaw (stored wrapped), the object's pose equal to the tip's.
  {
    auto a = good;
    Rows& object = a["object_pose"];
    const Eigen::Index mid = object.rows() / 2;
    object(mid, 1) += 1.0;
    object(mid + 1, 1) += 1.0;
    write_h5(file("object_spike", ".h5"), a);
  }
  {
    auto a = good;
    Rows& object = a["object_pose"];
    object.col(1).tail(object.rows() / 2).array() += 1.0;
    write_h5(file("object_step", ".h5"), a);
  }
  {
    auto a = good;
    Rows& object = a["object_pose"];
    const Eigen::Index n = object.rows();
    for (Eigen::Index k = 0; k < n; ++k) {
      const double turned = object(k, 3) + 20 * 2 * M_PI * static_cast<double>(k) / static_cast<double>(n - 1);
      object(k, 3) = std::remainder(turned, 2 * M_PI);
    }
    write_h5(file("yaw_turns", ".h5"), a);
  }
  {
    auto a = good;
    // The object's pose replaced by the tip's at the tip's time stamps (its own stream's length and clock).
    a["object_pose"] = a["tip_pose"];
    write_h5(file("object_at_tip", ".h5"), a);
  }
  // NaN and Inf in the values, a stream of zero rows or one row, a stream missing, a stream shuffled, and the file cut
  // short (a copy interrupted): each refused by name.
  {
    auto a = good;
    a["ft_wrench"](7, 2) = std::nan("");
    write_h5(file("nan_force", ".h5"), a);
    a = good;
    a["object_pose"](5, 1) = INFINITY;
    write_h5(file("inf_pose", ".h5"), a);
    a = good;
    a["tip_pose"].resize(0, 4);
    write_h5(file("empty_stream", ".h5"), a);
    a = good;
    a["object_pose"].conservativeResize(1, 4);
    write_h5(file("single_row", ".h5"), a);
    a = good;
    a.erase("ft_wrench");
    write_h5(file("missing_array", ".h5"), a);
    a = good;
    Rows& force = a["ft_wrench"];
    std::vector<Eigen::Index> order(static_cast<std::size_t>(force.rows()));
    std::iota(order.begin(), order.end(), Eigen::Index{0});
    std::shuffle(order.begin(), order.end(), rng);
    const Rows unshuffled = force;
    for (Eigen::Index i = 0; i < force.rows(); ++i) force.row(i) = unshuffled.row(order[static_cast<std::size_t>(i)]);
    write_h5(file("shuffled", ".h5"), a);
    write_h5(file("truncated", ".h5"), good);
    const fs::path cut = file("truncated", ".h5");
    fs::resize_file(cut, fs::file_size(cut) / 2);
    // Cut after its signature, and inside its superblock: too short for libhdf5 to say more than an internal detail.
    write_h5(file("signature_only", ".h5"), good);
    fs::resize_file(file("signature_only", ".h5"), 8);
    write_h5(file("cut_in_header", ".h5"), good);
    fs::resize_file(file("cut_in_header", ".h5"), 40);
  }
  // Files a user has, written by other tools: HDF5 behind a user block; arrays as 32-bit floats with time stamps
  // from the push's start (read, converted, said) or as Unix time (refused: 32-bit floats keep 128 s of it).
  write_h5(file("user_block", ".h5"), good, {}, 0, 64, 512);
  {
    auto a = good;
    const double t0 = a["object_pose"](0, 0);
    for (auto& [n, m] : a) m.col(0).array() -= t0;
    write_h5(file("float32", ".h5"), a, {}, 0, 32);
  }
  write_h5(file("float32_unix", ".h5"), good, {}, 0, 32);
  // Good data in JSON behind a UTF-8 byte-order mark: must be read, not refused.
  write_bytes(file("bom_good", ".json"), "\xEF\xBB\xBF" + json_of(good));
  // The same data in plain JSON and HDF5 (good files with a new name, made at test time).
  write_bytes(file("good", ".json"), json_of(good));
  write_h5(file("good", ".h5"), good);
  std::cout << "wrote bad inputs into " << out.string() << "\n";
  return 0;
}
