#pragma once
// A recorded push as stored by the MCube dataset, after only the repairs a reader must make (sorting time
// stamps, dropping repeated ones). Nothing is resampled here: see preprocessing/ for the synchronised record.
//
// Frames and signs (as stored): everything is in the robot frame {rbt}; positions in metres, yaw in radians
// (object yaw wrapped to (-pi, pi]); `ft_wrench` is what the sensor at the tip reads, i.e. the reaction on the
// pusher. The force applied to the object is its negative.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pushpred/core/isolated_caller.hpp"

namespace pushpred {

/// One stream: rows [t, a, b, c], t in Unix seconds, strictly increasing after reading.
struct TimedStream {
  Eigen::VectorXd t_s;
  Eigen::MatrixX3d values;

  Eigen::Index size() const { return t_s.size(); }
  double start_s() const { return t_s(0); }
  double end_s() const { return t_s(t_s.size() - 1); }
  /// Samples per second over the whole stream.
  double rate_hz() const { return (size() - 1) / (end_s() - start_s()); }
};

/// The push parameters carried by a file name `motion_surface=S_shape=O_a=A_v=V_i=I_s=P_t=T.h5`.
struct PushParameters {
  std::string surface;
  std::string shape;
  double acceleration_m_s2 = 0;  ///< pusher acceleration; 0 for a constant-speed push
  double speed_m_s = 0;          ///< pusher speed; negative (-0.001) marks an acceleration push, as in the dataset
  double contact_side = 0;       ///< index of the object's side first touched
  double contact_position = 0;   ///< where along that side, 0..1
  double angle_rad = 0;          ///< push direction relative to the side's normal
};

/// Parses an MCube file name (a path is fine); nullopt when it does not follow the pattern.
std::optional<PushParameters> parse_push_filename(std::string_view filename);
/// The file name the dataset would give these parameters, with `extension` (".h5" or ".json").
std::string push_filename(const PushParameters& p, const std::string& extension = ".h5");

/// A repair the reader made to a stream, reported, never silent.
struct StreamRepair {
  std::string stream;
  std::string what;  ///< e.g. "sorted 3 out-of-order time stamps (max 1.2 ms)"
};

struct Recording {
  std::string source;                   ///< file path or a label
  std::optional<PushParameters> push;   ///< from the file name, when it parses
  TimedStream tip_pose;                 ///< tip x, y [m], yaw [rad], robot frame
  TimedStream object_pose;              ///< object centre x, y [m], yaw [rad] (wrapped), robot frame
  TimedStream ft_wrench;                ///< reaction on the pusher: fx, fy [N], tz [N m], robot frame
  std::vector<StreamRepair> repairs;
};

struct ReadOptions {
  /// A time stamp may run back by at most this many median sample periods before the file is rejected;
  /// smaller disorder (real files: up to 1.4 ms) is sorted and reported.
  double max_backstep_periods = 3.0;
  /// Bounds checked before anything is allocated, so that a file declaring a huge array is refused at once. A
  /// real push holds about 1,500 rows per stream; 2e6 rows is over two hours at 250 Hz.
  long long max_rows = 2'000'000;
  long long max_json_bytes = 256LL << 20;  ///< the real JSON file is 94 kB
  /// An HDF5 array whose time stamps span more than this is refused from its time column alone, before its other
  /// columns are read, so that refusing a huge file costs a column, not the file (the bound of
  /// PlausibilityLimits::max_span_s, which checks every recording again after reading).
  double max_span_s = 600.0;
  /// libhdf5 runs through `isolation`, in a child process (runtime/isolated_call.hpp) that is stopped after this long;
  /// a real file takes milliseconds.
  double hdf5_timeout_s = 60.0;
  /// Where libhdf5 runs, so that a crash on a corrupt file costs that file only; nullptr: default_isolated_caller(),
  /// the runtime's fork server in libpushpred.
  const IsolatedCaller* isolation = nullptr;
};

/// Reads an HDF5 or JSON recording, chosen by content (not by extension). Only regular files are opened (a FIFO
/// or device would block or never end). Throws InputError naming the file and the problem, in plain text, for
/// anything malformed: see docs/robustness.md. Plausibility of the values (rates, ranges) is checked later, by
/// check_plausible in preprocessing/.
Recording read_recording(const std::filesystem::path& path, const ReadOptions& options = {});
/// Throws InputError unless `path` is a regular file (following links): says what it is instead (missing, a
/// folder and whether it holds recordings, a FIFO, a device, a link loop).
void check_readable_file(const std::filesystem::path& path);
Recording read_recording_hdf5(const std::filesystem::path& path, const ReadOptions& options = {});
Recording read_recording_json(const std::filesystem::path& path, const ReadOptions& options = {});

/// Writes the three streams in the dataset's HDF5 layout (datasets tip_pose, object_pose, ft_wrench of n x 4
/// doubles), through a temporary file, so that a failed write leaves nothing behind.
void write_recording_hdf5(const Recording& recording, const std::filesystem::path& path);

/// Checks one stream as read (n x 4 rows, finite, at least two, at most options.max_rows samples), sorts small time-stamp disorder,
/// drops repeated stamps, and reports each repair. Exposed for readers of other formats.
TimedStream condition_stream(const std::string& source, const std::string& name, const Eigen::MatrixXd& rows,
                             const ReadOptions& options, std::vector<StreamRepair>& repairs);

}  // namespace pushpred
