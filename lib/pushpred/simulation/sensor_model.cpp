#include "pushpred/simulation/sensor_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>

#include "pushpred/core/batch.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/reading/recording.hpp"
#include "pushpred/mechanics/gravity.hpp"

namespace pushpred {

SensorModel SensorModel::mcube() {
  // From `pushpred simulate --measure-real` on the 90 abs recordings; docs/simulator.md shows the output and
  // how each number below follows from it.
  SensorModel m;
  StreamClock& obj = m.object_pose.clock;
  obj.kind = StreamClock::Kind::JitteredGrid;
  obj.period_s = 1.0 / 250.0;
  obj.jitter_s = 0.226e-3 / std::sqrt(2.0);  // interval core std = sqrt(2) x stamp jitter
  // 2.3 % of intervals are over 1 ms long and about 1 stamp in 1100 runs back (27.8 % of files, about 360
  // stamps each): p exp(-1 ms / m) = 0.023 and p exp(-4 ms / m) = 0.0009 give m = 0.92 ms, p = 0.07.
  obj.late_probability = 0.07;
  obj.late_mean_s = 0.92e-3;
  obj.late_max_s = 6e-3;
  obj.start_offset_min_s = -25e-3;
  obj.start_offset_max_s = -4e-3;
  obj.end_offset_min_s = -12e-3;
  obj.end_offset_max_s = -2e-3;

  StreamClock& ft = m.ft_wrench.clock;  // the reference: it spans the recording
  ft.kind = StreamClock::Kind::JitteredGrid;
  ft.period_s = 1.0 / 250.0;
  ft.jitter_s = 0.012e-3 / std::sqrt(2.0);
  // 1.6 % of intervals over 1 ms long, none out of order: delays of mean 0.6 ms, capped below a period.
  ft.late_probability = 0.0157 * std::exp(1.0 / 0.6);
  ft.late_mean_s = 0.6e-3;
  ft.late_max_s = 3.5e-3;

  StreamClock& tip = m.tip_pose.clock;
  tip.kind = StreamClock::Kind::TwoModeIntervals;
  tip.period_s = 1.0 / 248.0;
  tip.short_interval_s = 3.35e-3;  // the measured modes (3.40, 4.49 ms) less the median of the tail
  tip.long_interval_s = 4.44e-3;
  tip.tail_mean_s = 0.11e-3;  // with these, 47.5 % short intervals give the mean 4.032 ms, as measured
  tip.lock_width_s = 0.8e-3;  // successive intervals correlate at about -0.5, as measured
  tip.start_offset_min_s = -4e-3;
  tip.start_offset_max_s = 2e-3;
  tip.end_offset_min_s = -4e-3;
  tip.end_offset_max_s = 3e-3;

  // {white, slow}, from the measured rest-window spread `total` and first-difference spread `diff` (std of
  // differences / sqrt 2), for a slow Gauss-Markov part of time constant 0.1 s (an assumption):
  // - a 0.18 s window (45 samples, rho = exp(-4 ms / 0.1 s)) holds 0.413 of that process's variance, so
  //   slow = sqrt(total^2 - diff^2) / sqrt(0.413);
  // - its increments add (1 - rho) slow^2 = 0.0392 slow^2 to diff^2, so white = sqrt(diff^2 - 0.0392 slow^2)
  //   (0 for the tip positions, whose measured diff is smaller than that: their slow part is slower still).
  m.object_pose.noise[0] = {1.57e-6, 4.62e-6};
  m.object_pose.noise[1] = {1.52e-6, 4.35e-6};
  m.object_pose.noise[2] = {2.97e-5, 3.34e-5};
  m.ft_wrench.noise[0] = {0.0204, 0.0534};
  m.ft_wrench.noise[1] = {0.0272, 0.1446};
  m.ft_wrench.noise[2] = {3.00e-4, 1.99e-4};
  m.tip_pose.noise[0] = {0.0, 4.66e-6};
  m.tip_pose.noise[1] = {0.0, 5.04e-6};
  m.tip_pose.noise[2] = {1.94e-6, 1.23e-5};
  m.slow_time_constant_s = 0.1;
  return m;
}

StreamSchedule draw_schedule(const StreamClock& c, double duration, double js, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double first = js * (c.start_offset_min_s + (c.start_offset_max_s - c.start_offset_min_s) * unit(rng));
  const double last = duration + js * (c.end_offset_min_s + (c.end_offset_max_s - c.end_offset_min_s) * unit(rng));
  std::vector<double> stamp, sample;
  if (c.kind == StreamClock::Kind::JitteredGrid) {
    if (!(c.period_s > 0)) throw InputError("stream clock period must be positive");
    for (long k = 0;; ++k) {
      const double t = first + k * c.period_s;
      if (t > last) break;
      double off = c.jitter_s * gauss(rng);
      if (unit(rng) < c.late_probability && c.late_mean_s > 0)
        off += std::min(c.late_max_s, -c.late_mean_s * std::log(1.0 - unit(rng)));
      sample.push_back(t);
      stamp.push_back(t + js * off);
    }
  } else {
    if (!(c.period_s > 0) || !(c.long_interval_s > c.short_interval_s))
      throw InputError("stream clock needs a positive period and a long interval above the short one");
    const double p0 = std::clamp(
        (c.period_s - c.short_interval_s - c.tail_mean_s) / (c.long_interval_s - c.short_interval_s), 0.0, 1.0);
    std::exponential_distribution<double> tail(c.tail_mean_s > 0 ? 1.0 / c.tail_mean_s : 1.0);
    double ahead = 0;  // stamp minus its grid time
    for (double t = first; t <= last;) {
      sample.push_back(t);
      stamp.push_back(t);
      const double p_long = c.lock_width_s > 0 ? std::clamp(p0 - ahead / c.lock_width_s, 0.0, 1.0) : p0;
      double interval = unit(rng) < p_long ? c.long_interval_s : c.short_interval_s;
      if (c.tail_mean_s > 0) interval += tail(rng);
      const double step = c.period_s + js * (interval - c.period_s);
      ahead += step - c.period_s;
      t += step;
    }
  }
  StreamSchedule s;
  s.stamp_s = Eigen::Map<Eigen::VectorXd>(stamp.data(), static_cast<Eigen::Index>(stamp.size()));
  s.sample_s = Eigen::Map<Eigen::VectorXd>(sample.data(), static_cast<Eigen::Index>(sample.size()));
  return s;
}

Eigen::MatrixX3d draw_noise(const StreamModel& stream, double tau, const Eigen::VectorXd& t, double ns,
                            std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Eigen::Index n = t.size();
  Eigen::MatrixX3d out(n, 3);
  for (int c = 0; c < 3; ++c) {
    const double white = ns * stream.noise[c].white, slow_std = ns * stream.noise[c].slow;
    double slow = slow_std * gauss(rng);
    for (Eigen::Index k = 0; k < n; ++k) {
      if (k > 0) {
        const double phi = std::exp(-std::abs(t(k) - t(k - 1)) / tau);
        slow = phi * slow + std::sqrt(1 - phi * phi) * slow_std * gauss(rng);
      }
      out(k, c) = slow + white * gauss(rng);
    }
  }
  return out;
}

// ---- Measuring the real recordings ------------------------------------------------------------------------

namespace {

void min_median_max(const std::vector<double>& v, double out[3]) {
  if (v.empty()) return;
  out[0] = *std::min_element(v.begin(), v.end());
  out[1] = median(v);
  out[2] = *std::max_element(v.begin(), v.end());
}

}  // namespace

namespace {

/// |f_C| while the tip covers 30 % to 80 % of its travel (empty when it does not travel).
std::vector<double> mid_push_forces(const SynchronisedPush& p) {
  std::vector<double> f;
  const Eigen::Index n = p.size();
  if (n < 2) return f;
  const Eigen::Vector2d tip0 = p.tip_m.row(0).transpose();
  const Eigen::Vector2d d = p.tip_m.row(n - 1).transpose() - tip0;
  const double travel = d.norm();
  if (travel < 1e-3) return f;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double along = (p.tip_m.row(k).transpose() - tip0).dot(d) / (travel * travel);
    if (along > 0.3 && along < 0.8) f.push_back(p.force_N.row(k).norm());
  }
  return f;
}

}  // namespace

double mid_push_force_per_weight(const SynchronisedPush& p) {
  const std::vector<double> f = mid_push_forces(p);
  return f.empty() ? NAN : median(f) / (p.shape.mass_kg * kGravity_m_s2);
}

double mid_push_force_spread(const SynchronisedPush& p) {
  const std::vector<double> f = mid_push_forces(p);
  return f.size() < 2 ? NAN : standard_deviation(f);
}

namespace {

/// What measure_recordings collects from each file before taking medians over the files.
struct PerFileSamples {
  std::vector<double> rates[3], intervals[3], obj_start, tip_start, obj_end, tip_end;
  std::vector<double> total[3][3], white[3][3];
  std::vector<double> rest_before, rest_after, ramp, length, ratio_all, ratio_central, tip_lag1;
  int out_of_order_files = 0;
};

/// The streams in the order of RecordingStatistics' arrays: object, force, tip.
std::array<const TimedStream*, 3> streams_of(const Recording& r) { return {&r.object_pose, &r.ft_wrench, &r.tip_pose}; }

/// Reads and synchronises one file; a file that fails is listed in `skipped` (when given) and false returned.
bool read_push(const std::filesystem::path& path, Recording& r, SynchronisedPush& p,
               std::vector<std::string>* skipped) {
  try {
    r = read_recording(path);
    p = synchronise(r, shape_for(r, ""));
  } catch (const std::exception& e) {
    if (skipped) skipped->push_back(e.what());
    return false;
  }
  return true;
}

/// The streams' rates, intervals and their order, and where each starts and ends against the force sensor.
void add_stream_timing(PerFileSamples& f, const Recording& r) {
  const auto streams = streams_of(r);
  for (int k = 0; k < 3; ++k) {
    f.rates[k].push_back(streams[k]->rate_hz());
    for (Eigen::Index i = 1; i < streams[k]->size(); ++i)
      f.intervals[k].push_back(streams[k]->t_s(i) - streams[k]->t_s(i - 1));
  }
  {
    const TimedStream& t = r.tip_pose;
    std::vector<double> d;
    for (Eigen::Index i = 1; i < t.size(); ++i) d.push_back(t.t_s(i) - t.t_s(i - 1));
    const double m = std::accumulate(d.begin(), d.end(), 0.0) / d.size();
    double c0 = 0, c1 = 0;
    for (size_t i = 0; i < d.size(); ++i) {
      c0 += (d[i] - m) * (d[i] - m);
      if (i > 0) c1 += (d[i] - m) * (d[i - 1] - m);
    }
    if (c0 > 0) f.tip_lag1.push_back(c1 / c0);
  }
  for (const auto& rep : r.repairs)
    if (rep.stream == "object_pose" && rep.what.rfind("sorted", 0) == 0) {
      ++f.out_of_order_files;
      break;
    }
  f.obj_start.push_back(r.object_pose.start_s() - r.ft_wrench.start_s());
  f.tip_start.push_back(r.tip_pose.start_s() - r.ft_wrench.start_s());
  f.obj_end.push_back(r.object_pose.end_s() - r.ft_wrench.end_s());
  f.tip_end.push_back(r.tip_pose.end_s() - r.ft_wrench.end_s());
}

/// The tip's motion along its overall direction, from the raw tip stream: the rest before and after, the speed
/// ramp and the travel. Returns where the tip ends, or nothing when it does not travel (or the file name gives no
/// speed): such a file has no rest window either.
std::optional<Eigen::Vector2d> add_tip_motion(PerFileSamples& f, const Recording& r) {
  const TimedStream& tip = r.tip_pose;
  const Eigen::Index nt = tip.size();
  const Eigen::Vector2d tip0 = tip.values.row(0).head<2>().transpose();
  const Eigen::Vector2d tip1 = tip.values.row(nt - 1).head<2>().transpose();
  const double travel = (tip1 - tip0).norm();
  if (travel < 1e-3 || !r.push || !(r.push->speed_m_s > 0) || nt < 10) return std::nullopt;
  const Eigen::Vector2d u = (tip1 - tip0) / travel;
  const double v_nominal = r.push->speed_m_s;
  double t_go = NAN, t_cruise = NAN, t_halt = NAN;
  for (Eigen::Index i = 2; i + 2 < nt; ++i) {
    const double v = (tip.values.row(i + 2) - tip.values.row(i - 2)).head<2>().dot(u.transpose()) /
                     (tip.t_s(i + 2) - tip.t_s(i - 2));
    const double t = tip.t_s(i) - tip.start_s();
    if (std::isnan(t_go) && v > 0.05 * v_nominal) t_go = t;
    if (!std::isnan(t_go) && std::isnan(t_cruise) && v > 0.95 * v_nominal) t_cruise = t;
    if (v > 0.05 * v_nominal) t_halt = t;
  }
  f.length.push_back(travel);
  if (!std::isnan(t_go)) f.rest_before.push_back(t_go);
  if (!std::isnan(t_cruise)) f.ramp.push_back(t_cruise - t_go);
  if (!std::isnan(t_halt)) f.rest_after.push_back(tip.end_s() - tip.start_s() - t_halt);
  return tip1;
}

/// The spread of each stream's channels at rest after the push, from 0.1 s after the tip last moved more than
/// 0.2 mm from where it ends (`tip_end`); a frozen force sensor's is left out.
void add_rest_noise(PerFileSamples& f, RecordingStatistics& s, const Recording& r, const Eigen::Vector2d& tip_end,
                    bool live_force) {
  const TimedStream& tip = r.tip_pose;
  double t_still = tip.start_s();
  for (Eigen::Index i = tip.size() - 1; i >= 0; --i)
    if ((tip.values.row(i).head<2>().transpose() - tip_end).norm() > 0.2e-3) {
      t_still = tip.t_s(i);
      break;
    }
  const auto streams = streams_of(r);
  for (int k = 0; k < 3; ++k) {
    if (k == 1 && !live_force) continue;
    const TimedStream& st = *streams[k];
    for (int c = 0; c < 3; ++c) {
      std::vector<double> values, diffs;
      for (Eigen::Index i = 0; i < st.size(); ++i) {
        if (st.t_s(i) < t_still + 0.1) continue;
        if (!values.empty()) diffs.push_back((st.values(i, c) - values.back()) / std::sqrt(2.0));
        values.push_back(st.values(i, c));
      }
      if (values.size() < 20) continue;
      if (c == 0) ++s.rest_windows[k];
      f.total[k][c].push_back(standard_deviation(values));
      f.white[k][c].push_back(standard_deviation(diffs));
    }
  }
}

/// Force per weight in the middle of the push, over all pushes and over those at angle 0.
void add_force_per_weight(PerFileSamples& f, const Recording& r, const SynchronisedPush& p) {
  const double ratio = mid_push_force_per_weight(p);
  if (std::isfinite(ratio)) {
    f.ratio_all.push_back(ratio);
    if (std::abs(r.push->angle_rad) < 1e-6) f.ratio_central.push_back(ratio);
  }
}

void summarise_clocks(RecordingStatistics& s, const PerFileSamples& f) {
  for (int k = 0; k < 3; ++k) {
    s.rate_hz[k] = median(f.rates[k]);
    s.median_interval_s[k] = median(f.intervals[k]);
    std::vector<double> dev;
    int late = 0;
    for (double d : f.intervals[k]) {
      dev.push_back(std::abs(d - s.median_interval_s[k]));
      if (d > s.median_interval_s[k] + 1e-3) ++late;
    }
    s.interval_core_std_s[k] = 1.4826 * median(dev);
    s.late_share[k] = static_cast<double>(late) / f.intervals[k].size();
    for (int c = 0; c < 3; ++c) {
      s.noise_total[k][c] = median(f.total[k][c]);
      s.noise_white[k][c] = median(f.white[k][c]);
    }
  }
  // The tip's intervals fall into two modes on either side of their mean.
  const auto& ti = f.intervals[2];
  const double mean_tip = std::accumulate(ti.begin(), ti.end(), 0.0) / ti.size();
  std::vector<double> shorter, longer;
  for (double d : ti) (d < mean_tip ? shorter : longer).push_back(d);
  s.tip_short_s = median(shorter);
  s.tip_long_s = median(longer);
  s.tip_short_share = static_cast<double>(shorter.size()) / ti.size();
  s.object_out_of_order_share = static_cast<double>(f.out_of_order_files) / s.files;
  s.tip_interval_lag1 = median(f.tip_lag1);
  s.tip_rate_spread_hz[0] = *std::min_element(f.rates[2].begin(), f.rates[2].end());
  s.tip_rate_spread_hz[1] = *std::max_element(f.rates[2].begin(), f.rates[2].end());
  min_median_max(f.obj_start, s.object_start_offset_s);
  min_median_max(f.tip_start, s.tip_start_offset_s);
  min_median_max(f.obj_end, s.object_end_offset_s);
  min_median_max(f.tip_end, s.tip_end_offset_s);
}

void summarise_motion(RecordingStatistics& s, const PerFileSamples& f) {
  s.rest_before_s = median(f.rest_before);
  s.rest_after_s = median(f.rest_after);
  s.ramp_5_95_s = median(f.ramp);
  s.push_length_m = median(f.length);
  s.force_weight_ratio_all = median(f.ratio_all);
  s.force_weight_ratio_central = median(f.ratio_central);
  s.central_files = static_cast<int>(f.ratio_central.size());
}

}  // namespace

RecordingStatistics measure_recordings(const std::vector<std::string>& paths, std::vector<std::string>* skipped) {
  RecordingStatistics s;
  PerFileSamples f;
  for (const auto& path : expand_inputs(paths)) {
    Recording r;
    SynchronisedPush p;
    if (!read_push(path, r, p, skipped)) continue;
    ++s.files;
    const bool live_force = !p.flags.frozen_force_sensor;
    if (live_force) ++s.force_files;
    add_stream_timing(f, r);
    const std::optional<Eigen::Vector2d> tip_end = add_tip_motion(f, r);
    if (!tip_end) continue;
    add_rest_noise(f, s, r, *tip_end, live_force);
    if (live_force) add_force_per_weight(f, r, p);
  }
  if (s.files == 0) throw InputError("no recording could be read from the given paths");
  summarise_clocks(s, f);
  summarise_motion(s, f);
  return s;
}

std::string RecordingStatistics::text() const {
  std::string out;
  char line[512];
  const char* stream[3] = {"object_pose", "ft_wrench", "tip_pose"};
  const char* unit[3][3] = {{"m", "m", "rad"}, {"N", "N", "N m"}, {"m", "m", "rad"}};
  std::snprintf(line, sizeof line, "%d recordings (%d with a live force sensor)\n\n", files, force_files);
  out += line;
  out += "clocks                 rate_hz  median_ms  core_std_ms  late>1ms\n";
  for (int k = 0; k < 3; ++k) {
    std::snprintf(line, sizeof line, "  %-18s %8.2f %10.3f %12.3f %8.4f\n", stream[k], rate_hz[k],
                  median_interval_s[k] * 1e3, interval_core_std_s[k] * 1e3, late_share[k]);
    out += line;
  }
  std::snprintf(line, sizeof line, "  tip intervals: short mode %.3f ms (share %.3f), long mode %.3f ms\n",
                tip_short_s * 1e3, tip_short_share, tip_long_s * 1e3);
  out += line;
  std::snprintf(line, sizeof line,
                "  tip: successive intervals correlate at %.3f (median); rates from %.2f to %.2f Hz over files\n",
                tip_interval_lag1, tip_rate_spread_hz[0], tip_rate_spread_hz[1]);
  out += line;
  std::snprintf(line, sizeof line, "  files with out-of-order object stamps: %.3f\n", object_out_of_order_share);
  out += line;
  auto offsets = [&](const char* what, const double v[3]) {
    std::snprintf(line, sizeof line, "  %-34s min %7.1f  median %7.1f  max %7.1f ms\n", what, v[0] * 1e3, v[1] * 1e3,
                  v[2] * 1e3);
    out += line;
  };
  offsets("object start - force start", object_start_offset_s);
  offsets("tip start - force start", tip_start_offset_s);
  offsets("object end - force end", object_end_offset_s);
  offsets("tip end - force end", tip_end_offset_s);
  out += "\nnoise at rest after the push (median over files)\n";
  out += "  stream       channel   total_std     white_std   (windows)\n";
  const char* channel[3][3] = {{"x", "y", "yaw"}, {"fx", "fy", "tz"}, {"x", "y", "yaw"}};
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) {
      std::snprintf(line, sizeof line, "  %-12s %-4s %11.3g %13.3g   %s (%d)\n", stream[k], channel[k][c],
                    noise_total[k][c], noise_white[k][c], unit[k][c], rest_windows[k]);
      out += line;
    }
  out += "\ntip motion (median over files)\n";
  std::snprintf(line, sizeof line,
                "  rest before %.3f s, speed ramp 5-95 %% %.3f s, rest after %.3f s, push length %.4f m\n",
                rest_before_s, ramp_5_95_s, rest_after_s, push_length_m);
  out += line;
  out += "\nforce per weight in the middle of the push (median |f| / (m g), live sensors)\n";
  std::snprintf(line, sizeof line, "  all pushes %.3f; pushes at angle 0: %.3f (%d files)\n", force_weight_ratio_all,
                force_weight_ratio_central, central_files);
  out += line;
  return out;
}

}  // namespace pushpred
