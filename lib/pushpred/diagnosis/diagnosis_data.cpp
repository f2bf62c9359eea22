#include "pushpred/diagnosis/diagnosis_data.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "pushpred/systems/exact_discretisation.hpp"

namespace pushpred {

EffectState DiagnosisPush::state(Eigen::Index row) const {
  EffectState s;
  s.pose = smooth_pose.row(row).transpose();
  s.velocity = smooth_velocity.row(row).transpose();
  s.input = estimate.u.row(row).transpose();
  s.start_pose = push.pose.row(0).transpose();
  return s;
}

Eigen::MatrixX3d DiagnosisPush::as_observed(const Eigen::MatrixX3d& raw) const {
  if (raw.rows() != rows()) throw InputError("diagnosis: a regressor has the wrong number of rows");
  Eigen::MatrixX3d masked = raw;
  for (Eigen::Index k = 0; k < masked.rows(); ++k)
    if (stuck[k]) masked.row(k).setZero();
  return q_filter(estimate.t_s, masked, q_zeta, q_wn_rad_s, nullptr, FilterOutput::IntervalMean);
}

Eigen::MatrixXd zero_phase_smooth(const Eigen::VectorXd& t_s, const Eigen::MatrixXd& values, double wn,
                                  Eigen::MatrixXd* rate) {
  const double zeta = 1.0 / std::sqrt(2.0);
  const Eigen::Index n = t_s.size();
  const Eigen::MatrixXd forward = q_filter(t_s, values, zeta, wn);
  // Backward: the same filter on reversed time (t -> t_end - t keeps the steps).
  const Eigen::VectorXd reversed_t = (t_s(n - 1) - t_s.reverse().array()).matrix();
  Eigen::MatrixXd backward_rate;
  const Eigen::MatrixXd backward = q_filter(reversed_t, forward.colwise().reverse(), zeta, wn, &backward_rate);
  if (rate) *rate = -backward_rate.colwise().reverse();
  return backward.colwise().reverse();
}

Eigen::MatrixXd q_filter(const Eigen::VectorXd& t_s, const Eigen::MatrixXd& values, double zeta, double wn,
                         Eigen::MatrixXd* rate, FilterOutput output) {
  const Eigen::Index m = values.cols(), n = values.rows();
  if (n != t_s.size() || n < 2) throw InputError("q_filter: need at least two samples, one per time");
  // One second-order filter per column: states (z, z') of column c at 2c, 2c + 1.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * m, 2 * m), B = Eigen::MatrixXd::Zero(2 * m, m);
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(2 * m);
  for (Eigen::Index c = 0; c < m; ++c) {
    A(2 * c, 2 * c + 1) = 1;
    A(2 * c + 1, 2 * c) = -wn * wn;
    A(2 * c + 1, 2 * c + 1) = -2 * zeta * wn;
    B(2 * c + 1, c) = wn * wn;
    x0(2 * c) = values(0, c);
  }
  const Eigen::MatrixXd states = propagate_exactly(A, B, x0, SampledSignal(t_s, values, Hold::First));
  Eigen::MatrixXd out(n, m);
  if (rate) rate->resize(n, m);
  for (Eigen::Index c = 0; c < m; ++c) {
    if (output == FilterOutput::Point) {
      out.col(c) = states.col(2 * c);
      if (rate) rate->col(c) = states.col(2 * c + 1);
      continue;
    }
    // Over [t_{k-1}, t_k]: the observer's interval mean (q_filter_interval_mean), mean x the trapezoid under
    // first-order hold; mean z' = D z / h.
    for (Eigen::Index k = 1; k < n; ++k) {
      const double h = t_s(k) - t_s(k - 1);
      const double dz = states(k, 2 * c) - states(k - 1, 2 * c), dv = states(k, 2 * c + 1) - states(k - 1, 2 * c + 1);
      out(k, c) = q_filter_interval_mean(0.5 * (values(k - 1, c) + values(k, c)), dz, dv, zeta, wn, h);
      if (rate) (*rate)(k, c) = dz / h;
    }
    out(0, c) = out(1, c);
    if (rate) (*rate)(0, c) = (*rate)(1, c);
  }
  return out;
}

DiagnosisPush prepare_diagnosis_push(const SynchronisedPush& push, double t0, double t1,
                                     const QFilterObserverOptions& options) {
  const QFilterObserver observer(options);
  // The exact discretisation: the same estimate as the CVODE path (the observer's tests hold them together),
  // many times faster for this linear system.
  return diagnosis_push_from_estimate(push, observer.estimate_exactly(push, t0, t1), options);
}

DiagnosisPush diagnosis_push_from_estimate(const SynchronisedPush& push, DisturbanceEstimate estimate,
                                           const QFilterObserverOptions& options) {
  if (estimate.t_s.size() < 2) throw InputError(about(push.source, "diagnosis: an estimate of fewer than 2 samples"));
  DiagnosisPush d;
  d.push = push;
  d.estimate = std::move(estimate);
  d.first = push.index_at(d.estimate.t_s(0));
  Eigen::MatrixXd rate;
  d.filtered_input =
      q_filter(d.estimate.t_s, d.estimate.u, options.zeta, options.wn_rad_s, &rate, FilterOutput::IntervalMean);
  d.filtered_input_rate = rate;
  const Eigen::MatrixX3d y = push.pose.middleRows(d.first, d.rows()).rowwise() - push.pose.row(d.first);
  Eigen::MatrixXd velocity;
  d.smooth_pose = zero_phase_smooth(d.estimate.t_s, y, kSmoothingBandwidth_rad_s, &velocity);
  d.smooth_pose.rowwise() += push.pose.row(d.first);
  d.smooth_velocity = velocity;
  Eigen::MatrixXd acceleration;
  zero_phase_smooth(d.estimate.t_s, d.smooth_velocity, kSmoothingBandwidth_rad_s, &acceleration);
  d.smooth_acceleration = acceleration;
  d.stuck.resize(d.rows());
  d.unresolved.resize(d.rows());
  d.blurred.resize(d.rows());
  // sliding_speed of the acceleration: the same footprint measure of a rate of change.
  std::vector<double> sliding_rate(static_cast<std::size_t>(d.rows()));
  for (Eigen::Index k = 0; k < d.rows(); ++k)
    sliding_rate[static_cast<std::size_t>(k)] = sliding_speed(d.smooth_acceleration.row(k).transpose(), push.shape);
  for (Eigen::Index k = 0; k < d.rows(); ++k) {
    const double speed = sliding_speed(d.smooth_velocity.row(k).transpose(), push.shape);
    d.stuck[k] = speed < kStuckSpeed_m_s;
    d.unresolved[k] = !d.stuck[k] && speed < kSpeedResolution_s * sliding_rate[static_cast<std::size_t>(k)];
    // The largest rate within the smoother's time scale: in the blurred tail of a start or stop the smoothed
    // acceleration passes through zero, and the speed there (a few mm/s) is still the blur, not a slow slide.
    double largest_rate = 0;
    for (Eigen::Index j = k; j >= 0 && d.estimate.t_s(k) - d.estimate.t_s(j) <= kSpeedResolution_s; --j)
      largest_rate = std::max(largest_rate, sliding_rate[static_cast<std::size_t>(j)]);
    for (Eigen::Index j = k + 1; j < d.rows() && d.estimate.t_s(j) - d.estimate.t_s(k) <= kSpeedResolution_s; ++j)
      largest_rate = std::max(largest_rate, sliding_rate[static_cast<std::size_t>(j)]);
    d.blurred[k] = !d.stuck[k] && speed < kSpeedResolution_s * largest_rate;
  }
  d.friction_explained = Eigen::MatrixX3d::Zero(d.rows(), 3);
  d.q_zeta = options.zeta;
  d.q_wn_rad_s = options.wn_rad_s;
  return d;
}

SynchronisedPush apply_data_correction(const SynchronisedPush& push, const ModelCorrection& c) {
  SynchronisedPush p = push;
  const Eigen::Index n = p.size();
  if (c.force_delay_s != 0 && n >= 2) {
    Eigen::MatrixXd values(n, 3);
    values.leftCols<2>() = push.force_N;
    values.col(2) = push.tip_torque_Nm;
    Eigen::VectorXd query = (push.t_s.array() + c.force_delay_s).matrix();
    for (Eigen::Index k = 0; k < n; ++k) query(k) = std::clamp(query(k), push.t_s(0), push.t_s(n - 1));
    const Eigen::MatrixXd shifted = interpolate_linear(push.t_s, values, query);
    p.force_N = shifted.leftCols<2>();
    p.tip_torque_Nm = shifted.col(2);
  }
  // f_C = -reading; the reading carries +bias, so the recorded f_C is short by the bias.
  p.force_N.rowwise() += c.sensor_bias_N.transpose();
  for (Eigen::Index k = 0; k < n; ++k)
    p.torque_about_centre_Nm(k) =
        p.tip_torque_Nm(k) + p.lever_m(k, 0) * p.force_N(k, 1) - p.lever_m(k, 1) * p.force_N(k, 0);
  if (c.inertia_factor != 1) {
    if (!(c.inertia_factor > 0)) throw InputError("a data correction's inertia factor must be positive");
    p.shape.mass_kg *= c.inertia_factor;
    p.shape.inertia_kgm2 *= c.inertia_factor;
  }
  return p;
}

std::vector<Eigen::Index> samples_before_tip_moves(const SynchronisedPush& push, double travel_m) {
  std::vector<Eigen::Index> out;
  const Eigen::Index n = push.size();
  if (n == 0) return out;
  // The rest position: the median of the first few samples, robust to one glitch.
  const Eigen::Index head = std::min<Eigen::Index>(n, 5);
  Eigen::Vector2d rest;
  for (int c = 0; c < 2; ++c) {
    std::vector<double> v(push.tip_m.col(c).data(), push.tip_m.col(c).data() + head);
    std::nth_element(v.begin(), v.begin() + head / 2, v.end());
    rest(c) = v[head / 2];
  }
  for (Eigen::Index k = 0; k < n; ++k) {
    if ((push.tip_m.row(k).transpose() - rest).norm() > travel_m) break;
    out.push_back(k);
  }
  return out;
}

Eigen::Vector2d mean_force_N(const SynchronisedPush& push, const std::vector<Eigen::Index>& samples) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Index k : samples) mean += push.force_N.row(k).transpose();
  return mean / static_cast<double>(samples.size());
}

Outline::Closest rod_closest(const SynchronisedPush& push, const Outline& outline, Eigen::Index k) {
  const double c = std::cos(push.pose(k, 2)), s = std::sin(push.pose(k, 2));
  const Eigen::Vector2d d = push.tip_m.row(k).transpose() - push.pose.row(k).head<2>().transpose();
  return outline.closest(Eigen::Vector2d(c * d.x() + s * d.y(), -s * d.x() + c * d.y()));
}

namespace {

double rod_gap_m(const SynchronisedPush& push, const Outline& outline, Eigen::Index k) {
  return rod_closest(push, outline, k).signed_distance_m - kPusherRadius_m;
}

bool rest_force_points_into_contact(const SynchronisedPush& push, const Outline& outline,
                                    const std::vector<Eigen::Index>& rest, const Eigen::Vector2d& shared_N) {
  const Eigen::Vector2d mean = mean_force_N(push, rest) - shared_N;
  // The sensor's noise from first differences (the rest's spread about its mean would hold a preload's slow change).
  double sum2 = 0;
  for (std::size_t i = 1; i < rest.size(); ++i)
    sum2 += (push.force_N.row(rest[i]) - push.force_N.row(rest[i - 1])).squaredNorm();
  const double noise = std::sqrt(sum2 / std::max<double>(1.0, 4.0 * (static_cast<double>(rest.size()) - 1)));
  if (!(mean.norm() > kRestForceResolution * noise)) return false;
  const Eigen::Index k = rest[rest.size() / 2];
  const Eigen::Vector2d inward_body = -rod_closest(push, outline, k).normal;
  const double c = std::cos(push.pose(k, 2)), s = std::sin(push.pose(k, 2));
  const Eigen::Vector2d inward(c * inward_body.x() - s * inward_body.y(), s * inward_body.x() + c * inward_body.y());
  return mean.dot(inward) > std::cos(kRestContactCone_rad) * mean.norm();
}

}  // namespace

double measured_rod_gap_m(const SynchronisedPush& push, Eigen::Index k) {
  if (!push.shape.has_outline()) return std::numeric_limits<double>::quiet_NaN();
  return rod_gap_m(push, Outline(push.shape), k);
}

bool rest_force_points_into_contact(const SynchronisedPush& push, const Eigen::Vector2d& shared_rest_force_N) {
  const std::vector<Eigen::Index> rest = samples_before_tip_moves(push);
  if (rest.empty() || !push.shape.has_outline()) return false;
  const Outline outline(push.shape);
  return rest_force_points_into_contact(push, outline, rest, Eigen::Vector2d::Zero()) &&
         rest_force_points_into_contact(push, outline, rest, shared_rest_force_N);
}

Eigen::Vector2d shared_rest_force_N(const std::vector<SynchronisedPush>& pushes) {
  std::vector<double> x, y;
  for (const auto& push : pushes) {
    const std::vector<Eigen::Index> rest = samples_without_contact(push);
    if (rest.size() < kRestSamplesForZero) continue;
    const Eigen::Vector2d f = mean_force_N(push, rest);
    x.push_back(f.x());
    y.push_back(f.y());
  }
  if (x.empty()) return Eigen::Vector2d::Zero();
  return {median(x), median(y)};
}

std::vector<Eigen::Index> samples_without_contact(const SynchronisedPush& push,
                                                  const Eigen::Vector2d& shared_rest_force_N) {
  std::vector<Eigen::Index> rest = samples_before_tip_moves(push);
  if (rest.empty() || !push.shape.has_outline()) return rest;
  const Outline outline(push.shape);
  std::vector<double> gaps;
  gaps.reserve(rest.size());
  for (Eigen::Index k : rest) gaps.push_back(rod_gap_m(push, outline, k));
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  if (!(gaps[gaps.size() / 2] > kContactMargin_m)) return {};
  // Pressed only if the rest force points into the contact both as recorded and less the shared force: the shared
  // force clears a push whose bias pointed into its contact, and never presses one the push alone reads clear.
  if (rest_force_points_into_contact(push, outline, rest, Eigen::Vector2d::Zero()) &&
      rest_force_points_into_contact(push, outline, rest, shared_rest_force_N))
    return {};
  return rest;
}

std::optional<MeasuredZero> measured_sensor_zero(const DiagnosisPush& push) {
  const std::vector<Eigen::Index> rest = samples_without_contact(push.push, push.shared_rest_force_N);
  if (rest.size() < kRestSamplesForZero) return std::nullopt;
  const auto n = static_cast<double>(rest.size());
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Index k : rest) sum += push.push.force_N.row(k).transpose();
  const Eigen::Vector2d mean = sum / n;
  double sum2 = 0;
  for (const Eigen::Index k : rest) sum2 += (push.push.force_N.row(k).transpose() - mean).squaredNorm();
  // At rest f_C = 0, so the recorded f_C is -z.
  return MeasuredZero{-mean, sum2 / (2 * (n - 1))};
}

std::optional<Eigen::Vector2d> measured_sensor_zero_N(const DiagnosisPush& push) {
  const std::optional<MeasuredZero> z = measured_sensor_zero(push);
  if (!z) return std::nullopt;
  return z->zero_N;
}

}  // namespace pushpred
