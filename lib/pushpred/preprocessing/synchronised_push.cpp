#include "pushpred/preprocessing/synchronised_push.hpp"

#include <algorithm>
#include <sstream>
#include <cmath>
#include <cstdio>
#include <set>
#include <tuple>

#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/plausibility.hpp"

namespace pushpred {

std::vector<std::string> PushFlags::names() const {
  std::vector<std::string> n;
  if (frozen_force_sensor) n.emplace_back("frozen_force_sensor");
  if (barely_moves) n.emplace_back("barely_moves");
  if (no_contact) n.emplace_back("no_contact");
  if (contact_from_geometry) n.emplace_back("contact_from_geometry");
  return n;
}

Eigen::MatrixX3d SynchronisedPush::applied_input() const {
  Eigen::MatrixX3d u(size(), 3);
  u.leftCols<2>() = force_N;
  u.col(2) = torque_about_centre_Nm;
  return u;
}

Eigen::Index SynchronisedPush::index_at(double t) const {
  if (size() == 0) return 0;
  const auto it = std::lower_bound(t_s.data(), t_s.data() + t_s.size(), t - 1e-9);
  return std::min<Eigen::Index>(it - t_s.data(), size() - 1);
}

Eigen::VectorXd unwrap_angle(const Eigen::VectorXd& wrapped) {
  Eigen::VectorXd out = wrapped;
  double offset = 0;
  for (Eigen::Index i = 1; i < wrapped.size(); ++i) {
    const double d = wrapped(i) - wrapped(i - 1);
    if (d > M_PI) offset -= 2 * M_PI * std::round(d / (2 * M_PI));
    else if (d < -M_PI) offset += 2 * M_PI * std::round(-d / (2 * M_PI));
    out(i) = wrapped(i) + offset;
  }
  return out;
}

int remove_single_sample_glitches(Eigen::MatrixX3d& pose, double pos_thr, double yaw_thr) {
  int count = 0;
  for (Eigen::Index i = 1; i + 1 < pose.rows(); ++i) {
    const Eigen::RowVector3d mid = 0.5 * (pose.row(i - 1) + pose.row(i + 1));
    const Eigen::RowVector3d off = pose.row(i) - mid;
    const Eigen::RowVector3d span = pose.row(i + 1) - pose.row(i - 1);
    const double off_pos = off.head<2>().norm(), off_yaw = std::abs(off(2));
    // A glitch stands out from both neighbours while the neighbours agree with each other: a real jump
    // (fast motion) moves the neighbours apart as much as it moves the sample.
    const bool pos_glitch = off_pos > pos_thr && span.head<2>().norm() < off_pos;
    const bool yaw_glitch = off_yaw > yaw_thr && std::abs(span(2)) < off_yaw;
    if (pos_glitch || yaw_glitch) {
      pose.row(i) = mid;
      ++count;
    }
  }
  return count;
}

Eigen::MatrixXd interpolate_linear(const Eigen::VectorXd& t, const Eigen::MatrixXd& v, const Eigen::VectorXd& grid) {
  Eigen::MatrixXd out(grid.size(), v.cols());
  Eigen::Index j = 0;
  for (Eigen::Index k = 0; k < grid.size(); ++k) {
    const double g = grid(k);
    while (j + 2 < t.size() && t(j + 1) < g) ++j;
    const double w = std::clamp((g - t(j)) / (t(j + 1) - t(j)), 0.0, 1.0);
    out.row(k) = (1 - w) * v.row(j) + w * v.row(j + 1);
  }
  return out;
}

bool force_stream_frozen(const TimedStream& ft) {
  std::set<std::tuple<double, double, double>> distinct;
  int run = 1, longest = 1;
  for (Eigen::Index i = 0; i < ft.size(); ++i) {
    distinct.insert({ft.values(i, 0), ft.values(i, 1), ft.values(i, 2)});
    if (i > 0 && ft.values.row(i) == ft.values.row(i - 1)) longest = std::max(longest, ++run);
    else run = 1;
  }
  // A live sensor at 250 Hz never repeats a reading exactly; frozen ones hold 2-4 values for most samples.
  return distinct.size() < 0.5 * static_cast<double>(ft.size()) || longest >= 10;
}

const ShapeInfo& shape_for(const Recording& r, const std::string& shape_override, const ShapeTable& table) {
  if (!shape_override.empty()) {
    try {
      return table.find(shape_override);
    } catch (const InputError& e) {
      throw InputError(about(r.source, e.what()));
    }
  }
  if (!r.push)
    throw InputError(about(r.source,
                           "file name does not parse as motion_surface=S_shape=O_a=A_v=V_i=I_s=P_t=T; "
                           "give the shape with --shape (in Python: shape=)"));
  try {
    return table.find(r.push->shape);
  } catch (const InputError& e) {
    throw InputError(about(r.source, e.what()));
  }
}

SynchronisedPush synchronise(const Recording& r, const ShapeInfo& shape, const PreprocessOptions& o) {
  require_positive_finite(o.rate_hz, "resampling rate");
  // A grid finer than the fastest stream a recording may hold only interpolates, and a rate of 1e9 Hz would ask for
  // billions of samples.
  if (o.rate_hz > o.limits.max_rate_hz) {
    char text[128];
    std::snprintf(text, sizeof text, "resampling rate of %g Hz is above the %g Hz a recording's streams may run at",
                  o.rate_hz, o.limits.max_rate_hz);
    throw InputError(text);
  }
  check_plausible(r, o.limits);
  SynchronisedPush p;
  p.source = r.source;
  if (r.push) p.push = *r.push;
  else p.push.surface = "unknown";
  p.push.shape = shape.name;
  p.shape = shape;
  p.rate_hz = o.rate_hz;
  p.repairs = r.repairs;
  p.stream_rate_hz[0] = r.object_pose.rate_hz();
  p.stream_rate_hz[1] = r.ft_wrench.rate_hz();
  p.stream_rate_hz[2] = r.tip_pose.rate_hz();

  const double start = std::max({r.object_pose.start_s(), r.ft_wrench.start_s(), r.tip_pose.start_s()});
  const double end = std::min({r.object_pose.end_s(), r.ft_wrench.end_s(), r.tip_pose.end_s()});
  if (!(end > start)) throw InputError(about(r.source, "the three streams do not overlap in time"));
  const Eigen::Index n = static_cast<Eigen::Index>(std::floor((end - start) * o.rate_hz + 1e-9)) + 1;
  if (n < 2) throw InputError(about(r.source, "the streams overlap for less than two grid samples"));
  p.t0_unix_s = start;
  p.t_s = Eigen::VectorXd::LinSpaced(n, 0.0, (n - 1) / o.rate_hz);
  const Eigen::VectorXd grid = p.t_s.array() + start;

  Eigen::MatrixX3d object = r.object_pose.values;
  object.col(2) = unwrap_angle(object.col(2));
  p.object_glitches = remove_single_sample_glitches(object, o.glitch_position_m, o.glitch_yaw_rad);
  Eigen::MatrixX3d tip = r.tip_pose.values;
  tip.col(2) = unwrap_angle(tip.col(2));
  p.tip_glitches = remove_single_sample_glitches(tip, o.glitch_position_m, o.glitch_yaw_rad);
  if (p.object_glitches)
    p.repairs.push_back({"object_pose", "replaced " + std::to_string(p.object_glitches) + " single-sample glitches"});
  if (p.tip_glitches)
    p.repairs.push_back({"tip_pose", "replaced " + std::to_string(p.tip_glitches) + " single-sample glitches"});

  p.pose = interpolate_linear(r.object_pose.t_s, object, grid);
  const Eigen::MatrixXd tip_g = interpolate_linear(r.tip_pose.t_s, tip, grid);
  const Eigen::MatrixXd ft_g = interpolate_linear(r.ft_wrench.t_s, r.ft_wrench.values, grid);

  p.tip_m.resize(n, 2);
  p.tip_yaw_rad = tip_g.col(2);
  p.force_N.resize(n, 2);
  p.lever_m.resize(n, 2);
  p.tip_torque_Nm = -ft_g.col(2);
  p.torque_about_centre_Nm.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double c = std::cos(p.tip_yaw_rad(k)), s = std::sin(p.tip_yaw_rad(k));
    Eigen::Matrix2d C;
    C << c, -s, s, c;
    p.tip_m.row(k) = (C * tip_g.row(k).head<2>().transpose()).transpose();
    p.force_N.row(k) = -(C * ft_g.row(k).head<2>().transpose()).transpose();
    p.lever_m.row(k) = p.tip_m.row(k) - p.pose.row(k).head<2>();
    const double cross = p.lever_m(k, 0) * p.force_N(k, 1) - p.lever_m(k, 1) * p.force_N(k, 0);
    p.torque_about_centre_Nm(k) = p.tip_torque_Nm(k) + cross;
  }

  p.flags.frozen_force_sensor = force_stream_frozen(r.ft_wrench);
  const double travel = (p.pose.row(n - 1).head<2>() - p.pose.row(0).head<2>()).norm();
  p.flags.barely_moves = travel < o.barely_moves_m;

  p.in_contact.assign(n, 0);
  if (!p.flags.frozen_force_sensor) {
    for (Eigen::Index k = 0; k < n; ++k) p.in_contact[k] = p.force_N.row(k).norm() > o.contact_force_N;
  } else if (shape.has_outline()) {
    // The force cannot be trusted: contact is where the rod's surface touches the outline.
    p.flags.contact_from_geometry = true;
    for (Eigen::Index k = 0; k < n; ++k) {
      const double c = std::cos(p.pose(k, 2)), s = std::sin(p.pose(k, 2));
      const Eigen::Vector2d d = p.lever_m.row(k).transpose();
      const Eigen::Vector2d body(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
      p.in_contact[k] = signed_distance_to_outline(shape, body) - kPusherRadius_m < o.contact_gap_m;
    }
  }
  const auto first = std::find(p.in_contact.begin(), p.in_contact.end(), 1);
  if (first == p.in_contact.end()) {
    p.flags.no_contact = true;
  } else {
    const auto last = std::find(p.in_contact.rbegin(), p.in_contact.rend(), 1);
    p.has_contact = true;
    p.contact_start_s = p.t_s(first - p.in_contact.begin());
    p.contact_end_s = p.t_s(static_cast<Eigen::Index>(p.in_contact.rend() - last) - 1);
  }
  check_plausible_motion(p, o.limits);
  return p;
}

SynchronisedPush load_push(const std::filesystem::path& path, const std::string& shape_override,
                           const PreprocessOptions& options) {
  const Recording r = read_recording(path);
  return synchronise(r, shape_for(r, shape_override), options);
}

void check_plausible_motion(const SynchronisedPush& p, const PlausibilityLimits& limits) {
  const Eigen::Index n = p.size();
  if (n < 2 || !(p.rate_hz > 0)) return;
  const Eigen::Index w =
      std::max<Eigen::Index>(1, static_cast<Eigen::Index>(std::lround(limits.motion_window_s * p.rate_hz)));
  const auto at = [&](Eigen::Index k) {
    return "at t = " + three_significant_digits(p.t_s(k)) + " s (grid sample " + std::to_string(k) + ")";
  };
  const auto refuse = [&](const std::string& what) {
    throw InputError(about(p.source, what + "; docs/robustness.md says why such motion is refused"));
  };
  const double rho =
      p.shape.mass_kg > 0 && p.shape.inertia_kgm2 > 0 ? std::sqrt(p.shape.inertia_kgm2 / p.shape.mass_kg) : 0.0;
  const double max_yaw_rate = rho > 0 ? limits.max_speed_m_s / rho : 0.0;
  // Speed, then yaw rate, then acceleration, so that a jump is named by the first of them it breaks.
  for (Eigen::Index k = 0; k + w < n; ++k) {
    const double speed = (p.pose.row(k + w).head<2>() - p.pose.row(k).head<2>()).norm() / (p.t_s(k + w) - p.t_s(k));
    if (speed > limits.max_speed_m_s)
      refuse("object_pose moves at " + three_significant_digits(speed) + " m/s " + at(k) + ", beyond the " +
             three_significant_digits(limits.max_speed_m_s) + " m/s a pushed object can");
  }
  for (Eigen::Index k = 0; max_yaw_rate > 0 && k + w < n; ++k) {
    const double yaw_rate = std::abs(p.pose(k + w, 2) - p.pose(k, 2)) / (p.t_s(k + w) - p.t_s(k));
    if (yaw_rate > max_yaw_rate)
      refuse("object_pose turns at " + three_significant_digits(yaw_rate) + " rad/s " + at(k) + ", beyond the " + three_significant_digits(max_yaw_rate) +
             " rad/s at which a point of " + p.shape.name + " one radius of gyration (" + three_significant_digits(1e3 * rho) +
             " mm) from its centre would move at " + three_significant_digits(limits.max_speed_m_s) + " m/s");
  }
  for (Eigen::Index k = 0; k + 2 * w < n; ++k) {
    const double h = 0.5 * (p.t_s(k + 2 * w) - p.t_s(k));
    const double acceleration =
        (p.pose.row(k + 2 * w).head<2>() - 2 * p.pose.row(k + w).head<2>() + p.pose.row(k).head<2>()).norm() / (h * h);
    if (acceleration > limits.max_acceleration_m_s2)
      refuse("object_pose accelerates at " + three_significant_digits(acceleration) + " m/s^2 " + at(k + w) + ", beyond the " +
             three_significant_digits(limits.max_acceleration_m_s2) + " m/s^2 a push force and friction can give it");
  }
  if (!p.shape.has_outline()) return;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double c = std::cos(p.pose(k, 2)), s = std::sin(p.pose(k, 2));
    const Eigen::Vector2d d = p.lever_m.row(k).transpose();
    const Eigen::Vector2d body(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
    const double penetration = kPusherRadius_m - signed_distance_to_outline(p.shape, body);
    if (penetration > limits.max_tip_penetration_m)
      refuse("the rod's surface lies " + three_significant_digits(1e3 * penetration) + " mm inside " + p.shape.name + "'s outline " +
             at(k) + ", more than the " + three_significant_digits(1e3 * limits.max_tip_penetration_m) +
             " mm a pressed contact allows: the object pose is not the object's");
  }
}

}  // namespace pushpred
