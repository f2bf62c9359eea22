#include "pushpred/reading/recording.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

#include "pushpred/core/data_folder.hpp"
#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

std::string format_ms(double seconds) { return three_significant_digits(seconds * 1e3) + " ms"; }

}  // namespace

TimedStream condition_stream(const std::string& source, const std::string& name, const Eigen::MatrixXd& rows,
                             const ReadOptions& options, std::vector<StreamRepair>& repairs) {
  const std::string where = "array '" + name + "'";
  if (rows.cols() != 4)
    throw InputError(about(source, where + " has " + std::to_string(rows.cols()) + " columns, expected 4 [t, a, b, c]"));
  if (rows.rows() == 0) throw InputError(about(source, where + " is empty"));
  if (rows.rows() < 2) throw InputError(about(source, where + " has one sample; need at least two"));
  if (rows.rows() > options.max_rows)
    throw InputError(about(source, where + " has " + std::to_string(rows.rows()) + " rows, more than the " +
                                       std::to_string(options.max_rows) + " a recording may hold"));
  for (Eigen::Index i = 0; i < rows.rows(); ++i)
    for (Eigen::Index j = 0; j < 4; ++j)
      if (!std::isfinite(rows(i, j)))
        throw InputError(about(source, where + " holds " + (std::isnan(rows(i, j)) ? "NaN" : "Inf") + " at row " +
                                           std::to_string(i) + ", column " + std::to_string(j)));

  const Eigen::Index n = rows.rows();
  // Median of the positive steps: the nominal sample period, robust to the disorder being checked.
  std::vector<double> steps;
  steps.reserve(n);
  for (Eigen::Index i = 1; i < n; ++i)
    if (rows(i, 0) > rows(i - 1, 0)) steps.push_back(rows(i, 0) - rows(i - 1, 0));
  if (steps.empty()) throw InputError(about(source, where + ": time does not advance"));
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  const double period = steps[steps.size() / 2];

  double running_max = rows(0, 0);
  int out_of_order = 0;
  double worst_backstep = 0;
  for (Eigen::Index i = 1; i < n; ++i) {
    const double back = running_max - rows(i, 0);
    if (back > options.max_backstep_periods * period) {
      throw InputError(about(source, where + ": time goes backwards by " + format_ms(back) + " at row " +
                                         std::to_string(i) + " (more than " +
                                         std::to_string(static_cast<int>(options.max_backstep_periods)) +
                                         " sample periods)"));
    }
    if (back > 0) {
      ++out_of_order;
      worst_backstep = std::max(worst_backstep, back);
    }
    running_max = std::max(running_max, rows(i, 0));
  }

  std::vector<Eigen::Index> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return rows(a, 0) < rows(b, 0); });
  if (out_of_order > 0)
    repairs.push_back({name, "sorted " + std::to_string(out_of_order) + " out-of-order time stamps (max " +
                                 format_ms(worst_backstep) + ")"});

  TimedStream s;
  s.t_s.resize(n);
  s.values.resize(n, 3);
  Eigen::Index kept = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index i = order[k];
    if (kept > 0 && rows(i, 0) == s.t_s(kept - 1)) continue;  // a repeated stamp: keep the first sample
    s.t_s(kept) = rows(i, 0);
    s.values.row(kept) = rows.row(i).tail<3>();
    ++kept;
  }
  if (kept < n) {
    repairs.push_back({name, "dropped " + std::to_string(n - kept) + " samples with repeated time stamps"});
    s.t_s.conservativeResize(kept);
    s.values.conservativeResize(kept, 3);
  }
  if (kept < 2) throw InputError(about(source, where + " has fewer than two distinct time stamps"));
  return s;
}

void check_readable_file(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  const std::string source = path.string();
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) throw InputError(about(source, "file does not exist"));
  if (ec) throw InputError(about(source, "cannot be read: " + ec.message()));
  if (status.type() == fs::file_type::directory) {
    std::vector<fs::path> inside;
    try {
      inside = list_recordings(path);
    } catch (const std::exception&) {
    }
    fs::directory_iterator it(path, ec);
    if (ec) throw InputError(about(source, "is a folder that cannot be listed: " + ec.message()));
    if (inside.empty()) throw InputError(about(source, "is a folder holding no recordings (*.h5, *.json)"));
    throw InputError(about(source, "is a folder, not a recording"));
  }
  if (status.type() != fs::file_type::regular) {
    const char* kind = status.type() == fs::file_type::fifo      ? "a FIFO"
                       : status.type() == fs::file_type::socket  ? "a socket"
                       : status.type() == fs::file_type::block   ? "a block device"
                       : status.type() == fs::file_type::character ? "a character device"
                                                                   : "not a regular file";
    throw InputError(about(source, std::string("is ") + kind + "; only regular files are read"));
  }
}

Recording read_recording(const std::filesystem::path& path, const ReadOptions& options) {
  check_readable_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(about(path.string(), "cannot open file"));
  char head[16] = {};
  in.read(head, sizeof head);
  const std::streamsize got = in.gcount();
  static const char kHdf5Signature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  if (got >= 8 && std::equal(head, head + 8, kHdf5Signature)) return read_recording_hdf5(path, options);
  // A file with a user block (h5py's userblock_size, h5jam) carries the signature at 512, 1024, 2048, ... bytes:
  // where the HDF5 library itself looks for it.
  for (std::streamoff at = 512; got == static_cast<std::streamsize>(sizeof head); at *= 2) {
    char signature[8] = {};
    in.clear();
    in.seekg(at);
    if (!in.read(signature, sizeof signature)) break;
    if (std::equal(signature, signature + 8, kHdf5Signature)) return read_recording_hdf5(path, options);
  }
  std::streamsize i = 0;
  if (got >= 3 && head[0] == '\xEF' && head[1] == '\xBB' && head[2] == '\xBF') i = 3;  // UTF-8 byte-order mark
  for (; i < got; ++i) {
    const char c = head[i];
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    if (c == '{' || c == '[') return read_recording_json(path, options);
    break;
  }
  if (got == 0) throw InputError(about(path.string(), "file is empty"));
  throw InputError(about(path.string(), "neither an HDF5 nor a JSON recording"));
}

}  // namespace pushpred
