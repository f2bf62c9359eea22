#pragma once
// How the MCube rig records a push, so that a simulated file looks like a real one: three streams on their own
// clocks with their own jitter, and noise on every channel. SensorModel::mcube() holds the values measured
// from the real recordings by measure_recordings() (`pushpred simulate --measure-real`, docs/simulator.md).
//
// Clocks. The object-pose and force streams tick on a nominal grid; each stamp is off its grid time by
// Gaussian jitter and, now and then, late by an exponentially distributed delay (the cause of the real files'
// slightly out-of-order object stamps, when the delay exceeds a period); the value is the one at the grid time.
// The tip stream's intervals take one of two values (about 3.4 and 4.5 ms in the real files) plus an
// exponential tail, the choice between them keeping the stamps within a millisecond or two of a 248 Hz grid
// (as in the real files: every tip stream runs at 248.0 +- 0.3 Hz and successive intervals correlate at about
// -0.5); the value is the one at the stamp. Streams start and end a few milliseconds apart, as measured.
//
// Noise. Each channel carries white Gaussian noise plus a slow first-order Gauss-Markov part (time constant
// `slow_time_constant_s`, an assumption: the real rest windows are too short to measure it), whose standard
// deviations together give the real files' spread at rest.
#include <Eigen/Core>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace pushpred {

struct SynchronisedPush;

struct StreamClock {
  enum class Kind { JitteredGrid, TwoModeIntervals };
  Kind kind = Kind::JitteredGrid;
  double period_s = 0.004;      ///< grid period (JitteredGrid)
  double jitter_s = 0;          ///< Gaussian stamp jitter (JitteredGrid)
  double late_probability = 0;  ///< chance that a stamp is late (JitteredGrid)...
  double late_mean_s = 0;       ///< ...by an exponential delay of this mean...
  double late_max_s = 0;        ///< ...capped here
  double short_interval_s = 0;  ///< TwoModeIntervals: the two interval modes...
  double long_interval_s = 0;
  double tail_mean_s = 0;  ///< ...the mean of the exponential excess added to each...
  /// ...and how tightly the stamps stay on the nominal grid of period_s: a stamp D ahead of its grid time makes
  /// the next interval long with probability p0 - D / lock_width_s (p0 the share that gives the mean period).
  double lock_width_s = 0;
  double start_offset_min_s = 0, start_offset_max_s = 0;  ///< first stamp relative to the recording start
  double end_offset_min_s = 0, end_offset_max_s = 0;      ///< last stamp relative to the recording end
};

struct ChannelNoise {
  double white = 0;  ///< std of the white part
  double slow = 0;   ///< std of the slow Gauss-Markov part
};

struct StreamModel {
  StreamClock clock;
  ChannelNoise noise[3];  ///< the three value columns (x, y, yaw or fx, fy, tz), SI units
};

struct SensorModel {
  StreamModel object_pose, ft_wrench, tip_pose;
  double slow_time_constant_s = 0.1;
  /// The rig as measured from the real recordings (see the file comment).
  static SensorModel mcube();
};

/// When each sample is taken and what it is stamped, on the simulation clock [s].
struct StreamSchedule {
  Eigen::VectorXd stamp_s;   ///< as written (may be slightly out of order)
  Eigen::VectorXd sample_s;  ///< the instant whose value the sample holds
};

/// Draws the schedule of one stream over a recording [0, duration_s]. `jitter_scale` scales every timing
/// irregularity (0: an ideal clock at the nominal rate).
StreamSchedule draw_schedule(const StreamClock& clock, double duration_s, double jitter_scale, std::mt19937_64& rng);

/// Noise for the three channels of one stream at the (stamp) times `t_s`, scaled by `noise_scale`.
Eigen::MatrixX3d draw_noise(const StreamModel& stream, double slow_time_constant_s, const Eigen::VectorXd& t_s,
                            double noise_scale, std::mt19937_64& rng);

/// What the real recordings show about the rig, for the defaults above and docs/simulator.md.
struct RecordingStatistics {
  int files = 0, force_files = 0;  ///< files read; of them, with a live force sensor
  double rate_hz[3] = {0, 0, 0};   ///< median mean rate: object, force, tip
  double median_interval_s[3] = {0, 0, 0};
  double interval_core_std_s[3] = {0, 0, 0};  ///< 1.4826 MAD of the intervals around their median
  double late_share[3] = {0, 0, 0};           ///< share of intervals more than 1 ms longer than the median
  double tip_short_s = 0, tip_long_s = 0, tip_short_share = 0;  ///< the tip's two interval modes
  double tip_interval_lag1 = 0;                                 ///< median correlation of successive tip intervals
  double tip_rate_spread_hz[2] = {0, 0};                        ///< min and max tip rate over files
  double object_out_of_order_share = 0;                         ///< share of files whose object stamps needed sorting
  double object_start_offset_s[3] = {0, 0, 0};                  ///< min, median, max of (object start - force start)
  double tip_start_offset_s[3] = {0, 0, 0};
  double object_end_offset_s[3] = {0, 0, 0};
  double tip_end_offset_s[3] = {0, 0, 0};
  double noise_total[3][3] = {};    ///< median std at rest, [stream][channel]
  double noise_white[3][3] = {};    ///< median std of first differences / sqrt 2
  int rest_windows[3] = {0, 0, 0};  ///< files contributing a rest window, per stream
  double rest_before_s = 0, rest_after_s = 0, ramp_5_95_s = 0, push_length_m = 0;  ///< medians
  double force_weight_ratio_all = 0;      ///< median |f| / (m g) in the middle of the push, live sensors
  double force_weight_ratio_central = 0;  ///< the same for pushes at angle 0
  int central_files = 0;
  std::string text() const;  ///< a readable report
};

/// Median |f_C| / (m g) while the tip covers 30 % to 80 % of its travel: the force level of a push in units of
/// the object's weight (the Coulomb coefficient, for a push that does not turn the object). NaN when the tip
/// does not travel.
double mid_push_force_per_weight(const SynchronisedPush& push);
/// Standard deviation of |f_C| [N] over the same span: how much the force fluctuates while pushing.
double mid_push_force_spread(const SynchronisedPush& push);

/// Measures the recordings at `paths` (files or folders); files that fail to load are skipped and listed in
/// `skipped`.
RecordingStatistics measure_recordings(const std::vector<std::string>& paths,
                                       std::vector<std::string>* skipped = nullptr);

}  // namespace pushpred
