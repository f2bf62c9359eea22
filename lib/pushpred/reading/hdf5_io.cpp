// HDF5 reading and writing of recordings. Every HDF5 handle lives in an RAII `Handle`, so that no early
// error return leaks a file, dataset or dataspace.
#include <hdf5.h>

#include <atomic>
#include <random>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/recording.hpp"

namespace pushpred {
namespace {

/// Owns one hid_t and closes it with the matching H5*close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
  Closer close_;
};

/// HDF5 prints its own error stack by default; errors here become InputError messages instead.
void silence_hdf5_errors() {
  static const bool done = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

Eigen::MatrixXd read_rows(hid_t file, const std::string& source, const char* name) {
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0)
    throw InputError(about(source, std::string("array '") + name + "' is missing"));
  Handle dataset(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  if (!dataset.valid()) throw InputError(about(source, std::string("'") + name + "' is not a dataset"));
  Handle type(H5Dget_type(dataset.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_FLOAT && H5Tget_class(type.get()) != H5T_INTEGER)
    throw InputError(about(source, std::string("array '") + name + "' is not numeric"));
  Handle space(H5Dget_space(dataset.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank != 2)
    throw InputError(about(source, std::string("array '") + name + "' has rank " + std::to_string(rank) +
                                       ", expected n x 4"));
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  if (dims[1] != 4)
    throw InputError(about(source, std::string("array '") + name + "' has shape (" + std::to_string(dims[0]) + ", " +
                                       std::to_string(dims[1]) + "), expected (n, 4)"));
  // HDF5 stores row-major; read into a row-major buffer and copy into Eigen's column-major matrix.
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> buffer(static_cast<Eigen::Index>(dims[0]), 4);
  if (dims[0] > 0 && H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
    throw InputError(about(source, std::string("array '") + name + "' cannot be read"));
  return buffer;
}

void write_rows(hid_t file, const std::string& target, const char* name, const TimedStream& s) {
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> buffer(s.size(), 4);
  buffer.col(0) = s.t_s;
  buffer.rightCols<3>() = s.values;
  const hsize_t dims[2] = {static_cast<hsize_t>(s.size()), 4};
  Handle space(H5Screate_simple(2, dims, nullptr), H5Sclose);
  Handle dataset(H5Dcreate2(file, name, H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                 H5Dclose);
  if (!dataset.valid() ||
      H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
    throw InputError(about(target, std::string("cannot write array '") + name + "'"));
}

}  // namespace

Recording read_recording_hdf5(const std::filesystem::path& path, const ReadOptions& options) {
  silence_hdf5_errors();
  const std::string source = path.string();
  if (!std::filesystem::exists(path)) throw InputError(about(source, "file does not exist"));
  if (H5Fis_hdf5(source.c_str()) <= 0) throw InputError(about(source, "not an HDF5 file"));
  Handle file(H5Fopen(source.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) throw InputError(about(source, "cannot open HDF5 file"));
  Recording r;
  r.source = source;
  r.push = parse_push_filename(source);
  r.tip_pose = condition_stream(source, "tip_pose", read_rows(file.get(), source, "tip_pose"), options, r.repairs);
  r.object_pose =
      condition_stream(source, "object_pose", read_rows(file.get(), source, "object_pose"), options, r.repairs);
  r.ft_wrench = condition_stream(source, "ft_wrench", read_rows(file.get(), source, "ft_wrench"), options, r.repairs);
  return r;
}

void write_recording_hdf5(const Recording& recording, const std::filesystem::path& path) {
  silence_hdf5_errors();
  const std::string target = path.string();
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path tmp =
      path.parent_path() / ("." + path.filename().string() + ".tmp-" + std::to_string(std::random_device{}()) + "-" +
                            std::to_string(counter++));
  try {
    {
      Handle file(H5Fcreate(tmp.string().c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
      if (!file.valid()) throw InputError(about(target, "cannot create HDF5 file"));
      write_rows(file.get(), target, "ft_wrench", recording.ft_wrench);
      write_rows(file.get(), target, "object_pose", recording.object_pose);
      write_rows(file.get(), target, "tip_pose", recording.tip_pose);
    }
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

}  // namespace pushpred
