// HDF5 reading and writing of recordings. Every HDF5 handle lives in an RAII `Handle`, so that no early
// error return leaks a file, dataset or dataspace.
#include <hdf5.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>

#include "pushpred/core/error.hpp"
#include "pushpred/core/isolated_caller.hpp"
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

constexpr std::array<const char*, 3> kArrayNames = {"tip_pose", "object_pose", "ft_wrench"};

/// Arrays longer than this have their time span checked before the rest is read: 400 s at 250 Hz.
constexpr hsize_t kEarlySpanCheckRows = 100'000;

/// HDF5 prints its own error stack by default; errors here become InputError messages instead.
void silence_hdf5_errors() {
  static const bool done = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

/// Why the last libhdf5 call failed, from its error stack: the innermost message, which names the cause ("truncated
/// file: eof = 20000, sblock->base_addr = 0, stored_eof = 38144"), said plainly where it is a truncated file; empty
/// when the stack holds none.
std::string hdf5_failure_reason() {
  std::string innermost;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_UPWARD,
      [](unsigned n, const H5E_error2_t* error, void* out) -> herr_t {
        if (n == 0 && error != nullptr && error->desc != nullptr) *static_cast<std::string*>(out) = error->desc;
        return 0;
      },
      &innermost);
  unsigned long long held = 0, declared = 0, base = 0;
  if (std::sscanf(innermost.c_str(), "truncated file: eof = %llu, sblock->base_addr = %llu, stored_eof = %llu", &held,
                  &base, &declared) == 3)
    return "not a complete HDF5 file: it holds " + std::to_string(held) + " bytes of the " + std::to_string(declared) +
           " its header declares (cut short, as by an interrupted copy)";
  return innermost;
}

/// For a file that ends inside its HDF5 superblock (the header after the signature, which declares the file's length;
/// a file cut after a few bytes), "not a complete HDF5 file: it holds 16 bytes, fewer than the 96 of its header
/// (superblock)"; empty
/// otherwise. libhdf5's own reason for such a file names an internal detail ("bad byte number in an address").
/// Superblock lengths from the HDF5 file format specification: versions 0 and 1 hold 24 (28) bytes of fields, four
/// addresses and the root group's symbol table entry (two addresses and 24 bytes); versions 2 and 3 hold 4 bytes of
/// fields, four addresses and a 4-byte checksum. Addresses are "size of offsets" bytes.
std::string incomplete_superblock(const std::string& source) {
  std::ifstream in(source, std::ios::binary);
  if (!in) return {};
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  static const char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  // Where libhdf5 looks for the signature: 0, 512, 1024, 2048, ...
  std::streamoff at = 0;
  for (;; at = at == 0 ? 512 : 2 * at) {
    if (at + 8 > size) return {};
    char head[8] = {};
    in.clear();
    in.seekg(at);
    if (!in.read(head, sizeof head)) return {};
    if (std::equal(head, head + 8, kSignature)) break;
  }
  const std::string held = "not a complete HDF5 file: it holds " + std::to_string(size) + " bytes";
  unsigned char fields[16] = {};
  in.clear();
  in.seekg(at + 8);
  in.read(reinterpret_cast<char*>(fields), sizeof fields);
  const std::streamoff got = in.gcount();
  if (got < 1) return held + " and ends inside its header (the superblock at byte " + std::to_string(at) + ")";
  const int version = fields[0];
  const std::streamoff offsets_at = version <= 1 ? 5 : 1;  // "size of offsets", counted from the version byte
  if (version > 3 || got <= offsets_at)
    return size - at < 8 + 16 ? held + " and ends inside its header (the superblock at byte " + std::to_string(at) + ")"
                              : std::string();
  const std::streamoff offset_size = fields[offsets_at];
  if (offset_size != 2 && offset_size != 4 && offset_size != 8 && offset_size != 16 && offset_size != 32)
    return {};  // not a superblock's field: libhdf5's own reason stands
  const std::streamoff length = version == 0   ? 8 + 16 + 4 * offset_size + 2 * offset_size + 24
                                : version == 1 ? 8 + 20 + 4 * offset_size + 2 * offset_size + 24
                                               : 8 + 4 + 4 * offset_size + 4;
  if (size - at >= length) return {};
  return held + ", fewer than the " + std::to_string(at + length) + " of its header (superblock)";
}

std::string type_description(hid_t type) {
  const size_t bits = 8 * H5Tget_size(type);
  switch (H5Tget_class(type)) {
    case H5T_INTEGER:
      return std::to_string(bits) + "-bit integers";
    case H5T_FLOAT:
      return std::to_string(bits) + "-bit floats";
    case H5T_STRING:
      return "strings";
    case H5T_COMPOUND:
      return "compound records";
    default:
      return "non-numeric data";
  }
}

/// The array `name` as n x 4 doubles; `stored_bits` receives the width the file stores it in (64, or 32 converted).
Eigen::MatrixXd read_rows(hid_t file, const std::string& source, const char* name, long long max_rows,
                          double max_span_s, std::int64_t& stored_bits) {
  const std::string where = std::string("array '") + name + "'";
  if (H5Lexists(file, name, H5P_DEFAULT) <= 0) throw InputError(about(source, where + " is missing"));
  // Only a dataset stored in this file: a soft or external link, or external or virtual storage, would make the
  // reader open other files.
  H5L_info_t link{};
  if (H5Lget_info(file, name, &link, H5P_DEFAULT) < 0 || link.type != H5L_TYPE_HARD)
    throw InputError(about(source, where + " is a link, not a dataset stored in the file"));
  H5O_info_t object{};
  if (H5Oget_info_by_name2(file, name, &object, H5O_INFO_BASIC, H5P_DEFAULT) < 0 || object.type != H5O_TYPE_DATASET)
    throw InputError(about(source, std::string("'") + name + "' is not a dataset"));
  Handle dataset(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  if (!dataset.valid()) throw InputError(about(source, std::string("'") + name + "' is not a dataset"));
  Handle plist(H5Dget_create_plist(dataset.get()), H5Pclose);
  if (!plist.valid() || H5Pget_external_count(plist.get()) != 0 || H5Pget_layout(plist.get()) == H5D_VIRTUAL)
    throw InputError(about(source, where + " is stored outside the file (external or virtual storage)"));
  Handle type(H5Dget_type(dataset.get()), H5Tclose);
  // The format stores 64-bit floats. Integers would be converted exactly but a pose in metres stored as integers
  // has already lost everything below a metre. 32-bit floats are converted (and the conversion is reported): they
  // hold poses and forces well, and time stamps only where they are small (checked after decoding).
  const std::size_t bytes = type.valid() ? H5Tget_size(type.get()) : 0;
  if (!type.valid() || H5Tget_class(type.get()) != H5T_FLOAT || (bytes != 8 && bytes != 4))
    throw InputError(about(source, where + " holds " +
                                       (type.valid() ? type_description(type.get()) : "unreadable data") +
                                       "; the format stores 64-bit floats"));
  stored_bits = static_cast<std::int64_t>(8 * bytes);
  Handle space(H5Dget_space(dataset.get()), H5Sclose);
  const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
  if (rank != 2) throw InputError(about(source, where + " has rank " + std::to_string(rank) + ", expected n x 4"));
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  if (dims[1] != 4)
    throw InputError(about(source, where + " has shape (" + std::to_string(dims[0]) + ", " + std::to_string(dims[1]) +
                                       "), expected (n, 4)"));
  // Checked before allocating: a file may declare far more rows than it holds.
  if (dims[0] > static_cast<hsize_t>(max_rows))
    throw InputError(about(source, where + " declares " + std::to_string(dims[0]) + " rows, more than the " +
                                       std::to_string(max_rows) + " a recording may hold"));
  // A long array's time column first (a hyperslab of column 0): one spanning hours is refused before the rest is
  // read, so that refusing a huge file costs a column of it. Arrays of ordinary length (a push holds about 1,500
  // rows) are read whole, and the plausibility checks say more precisely what is wrong with their time stamps.
  if (dims[0] > kEarlySpanCheckRows) {
    Eigen::VectorXd time(static_cast<Eigen::Index>(dims[0]));
    const hsize_t start[2] = {0, 0}, count[2] = {dims[0], 1};
    Handle memory(H5Screate_simple(2, count, nullptr), H5Sclose);
    if (H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 || !memory.valid() ||
        H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, memory.get(), space.get(), H5P_DEFAULT, time.data()) < 0)
      throw InputError(about(source, where + " cannot be read"));
    H5Sselect_all(space.get());
    const double span = time.maxCoeff() - time.minCoeff();
    if (span > max_span_s) {
      char text[96];
      std::snprintf(text, sizeof text, " spans %.3g s, longer than the %.3g s a push may last", span, max_span_s);
      throw InputError(about(source, std::string("stream '") + name + "'" + text));
    }
  }
  // HDF5 stores row-major; read into a row-major buffer and copy into Eigen's column-major matrix.
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> buffer(static_cast<Eigen::Index>(dims[0]), 4);
  if (dims[0] > 0 && H5Dread(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
    throw InputError(about(source, where + " cannot be read"));
  return buffer;
}

void write_rows(hid_t file, const std::string& target, const char* name, const TimedStream& s) {
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> buffer(s.size(), 4);
  buffer.col(0) = s.t_s;
  buffer.rightCols<3>() = s.values;
  const hsize_t dims[2] = {static_cast<hsize_t>(s.size()), 4};
  Handle space(H5Screate_simple(2, dims, nullptr), H5Sclose);
  Handle dataset(H5Dcreate2(file, name, H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!dataset.valid() || H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
    throw InputError(about(target, std::string("cannot write array '") + name + "'"));
}

/// Time stamps stored as 32-bit floats are refused where they are further apart than this [s].
constexpr double kLargestTimeSpacing_s = 1e-3;

/// The three arrays as doubles, and the width each is stored in.
struct StoredArrays {
  std::array<Eigen::MatrixXd, 3> values;
  std::array<std::int64_t, 3> stored_bits{64, 64, 64};
};

/// The three arrays, as read by libhdf5 (in the isolated caller's child process).
StoredArrays read_arrays(const std::string& source, long long max_rows, double max_span_s) {
  silence_hdf5_errors();
  if (H5Fis_hdf5(source.c_str()) <= 0) throw InputError(about(source, "not an HDF5 file"));
  Handle file(H5Fopen(source.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) {
    const std::string incomplete = incomplete_superblock(source);
    if (!incomplete.empty()) throw InputError(about(source, incomplete));
    const std::string reason = hdf5_failure_reason();
    if (reason.rfind("not a complete HDF5 file", 0) == 0) throw InputError(about(source, reason));
    throw InputError(about(source, "cannot open HDF5 file" + (reason.empty() ? "" : ": " + plain_text(reason))));
  }
  StoredArrays arrays;
  for (std::size_t k = 0; k < kArrayNames.size(); ++k)
    arrays.values[k] = read_rows(file.get(), source, kArrayNames[k], max_rows, max_span_s, arrays.stored_bits[k]);
  return arrays;
}

/// Arrays to bytes and back, to cross the pipe from the child: per array its row count, its stored width in bits,
/// then its values.
std::string encode(const StoredArrays& arrays) {
  std::string bytes;
  for (std::size_t k = 0; k < arrays.values.size(); ++k) {
    const Eigen::MatrixXd& m = arrays.values[k];
    const std::int64_t rows = m.rows();
    bytes.append(reinterpret_cast<const char*>(&rows), sizeof rows);
    bytes.append(reinterpret_cast<const char*>(&arrays.stored_bits[k]), sizeof arrays.stored_bits[k]);
    bytes.append(reinterpret_cast<const char*>(m.data()), sizeof(double) * static_cast<std::size_t>(m.size()));
  }
  return bytes;
}

StoredArrays decode(const std::string& source, const std::string& bytes) {
  StoredArrays arrays;
  std::size_t at = 0;
  for (std::size_t k = 0; k < arrays.values.size(); ++k) {
    Eigen::MatrixXd& m = arrays.values[k];
    std::int64_t rows = 0;
    if (bytes.size() < at + 2 * sizeof rows)
      throw InputError(about(source, "reading the HDF5 file gave a short result"));
    std::memcpy(&rows, bytes.data() + at, sizeof rows);
    at += sizeof rows;
    std::memcpy(&arrays.stored_bits[k], bytes.data() + at, sizeof rows);
    at += sizeof rows;
    const std::size_t n = sizeof(double) * 4 * static_cast<std::size_t>(rows);
    if (rows < 0 || bytes.size() < at + n) throw InputError(about(source, "reading the HDF5 file gave a short result"));
    m.resize(static_cast<Eigen::Index>(rows), 4);
    if (n > 0) std::memcpy(m.data(), bytes.data() + at, n);
    at += n;
  }
  return arrays;
}

/// The reader child's job: the request is max_rows (8 bytes), max_span_s (8 bytes) and the file's path.
std::string read_request(const std::string& request) {
  std::int64_t max_rows = 0;
  double max_span_s = 0;
  std::memcpy(&max_rows, request.data(), sizeof max_rows);
  std::memcpy(&max_span_s, request.data() + sizeof max_rows, sizeof max_span_s);
  return encode(read_arrays(request.substr(sizeof max_rows + sizeof max_span_s), max_rows, max_span_s));
}

}  // namespace

Recording read_recording_hdf5(const std::filesystem::path& path, const ReadOptions& options) {
  const std::string source = path.string();
  check_readable_file(path);
  // libhdf5 (1.10.8) dereferences NULL on some corrupt files: it runs in a child process, so that such a file is one
  // failure of the batch, not the end of it (the fork server of runtime/isolated_call.hpp, unless told otherwise).
  const IsolatedCaller& isolation = options.isolation ? *options.isolation : default_isolated_caller();
  std::string request(sizeof(std::int64_t) + sizeof(double), '\0');
  const std::int64_t max_rows = options.max_rows;
  std::memcpy(request.data(), &max_rows, sizeof max_rows);
  std::memcpy(request.data() + sizeof max_rows, &options.max_span_s, sizeof options.max_span_s);
  request += source;
  const std::string bytes =
      isolation.call("reading the HDF5 file", &read_request, source, request, options.hdf5_timeout_s);
  const StoredArrays arrays = decode(source, bytes);
  Recording r;
  r.source = source;
  r.push = parse_push_filename(source);
  for (std::size_t k = 0; k < kArrayNames.size(); ++k) {
    if (arrays.stored_bits[k] == 64) continue;
    // A float's spacing at t is about t 2^-23: Unix time (1.6e9 s) in 32 bits keeps 128 s, nothing of a push.
    const Eigen::MatrixXd& m = arrays.values[k];
    const double largest_time_s = m.rows() ? m.col(0).cwiseAbs().maxCoeff() : 0.0;
    const double spacing_s = largest_time_s * std::ldexp(1.0, -23);
    if (spacing_s > kLargestTimeSpacing_s) {
      char text[160];
      std::snprintf(text, sizeof text, "%.3g s; 32-bit floats there are %.3g s apart, coarser than %.0f ms",
                    largest_time_s, spacing_s, 1e3 * kLargestTimeSpacing_s);
      throw InputError(about(source, std::string("array '") + kArrayNames[k] +
                                         "' stores its time stamps as 32-bit floats, up to " + text));
    }
    r.repairs.push_back({kArrayNames[k], "stored as 32-bit floats: converted to 64-bit"});
  }
  r.tip_pose = condition_stream(source, "tip_pose", arrays.values[0], options, r.repairs);
  r.object_pose = condition_stream(source, "object_pose", arrays.values[1], options, r.repairs);
  r.ft_wrench = condition_stream(source, "ft_wrench", arrays.values[2], options, r.repairs);
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
