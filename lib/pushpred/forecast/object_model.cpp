#include "pushpred/forecast/object_model.hpp"

#include <ceres/ceres.h>
#include <cstdio>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/reading/text_files.hpp"
#include "pushpred/runtime/parallel_batch.hpp"

namespace pushpred {
namespace {

// The descriptors' fixed scales (descriptor_distance2, trend_features): 20 degrees of push angle, 15 mm of contact
// point, a factor e of speed.
constexpr double kDescriptorAngle_rad = 20 * M_PI / 180, kDescriptorContact_m = 0.015, kDescriptorLogSpeed = 1.0;

/// Indices of at most `count` entries spread evenly over [0, n), always with the last.
std::vector<Eigen::Index> spread_indices(Eigen::Index n, int count) {
  std::vector<Eigen::Index> idx;
  if (n <= 0) return idx;
  const Eigen::Index m = std::min<Eigen::Index>(n, std::max(2, count));
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = m == 1 ? n - 1 : (k * (n - 1)) / (m - 1);
    if (idx.empty() || idx.back() != i) idx.push_back(i);
  }
  return idx;
}

/// The plan time at which the tip has covered `distance_m` (bisection on the monotone path).
double time_to_cover(const TipPlan& plan, double distance_m) {
  double lo = 0, hi = plan.end_time_s();
  Eigen::Vector2d p, v;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    plan.evaluate(mid, p, v);
    ((p - plan.start_m()).norm() < distance_m ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

bool outline_limit_surface(const ForecastObject& object) { return object.limit_surface == LimitSurfaceKind::Outline; }

struct TrajectoryResidual {
  const RecordedForecastCase* c = nullptr;
  Eigen::VectorXd times;
  Eigen::MatrixX3d truth;
  mutable Eigen::MatrixX3d poses;
  FitOptions options;
  double weight = 1;
  mutable int evaluations = 0;

  bool operator()(const double* log_theta, double* r) const {
    ForecastParameters p{std::exp(log_theta[0]), std::exp(log_theta[1]), std::exp(log_theta[2])};
    forecast_into(c->forecast_object, p, c->plan, c->start_pose, times, poses, options.settings);
    ++evaluations;
    for (Eigen::Index k = 0; k < times.size(); ++k) {
      r[3 * k] = weight * (poses(k, 0) - truth(k, 0)) / options.position_scale_m;
      r[3 * k + 1] = weight * (poses(k, 1) - truth(k, 1)) / options.position_scale_m;
      r[3 * k + 2] = weight * (poses(k, 2) - truth(k, 2)) / options.yaw_scale_rad;
    }
    return true;
  }
};

/// The covariance options of a trajectory fit's parameters (fit_push_parameters, fit_centre_of_friction): dense SVD
/// with the directions the residuals barely inform dropped (a pseudo-inverse), so a near-singular Jacobian still
/// gives standard errors rather than a failed computation.
ceres::Covariance::Options fit_covariance_options() {
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  options.null_space_rank = -1;
  options.min_reciprocal_condition_number = 1e-12;
  return options;
}

/// The log-parameters (ln mu_p, ln c, ln mu_s) a fit holds constant: mu_p (0) when FitOptions::held_pusher_friction
/// is set, c (1) on the outline's limit surface, which has none.
std::vector<int> held_indices(bool fixed_ratio, const FitOptions& options) {
  std::vector<int> held;
  if (options.held_pusher_friction > 0) held.push_back(0);
  if (fixed_ratio) held.push_back(1);
  return held;
}

bool is_held(const std::vector<int>& held, int k) { return std::find(held.begin(), held.end(), k) != held.end(); }

/// The rod friction mu_p's bounds in every push fit.
constexpr double kMinPusherFriction = 0.02, kMaxPusherFriction = 2.0;

/// A held rod friction (FitOptions::held_pusher_friction) inside the fits' bounds.
double held_pusher_friction(const FitOptions& options) {
  return std::clamp(options.held_pusher_friction, kMinPusherFriction, kMaxPusherFriction);
}

/// The covariance of a push's log-parameters theta = (ln mu_p, ln c, ln mu_s), row-major 3 x 3, into `out`. With
/// some held (`held`, a SubsetManifold of them: c on the outline's limit surface, mu_p when held) it is read in the
/// tangent space of the others and the held ones' rows and columns stay zero: Ceres' lift to the ambient space
/// multiplies by the manifold's Jacobian for nothing here, and under AddressSanitizer that lift's temporary matrices
/// were freed as not allocated (Debian's Ceres 2.1).
bool theta_covariance(const ceres::Covariance& covariance, const double* theta, const std::vector<int>& held,
                      double* out) {
  std::fill(out, out + 9, 0.0);
  if (held.empty()) return covariance.GetCovarianceBlock(theta, theta, out);
  std::vector<int> free;
  for (int k = 0; k < 3; ++k)
    if (!is_held(held, k)) free.push_back(k);
  const int m = static_cast<int>(free.size());
  double tangent[9] = {0};
  if (!covariance.GetCovarianceBlockInTangentSpace(theta, theta, tangent)) return false;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) out[3 * free[i] + free[j]] = tangent[m * i + j];
  return true;
}

/// (theta_i - centre) / width: a Gaussian prior on one log-parameter.
struct LogPrior {
  int index = 0;
  double centre = 0, width = 1;
  template <class T>
  bool operator()(const T* theta, T* r) const {
    r[0] = (theta[index] - T(centre)) / T(width);
    return true;
  }
};

double weighted_quantile(std::vector<std::pair<double, double>> value_weight, double q) {
  if (value_weight.empty()) return std::nan("");
  std::sort(value_weight.begin(), value_weight.end());
  double total = 0;
  for (const auto& vw : value_weight) total += vw.second;
  double acc = 0;
  for (const auto& vw : value_weight) {
    acc += vw.second;
    if (acc >= q * total) return vw.first;
  }
  return value_weight.back().first;
}

/// The bandwidth argument of member_weights that stands for the averaged weighting (ObjectModel::similarity_averaged).
constexpr double kAveragedBandwidth = -1;
double weighting_bandwidth(const ObjectModel& model) {
  return model.similarity_averaged ? kAveragedBandwidth : model.similarity_bandwidth;
}

/// The weights of `members` for a plan described by `d` under bandwidth h (all 1 for h = 0; members far beyond the
/// bandwidth get 0 so that they cost no forecast), or for h = kAveragedBandwidth the mean over kAveragedBandwidths of
/// the weights under each, normalised to sum 1.
void member_weights(const std::vector<const PushFit*>& members, double h, const PushDescriptor& d,
                    std::vector<double>& w) {
  if (h == kAveragedBandwidth) {
    thread_local std::vector<double> part;
    w.assign(members.size(), 0.0);
    for (const double each : kAveragedBandwidths) {
      member_weights(members, each, d, part);
      double total = 0;
      for (const double x : part) total += x;
      if (!(total > 0)) continue;
      for (std::size_t i = 0; i < members.size(); ++i)
        w[i] += part[i] / (total * static_cast<double>(kAveragedBandwidths.size()));
    }
    return;
  }
  w.assign(members.size(), 1.0);
  if (!(h > 0)) return;
  double best = 0;
  for (std::size_t i = 0; i < members.size(); ++i) {
    w[i] = std::exp(-0.5 * descriptor_distance2(members[i]->descriptor, d) / (h * h));
    best = std::max(best, w[i]);
  }
  // No member near: all alike, as for h = 0.
  if (!(best > 1e-6)) w.assign(members.size(), 1.0);
  for (double& x : w)
    if (x < 1e-3 * best) x = 0;
}

ForecastParameters weighted_median_parameters(const std::vector<ForecastParameters>& members,
                                              const std::vector<double>& w) {
  thread_local std::vector<std::pair<double, double>> value_weight;
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    value_weight.clear();
    for (std::size_t m = 0; m < members.size(); ++m)
      if (w[m] > 0) value_weight.emplace_back(std::log(members[m].vector()(i)), w[m]);
    out(i) = std::exp(weighted_median(value_weight));
  }
  return ForecastParameters::from_vector(out);
}

/// `member`'s parameters moved along `trend` from where it pushed to where the plan described by `d` pushes.
ForecastParameters parameters_along_trend(const PushFit& member, const ParameterTrend& trend, const PushDescriptor& d) {
  if (!trend.active()) return member.parameters;
  const Eigen::Vector3d shift = (trend.slope * (trend_features(d) - trend_features(member.descriptor)))
                                    .cwiseMax(-trend.max_shift_log)
                                    .cwiseMin(trend.max_shift_log);
  return ForecastParameters::from_vector(member.parameters.vector().cwiseProduct(shift.array().exp().matrix()));
}

/// The trend of `members`' log-parameters over their trend_features: ridge regression about their means.
ParameterTrend fit_trend(const std::vector<const PushFit*>& members, double ridge) {
  ParameterTrend trend;
  if (!(ridge > 0) || members.size() < 3) return trend;
  const Eigen::Index n = static_cast<Eigen::Index>(members.size());
  Eigen::MatrixXd F(n, kTrendFeatures);
  Eigen::MatrixXd Y(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const PushFit& f = *members[static_cast<std::size_t>(i)];
    F.row(i) = trend_features(f.descriptor).transpose();
    Y.row(i) = f.parameters.vector().array().log().matrix().transpose();
  }
  F.rowwise() -= F.colwise().mean();
  Y.rowwise() -= Y.colwise().mean();
  const double nd = static_cast<double>(n);
  const Eigen::Matrix<double, kTrendFeatures, kTrendFeatures> A =
      F.transpose() * F / nd + ridge * Eigen::Matrix<double, kTrendFeatures, kTrendFeatures>::Identity();
  trend.slope = A.ldlt().solve(F.transpose() * Y / nd).transpose();
  trend.ridge = ridge;
  return trend;
}

/// The ensemble median's stopping step, 0.1 micrometre: where the members lie near a line the sum of distances is
/// nearly flat along it and Weiszfeld's steps shrink slowly; a hundredth of the study's 0.01 mm.
constexpr double kMedianTolerance_m = 1e-7;

/// The central forecast of a plan from `members` (weighted by bandwidth h, moved along `trend`; CentralForecast) and,
/// when `spread` is set, the members' weighted RMS spread about it: the core of forecast_distribution_into and of the
/// calibration. The ensemble's median keeps the members' trajectories in `work`.
void central_and_spread(const ForecastObject& object, const std::vector<const PushFit*>& members, double h,
                        const ParameterTrend& trend, const TipPlan& plan, const Eigen::Vector3d& pose0,
                        const Eigen::VectorXd& times, const ForecastSettings& settings,
                        Eigen::Ref<Eigen::MatrixX3d> mean, Eigen::Ref<Eigen::VectorXd> pos_spread,
                        Eigen::Ref<Eigen::VectorXd> yaw_spread, ForecastWorkspace& work, ForecastRun& run,
                        CentralForecast mode, bool spread = true) {
  thread_local std::vector<double> w;
  thread_local std::vector<ForecastParameters> parameters;
  const PushDescriptor d = describe_push(object, plan, pose0);
  member_weights(members, h, d, w);
  parameters.resize(members.size());
  for (std::size_t m = 0; m < members.size(); ++m) parameters[m] = parameters_along_trend(*members[m], trend, d);
  run = forecast_into(object, weighted_median_parameters(parameters, w), plan, pose0, times, mean, settings);
  if (!spread && mode == CentralForecast::MedianParameters) return;
  const Eigen::Index n = times.size();
  Eigen::MatrixX3d& member = work.member;
  if (member.rows() != n) member.resize(n, 3);
  if (mode == CentralForecast::EnsembleMedian) {
    // Every member's trajectory kept (nothing allocated after the first call of a size), then at each time the
    // medians and the spread about them.
    const Eigen::Index capacity = static_cast<Eigen::Index>(members.size());
    if (work.ensemble_xy.rows() != 2 * capacity || work.ensemble_xy.cols() != n)
      work.ensemble_xy.resize(2 * capacity, n);
    if (work.ensemble_yaw.rows() != capacity || work.ensemble_yaw.cols() != n) work.ensemble_yaw.resize(capacity, n);
    if (work.weights.size() != capacity) work.weights.resize(capacity);
    if (work.value_weight.size() < members.size()) work.value_weight.resize(members.size());
    Eigen::Index count = 0;
    double total = 0;
    for (std::size_t m = 0; m < members.size(); ++m) {
      if (!(w[m] > 0)) continue;
      forecast_into(object, parameters[m], plan, pose0, times, member, settings);
      work.ensemble_xy.middleRows(2 * count, 2) = member.leftCols<2>().transpose();
      work.ensemble_yaw.row(count) = member.col(2).transpose();
      work.weights(count) = w[m];
      total += w[m];
      ++count;
    }
    if (count == 0 || !(total > 0)) {
      if (spread) {
        pos_spread.setZero();
        yaw_spread.setZero();
      }
      return;
    }
    const auto weights = work.weights.head(count);
    work.value_weight.resize(static_cast<std::size_t>(count));  // within its capacity: no allocation
    // Each time's position median from the previous one moved as the ensemble's mean moved (the trajectories are
    // smooth, so Weiszfeld's iteration starts next to it).
    Eigen::Vector2d previous_median, previous_mean;
    for (Eigen::Index k = 0; k < n; ++k) {
      const Eigen::Map<const Eigen::Matrix2Xd> xy(work.ensemble_xy.col(k).data(), 2, count);
      const Eigen::Vector2d ensemble_mean = xy * weights / total;
      const Eigen::Vector2d start =
          k > 0 ? Eigen::Vector2d(previous_median + ensemble_mean - previous_mean) : ensemble_mean;
      previous_median = weighted_geometric_median(xy, weights, kMedianTolerance_m, 200, &start);
      previous_mean = ensemble_mean;
      mean.row(k).head<2>() = previous_median.transpose();
      for (Eigen::Index a = 0; a < count; ++a)
        work.value_weight[static_cast<std::size_t>(a)] = {work.ensemble_yaw(a, k), weights(a)};
      mean(k, 2) = weighted_median(work.value_weight);
      if (!spread) continue;
      double pos2 = 0, yaw2 = 0;
      for (Eigen::Index a = 0; a < count; ++a) {
        pos2 += weights(a) * (xy.col(a) - mean.row(k).head<2>().transpose()).squaredNorm();
        yaw2 += weights(a) * (work.ensemble_yaw(a, k) - mean(k, 2)) * (work.ensemble_yaw(a, k) - mean(k, 2));
      }
      pos_spread(k) = std::sqrt(pos2 / total);
      yaw_spread(k) = std::sqrt(yaw2 / total);
    }
    return;
  }
  const bool ensemble_mean = mode == CentralForecast::EnsembleMean;
  thread_local Eigen::MatrixX3d sum;
  thread_local Eigen::VectorXd sum_pos2, sum_yaw2;
  if (ensemble_mean) {
    sum.setZero(n, 3);
    sum_pos2.setZero(n);
    sum_yaw2.setZero(n);
  }
  pos_spread.setZero();
  yaw_spread.setZero();
  double total = 0;
  for (std::size_t m = 0; m < members.size(); ++m) {
    if (!(w[m] > 0)) continue;
    total += w[m];
    forecast_into(object, parameters[m], plan, pose0, times, member, settings);
    if (ensemble_mean) {
      sum += w[m] * member;
      sum_pos2 += w[m] * member.leftCols<2>().rowwise().squaredNorm();
      sum_yaw2 += w[m] * member.col(2).cwiseAbs2();
      continue;
    }
    for (Eigen::Index k = 0; k < n; ++k) {
      pos_spread(k) += w[m] * (member.row(k).head<2>() - mean.row(k).head<2>()).squaredNorm();
      yaw_spread(k) += w[m] * (member(k, 2) - mean(k, 2)) * (member(k, 2) - mean(k, 2));
    }
  }
  if (!(total > 0)) return;
  if (ensemble_mean) {
    mean = sum / total;
    pos_spread = (sum_pos2 / total - mean.leftCols<2>().rowwise().squaredNorm()).cwiseMax(0.0).cwiseSqrt();
    yaw_spread = (sum_yaw2 / total - mean.col(2).cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
    return;
  }
  pos_spread = (pos_spread / total).cwiseSqrt();
  yaw_spread = (yaw_spread / total).cwiseSqrt();
}

/// The plan's unit axis (from its start to its end; for a plan that ends where it starts, its direction).
Eigen::Vector2d plan_axis(const TipPlan& plan) {
  const Eigen::Vector2d span = plan.end_m() - plan.start_m();
  const double length = span.norm();
  return length > 1e-9 ? Eigen::Vector2d(span / length) : plan.direction().normalized();
}

/// The tip's progress along the plan at t: its advance along plan_axis over the plan's, 0 at the start, 1 from the
/// plan's end on (the slide included).
double plan_progress(const TipPlan& plan, double t_s) {
  const Eigen::Vector2d span = plan.end_m() - plan.start_m();
  const double length2 = span.squaredNorm();
  if (!(length2 > 1e-18)) return t_s >= plan.end_time_s() ? 1.0 : 0.0;
  Eigen::Vector2d position, velocity;
  plan.evaluate(std::min(t_s, plan.end_time_s()), position, velocity);
  return std::clamp((position - plan.start_m()).dot(span) / length2, 0.0, 1.0);
}

/// A forecast pose's error (predicted minus recorded) in the plan's frame: along plan_axis [m], across it
/// (counter-clockwise) [m], yaw [rad].
Eigen::Vector3d plan_frame_error(const TipPlan& plan, const Eigen::Vector3d& predicted,
                                 const Eigen::Vector3d& recorded) {
  const Eigen::Vector2d u = plan_axis(plan);
  const Eigen::Vector2d e = predicted.head<2>() - recorded.head<2>();
  return {u.dot(e), u.x() * e.y() - u.y() * e.x(), predicted(2) - recorded(2)};
}

/// The residual correction's shift in the plan's frame: the members' leave-one-out final errors' weighted mean under
/// weights `w`, shrunk by n_eff / (n_eff + k).
Eigen::Vector3d residual_shift(const std::vector<const PushFit*>& members, const std::vector<double>& w, double k) {
  double total = 0, total2 = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t m = 0; m < members.size(); ++m) {
    if (!(w[m] > 0)) continue;
    total += w[m];
    total2 += w[m] * w[m];
    sum += w[m] * members[m]->loo_final_error;
  }
  if (!(total > 0)) return Eigen::Vector3d::Zero();
  const double n_eff = total * total / total2;
  return sum / total * (n_eff / (n_eff + std::max(0.0, k)));
}

/// Subtracts `shift` (plan frame, residual_shift) from the central forecast `mean` at `times`, scaled by the tip's
/// progress along the plan.
void apply_residual_shift(const Eigen::Vector3d& shift, const TipPlan& plan, const Eigen::VectorXd& times,
                          Eigen::Ref<Eigen::MatrixX3d> mean) {
  const Eigen::Vector2d u = plan_axis(plan);
  const Eigen::Vector2d world = shift(0) * u + shift(1) * Eigen::Vector2d(-u.y(), u.x());
  for (Eigen::Index k = 0; k < times.size(); ++k) {
    const double f = plan_progress(plan, times(k));
    mean(k, 0) -= f * world.x();
    mean(k, 1) -= f * world.y();
    mean(k, 2) -= f * shift(2);
  }
}

/// The recorded times of a case used for scoring and calibration: at most 60, evenly spread.
Eigen::VectorXd scoring_times(const RecordedForecastCase& c, std::vector<Eigen::Index>& idx) {
  idx = spread_indices(c.times_s.size(), 60);
  Eigen::VectorXd times(static_cast<Eigen::Index>(idx.size()));
  for (std::size_t k = 0; k < idx.size(); ++k) times(static_cast<Eigen::Index>(k)) = c.times_s(idx[k]);
  return times;
}

double number_at(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key) || !j.at(key).is_number())
    throw InputError(where + ": '" + key + "' must be a number");
  const double v = j.at(key).get<double>();
  if (!std::isfinite(v)) throw InputError(where + ": '" + key + "' must be finite");
  return v;
}

}  // namespace

ForecastOutline read_outline_csv(const std::filesystem::path& path, const std::string& description) {
  std::vector<Eigen::Vector2d> v = read_outline_csv_vertices(path);
  try {
    return ForecastOutline::polygon(std::move(v), description);
  } catch (const InputError& e) {
    throw InputError(about(path.string(), e.what()));
  }
}

ForecastObject dataset_forecast_object(const ShapeInfo& shape, const std::filesystem::path& data_folder) {
  ForecastObject o;
  o.name = shape.name;
  o.mass_kg = shape.mass_kg;
  o.inertia_kgm2 = shape.inertia_kgm2;
  o.centre_of_friction_m = shape.centroid_m;
  if (shape.has_outline()) {
    o.outline = std::make_shared<const ForecastOutline>(ForecastOutline::of_shape(shape));
  } else if (shape.name == "butter") {
    if (data_folder.empty())
      throw InputError("butter's outline is read from the data folder's butter_outline.csv, and no data folder was "
                       "found: give --data DIR or set PUSHPRED_DATA");
    o.outline = std::make_shared<const ForecastOutline>(
        read_outline_csv(data_folder / "butter_outline.csv", "data folder: butter_outline.csv"));
  } else {
    throw InputError("shape '" + shape.name + "' has no outline: give one (a polygon file, a circle or an ellipse)");
  }
  o.validate();
  return o;
}

RecordedForecastCase recorded_forecast_case(const SynchronisedPush& push, const ForecastObject& object,
                                            double push_length_m) {
  if (push.push.shape.empty()) throw InputError(about(push.source, "the file name carries no push parameters"));
  if (!(push.push.speed_m_s > 0))
    throw InputError(about(push.source, "not a constant-speed push (the forecast's study plans those only)"));
  RecordedForecastCase c;
  c.name = std::filesystem::path(push.source).stem().string();
  c.object = push.push.shape;
  c.surface = push.push.surface;
  c.forecast_object = object;
  // When the tip starts moving: it first leaves its rest position by 0.5 mm, less the plan's time for 0.5 mm.
  constexpr double kMoved_m = 5e-4;
  const Eigen::Vector2d rest = push.tip_m.row(0).transpose();
  Eigen::Index j = 1;
  while (j < push.size() && (push.tip_m.row(j).transpose() - rest).norm() < kMoved_m) ++j;
  if (j >= push.size()) throw InputError(about(push.source, "the tip never moves 0.5 mm"));
  const double d0 = (push.tip_m.row(j - 1).transpose() - rest).norm(),
               d1 = (push.tip_m.row(j).transpose() - rest).norm();
  const double t_cross = push.t_s(j - 1) + (kMoved_m - d0) / std::max(d1 - d0, 1e-12) * (push.t_s(j) - push.t_s(j - 1));
  const TipPlan probe =
      TipPlan::straight(Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitX(), push.push.speed_m_s, push_length_m);
  c.start_time_s = std::max(0.0, t_cross - time_to_cover(probe, kMoved_m));
  const Eigen::Index i0 = push.index_at(c.start_time_s);
  c.start_pose = push.pose.row(i0).transpose();
  const Eigen::Vector2d tip0 = push.tip_m.row(i0).transpose();
  const Eigen::Rotation2Dd R(c.start_pose(2));
  Eigen::Vector2d direction_body;
  const int side = static_cast<int>(std::lround(push.push.contact_side));
  if (push.shape.has_outline()) {
    direction_body = dataset_push_direction_body(push.shape, side, push.push.contact_position, push.push.angle_rad);
    c.direction_source = "inward normal at the file name's side and position, turned by its angle";
  } else {
    direction_body = perimeter_push_direction_body(*object.outline, push.push.contact_position, push.push.angle_rad);
    c.direction_source = "inward normal at the file name's position along the perimeter, turned by its angle";
  }
  c.plan = TipPlan::straight(tip0, R * direction_body, push.push.speed_m_s, push_length_m);
  const Eigen::Index n = push.size() - i0;
  c.times_s = push.t_s.tail(n).array() - c.start_time_s;
  c.truth = push.pose.bottomRows(n);
  c.measured_pusher_friction = measured_pusher_friction(push, c);
  c.identified_torque_ratio = identify_torque_ratio(push, c);
  return c;
}

RodContactSamples::RodContactSamples(const SynchronisedPush& push, const RecordedForecastCase& c)
    : push_(push),
      outline_(*c.forecast_object.outline),
      direction_(c.plan.direction()),
      tip0_(push.tip_m.row(push.size() - c.times_s.size()).transpose()),
      length_m_(c.plan.length_m()),
      touch_m_(ForecastSettings{}.rod_radius_m + kTouch_m) {}

std::optional<RodContactSamples::Sample> RodContactSamples::at(Eigen::Index j) {
  Sample s;
  s.progress = (push_.tip_m.row(j).transpose() - tip0_).dot(direction_) / length_m_;
  if (s.progress < kFrom || s.progress > kTo) return std::nullopt;
  const Eigen::Vector3d pose = push_.pose.row(j).transpose();
  s.R = Eigen::Rotation2Dd(pose(2)).toRotationMatrix();
  const Eigen::Vector2d tip = push_.tip_m.row(j).transpose();
  s.closest = outline_.closest(s.R.transpose() * (tip - pose.head<2>()), hint_);
  if (s.closest.signed_distance_m > touch_m_) return std::nullopt;
  return s;
}

double measured_pusher_friction(const SynchronisedPush& push, const RecordedForecastCase& c) {
  constexpr double kMinNormal_N = 0.5, kSlipShare = 0.15;
  constexpr std::size_t kMinSamples = 10;
  const Eigen::Index n = c.times_s.size(), i0 = push.size() - n;
  if (n < 3 || i0 < 0 || !c.forecast_object.outline) return std::numeric_limits<double>::quiet_NaN();
  RodContactSamples samples(push, c);
  const double slip_min = kSlipShare * c.plan.speed_m_s();
  std::vector<double> ratios;
  for (Eigen::Index k = 1; k + 1 < n; ++k) {
    const Eigen::Index j = i0 + k;
    const std::optional<RodContactSamples::Sample> s = samples.at(j);
    if (!s) continue;
    const Eigen::Matrix2d& R = s->R;
    const Outline::Closest& cl = s->closest;
    const Eigen::Vector2d normal = -(R * cl.normal);  // into the object
    const Eigen::Vector2d tangent(-normal.y(), normal.x());
    const Eigen::Vector2d force = push.force_N.row(j).transpose();  // on the object
    const double fn = force.dot(normal);
    if (!(fn >= kMinNormal_N)) continue;
    const double dt = push.t_s(j + 1) - push.t_s(j - 1);
    if (!(dt > 0)) continue;
    const Eigen::Vector2d tip_velocity = (push.tip_m.row(j + 1) - push.tip_m.row(j - 1)).transpose() / dt;
    const Eigen::Vector2d velocity = (push.pose.row(j + 1).head<2>() - push.pose.row(j - 1).head<2>()).transpose() / dt;
    const double omega = (push.pose(j + 1, 2) - push.pose(j - 1, 2)) / dt;
    const Eigen::Vector2d arm = R * cl.point_m;
    const Eigen::Vector2d point_velocity = velocity + omega * Eigen::Vector2d(-arm.y(), arm.x());
    if (std::abs((tip_velocity - point_velocity).dot(tangent)) <= slip_min) continue;
    ratios.push_back(std::abs(force.dot(tangent)) / fn);
  }
  if (ratios.size() < kMinSamples) return std::numeric_limits<double>::quiet_NaN();
  return median(ratios);
}

namespace {

/// The errors of `fit`'s forecast of `c` (with `object`) against its whole recording.
void record_fit_errors(const RecordedForecastCase& c, const ForecastObject& object, const ForecastSettings& settings,
                       PushFit& fit) {
  const Eigen::MatrixX3d poses = forecast_poses(object, fit.parameters, c.plan, c.start_pose, c.times_s, settings);
  const Eigen::Index n = c.times_s.size();
  fit.rms_position_m = std::sqrt((poses.leftCols<2>() - c.truth.leftCols<2>()).rowwise().squaredNorm().mean());
  fit.rms_yaw_rad = std::sqrt((poses.col(2) - c.truth.col(2)).array().square().mean());
  fit.final_position_m = (poses.row(n - 1).head<2>() - c.truth.row(n - 1).head<2>()).norm();
  fit.final_yaw_rad = std::abs(poses(n - 1, 2) - c.truth(n - 1, 2));
}

}  // namespace

PushFit fit_push_parameters(const RecordedForecastCase& c, const FitOptions& options) {
  c.forecast_object.validate();
  const std::vector<Eigen::Index> idx = spread_indices(c.times_s.size(), options.residual_times);
  auto* residual = new TrajectoryResidual;
  residual->c = &c;
  residual->options = options;
  residual->times.resize(static_cast<Eigen::Index>(idx.size()));
  residual->truth.resize(static_cast<Eigen::Index>(idx.size()), 3);
  for (std::size_t k = 0; k < idx.size(); ++k) {
    residual->times(static_cast<Eigen::Index>(k)) = c.times_s(idx[k]);
    residual->truth.row(static_cast<Eigen::Index>(k)) = c.truth.row(idx[k]);
  }
  residual->poses.resize(residual->times.size(), 3);
  const int m = static_cast<int>(3 * idx.size());
  const bool fixed_ratio = outline_limit_surface(c.forecast_object);
  const double c_uniform =
      fixed_ratio ? c.forecast_object.pressure_surface->torque_ratio_m()
                  : c.forecast_object.outline->uniform_pressure_torque_ratio_m(c.forecast_object.centre_of_friction_m);
  // A coarse grid first: the trajectory error has several valleys (stick against slide).
  std::vector<double> r(static_cast<std::size_t>(m));
  const std::vector<int> held = held_indices(fixed_ratio, options);
  const double held_mu_p = held_pusher_friction(options);
  double theta[3] = {std::log(0.25), std::log(c_uniform), std::log(0.4)};
  double best = std::numeric_limits<double>::infinity();
  const std::vector<double> ratios =
      fixed_ratio ? std::vector<double>{1.0} : std::vector<double>{0.35, 0.5, 0.65, 0.8, 0.95, 1.15, 1.4, 1.8};
  const std::vector<double> frictions = is_held(held, 0)
                                            ? std::vector<double>{held_mu_p}
                                            : std::vector<double>{0.05, 0.1, 0.18, 0.28, 0.4, 0.55, 0.75, 1.0, 1.4};
  for (double mu_p : frictions)
    for (double ratio : ratios)
      for (double mu_s : {0.25, 0.5}) {
        const double t[3] = {std::log(mu_p), std::log(ratio * c_uniform), std::log(mu_s)};
        (*residual)(t, r.data());
        double cost = 0;
        for (double x : r) cost += x * x;
        if (cost < best) {
          best = cost;
          std::copy(t, t + 3, theta);
        }
      }
  ceres::NumericDiffOptions diff;
  diff.relative_step_size = 1e-2;  // the fixed-step forecast is piecewise smooth: a step that spans its kinks
  auto* cost = new ceres::NumericDiffCostFunction<TrajectoryResidual, ceres::CENTRAL, ceres::DYNAMIC, 3>(
      residual, ceres::TAKE_OWNERSHIP, m, diff);
  ceres::Problem problem;
  problem.AddResidualBlock(cost, new ceres::HuberLoss(3.0), theta);
  if (options.prior_width_log > 0) {
    const double centre[3] = {std::log(0.25), std::log(c_uniform), std::log(0.4)};
    for (int i = 0; i < 3; ++i)
      if (!is_held(held, i))
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<LogPrior, 1, 3>(new LogPrior{i, centre[i], options.prior_width_log}),
            nullptr, theta);
  }
  const double lower[3] = {std::log(kMinPusherFriction), std::log(0.15 * c_uniform), std::log(0.05)};
  const double upper[3] = {std::log(kMaxPusherFriction), std::log(2.5 * c_uniform), std::log(1.5)};
  for (int i = 0; i < 3; ++i) {
    theta[i] = std::clamp(theta[i], lower[i], upper[i]);
    if (is_held(held, i)) continue;
    problem.SetParameterLowerBound(theta, i, lower[i]);
    problem.SetParameterUpperBound(theta, i, upper[i]);
  }
  // The pressure's limit surface has no ratio c: it is held at the surface's own (unused by the forecast); a held
  // rod friction stays where it was put.
  if (!held.empty()) problem.SetManifold(theta, new ceres::SubsetManifold(3, held));
  ceres::Solver::Options solver;
  solver.max_num_iterations = 40;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  PushFit fit;
  fit.name = c.name;
  fit.descriptor = describe_push(c.forecast_object, c.plan, c.start_pose);
  fit.parameters = ForecastParameters{std::exp(theta[0]), std::exp(theta[1]), std::exp(theta[2])};
  // Standard errors: Ceres' covariance of the logarithms, scaled by the residuals' own variance.
  ceres::Covariance covariance(fit_covariance_options());
  std::vector<std::pair<const double*, const double*>> blocks{{theta, theta}};
  double cov[9] = {0};
  if (covariance.Compute(blocks, &problem) && theta_covariance(covariance, theta, held, cov)) {
    const double dof = std::max(1, m - 3);
    const double variance = 2 * summary.final_cost / dof;
    for (int i = 0; i < 3; ++i)
      fit.standard_error(i) = fit.parameters.vector()(i) * std::sqrt(std::max(0.0, cov[4 * i] * variance));
  }
  record_fit_errors(c, c.forecast_object, options.settings, fit);
  fit.evaluations = residual->evaluations;
  return fit;
}

namespace {

/// The pressure's limit surfaces fitted for the last few (centre of friction, rim weight) pairs, shared by the pushes
/// of one joint fit: its residuals move the pressure to the same few shapes (the iterate and its difference steps,
/// seven a Jacobian) push after push, and a surface costs a fit over the footprint (600 twists over some 300
/// elements). Not thread-safe: one per Ceres problem, evaluated on one thread.
class PressureSurfaceCache {
 public:
  /// False (the object unchanged) where no pressure of this shape is centred at `centre`.
  bool move(ForecastObject& object, const Eigen::Vector2d& centre, double rim_weight) {
    if (object.limit_surface != LimitSurfaceKind::Outline) {
      object.centre_of_friction_m = centre;
      return true;
    }
    if (object.centre_of_friction_m == centre && object.pressure_rim_weight == rim_weight && object.pressure_surface)
      return true;
    for (const Entry& e : entries_)
      if (e.centre == centre && e.rim_weight == rim_weight) {
        if (!e.surface) return false;
        object.centre_of_friction_m = centre;
        object.pressure_rim_weight = rim_weight;
        object.pressure_surface = e.surface;
        return true;
      }
    std::shared_ptr<const PolynomialLimitSurface> surface;
    try {
      ForecastObject moved = object;
      set_pressure_shape(moved, centre, rim_weight);
      surface = moved.pressure_surface;
      object = std::move(moved);
    } catch (const InputError&) {
    }
    entries_.push_back({centre, rim_weight, surface});
    if (entries_.size() > 8) entries_.erase(entries_.begin());
    return surface != nullptr;
  }

 private:
  struct Entry {
    Eigen::Vector2d centre;
    double rim_weight;
    std::shared_ptr<const PolynomialLimitSurface> surface;
  };
  std::vector<Entry> entries_;
};

/// One push's trajectory residuals (as TrajectoryResidual's) as a function of its log-parameters (block 0, size 3),
/// the centre of friction its object shares with other pushes (block 1, size 2, body frame [m]) and the pressure's rim
/// weight it shares with them (block 2, size 1; used by the outline's limit surface only). Central differences with a
/// step suited to each block: 0.02 in the logarithms (about fit_push_parameters' relative step), 0.2 mm for the
/// centre, 0.02 for the rim weight; all span the kinks of the piecewise-smooth fixed-step forecast. A held block
/// (Ceres' constant block) asks for no Jacobian and costs no forecast.
class SharedCentreResidual final : public ceres::CostFunction {
 public:
  SharedCentreResidual(const RecordedForecastCase& c, const ForecastObject& object, const FitOptions& options,
                       PressureSurfaceCache& surfaces)
      : case_(c), object_(object), options_(options), surfaces_(surfaces) {
    const std::vector<Eigen::Index> idx = spread_indices(c.times_s.size(), options.residual_times);
    const Eigen::Index n = static_cast<Eigen::Index>(idx.size());
    times_.resize(n);
    truth_.resize(n, 3);
    for (Eigen::Index k = 0; k < n; ++k) {
      times_(k) = c.times_s(idx[static_cast<std::size_t>(k)]);
      truth_.row(k) = c.truth.row(idx[static_cast<std::size_t>(k)]);
    }
    poses_.resize(n, 3);
    plus_.resize(static_cast<std::size_t>(3 * n));
    minus_.resize(static_cast<std::size_t>(3 * n));
    set_num_residuals(static_cast<int>(3 * n));
    mutable_parameter_block_sizes()->push_back(3);
    mutable_parameter_block_sizes()->push_back(2);
    mutable_parameter_block_sizes()->push_back(1);
  }

  bool Evaluate(double const* const* x, double* r, double** jacobians) const override {
    double block[3][3] = {{x[0][0], x[0][1], x[0][2]}, {x[1][0], x[1][1], 0}, {x[2][0], 0, 0}};
    // A centre so far off the outline that no planar pressure puts it there has no limit surface: Ceres takes the
    // step as infeasible and shortens it.
    if (!residuals(block[0], block[1], block[2][0], r)) return false;
    if (!jacobians) return true;
    const int m = num_residuals();
    for (int b = 0; b < 3; ++b) {
      if (!jacobians[b]) continue;
      const int size = b == 0 ? 3 : (b == 1 ? 2 : 1);
      const double step = b == 0 ? kLogStep : (b == 1 ? kCentreStep_m : kRimWeightStep);
      for (int j = 0; j < size; ++j) {
        const double keep = block[b][j];
        block[b][j] = keep + step;
        const bool plus = residuals(block[0], block[1], block[2][0], plus_.data());
        block[b][j] = keep - step;
        const bool minus = residuals(block[0], block[1], block[2][0], minus_.data());
        block[b][j] = keep;
        if (!plus || !minus) return false;
        for (int i = 0; i < m; ++i)
          jacobians[b][i * size + j] =
              (plus_[static_cast<std::size_t>(i)] - minus_[static_cast<std::size_t>(i)]) / (2 * step);
      }
    }
    return true;
  }

 private:
  static constexpr double kLogStep = 0.02, kCentreStep_m = 2e-4;

 public:
  static constexpr double kRimWeightStep = 0.02;

 private:
  bool residuals(const double* log_theta, const double* centre_m, double rim_weight, double* r) const {
    if (!surfaces_.move(object_, Eigen::Vector2d(centre_m[0], centre_m[1]), rim_weight)) return false;
    const ForecastParameters p{std::exp(log_theta[0]), std::exp(log_theta[1]), std::exp(log_theta[2])};
    forecast_into(object_, p, case_.plan, case_.start_pose, times_, poses_, options_.settings);
    for (Eigen::Index k = 0; k < times_.size(); ++k) {
      r[3 * k] = (poses_(k, 0) - truth_(k, 0)) / options_.position_scale_m;
      r[3 * k + 1] = (poses_(k, 1) - truth_(k, 1)) / options_.position_scale_m;
      r[3 * k + 2] = (poses_(k, 2) - truth_(k, 2)) / options_.yaw_scale_rad;
    }
    return true;
  }

  const RecordedForecastCase& case_;
  mutable ForecastObject object_;
  FitOptions options_;
  Eigen::VectorXd times_;
  Eigen::MatrixX3d truth_;
  mutable Eigen::MatrixX3d poses_;
  mutable std::vector<double> plus_, minus_;
  PressureSurfaceCache& surfaces_;
};

/// (w - prior) / sd: the pressure's rim weight's Gaussian prior.
struct RimWeightPrior {
  double prior = 0, sd = 1;
  template <class T>
  bool operator()(const T* w, T* r) const {
    r[0] = (w[0] - T(prior)) / T(sd);
    return true;
  }
};

/// (centre - prior) / sd per axis: the centre of friction's Gaussian prior.
struct CentrePrior {
  Eigen::Vector2d prior_m;
  double sd_m = 1;
  template <class T>
  bool operator()(const T* centre, T* r) const {
    r[0] = (centre[0] - T(prior_m.x())) / T(sd_m);
    r[1] = (centre[1] - T(prior_m.y())) / T(sd_m);
    return true;
  }
};

}  // namespace

CentreOfFrictionFit fit_centre_of_friction(const ForecastObject& object, const std::vector<RecordedForecastCase>& cases,
                                           const std::vector<PushFit>& fits, const CentreOfFrictionOptions& options) {
  if (cases.empty()) throw InputError("centre of friction: no push to fit it from");
  if (cases.size() != fits.size()) throw std::logic_error("fit_centre_of_friction: one fit per case");
  object.validate();
  const FitOptions& fit_options = options.fit;
  const Eigen::Vector2d start = object.centre_of_friction_m;
  const bool fixed_ratio = outline_limit_surface(object);
  const double c_uniform = object.outline->uniform_pressure_torque_ratio_m(start);
  const double lower[3] = {std::log(kMinPusherFriction), std::log(0.15 * c_uniform), std::log(0.05)};
  const double upper[3] = {std::log(kMaxPusherFriction), std::log(2.5 * c_uniform), std::log(1.5)};
  const double prior_centre[3] = {std::log(0.25), std::log(c_uniform), std::log(0.4)};
  const std::size_t n = cases.size();
  std::vector<std::array<double, 3>> theta(n);
  double centre[2] = {start.x(), start.y()};
  double rim[1] = {object.pressure_rim_weight};
  const bool fit_rim = options.fit_rim_weight && fixed_ratio;
  const std::vector<int> held = held_indices(fixed_ratio, fit_options);
  ceres::Problem problem;
  PressureSurfaceCache surfaces;
  int residual_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k)
      theta[i][static_cast<std::size_t>(k)] = std::clamp(std::log(fits[i].parameters.vector()(k)), lower[k], upper[k]);
    auto* cost = new SharedCentreResidual(cases[i], object, fit_options, surfaces);
    residual_count += cost->num_residuals();
    problem.AddResidualBlock(cost, new ceres::HuberLoss(3.0), theta[i].data(), centre, rim);
    // The pressure's limit surface has no ratio c: each push keeps its own fit's (unused by the forecast); a held rod
    // friction stays at its value.
    if (fixed_ratio) theta[i][1] = std::log(fits[i].parameters.torque_ratio_m);
    if (is_held(held, 0)) theta[i][0] = std::log(held_pusher_friction(fit_options));
    if (!held.empty()) problem.SetManifold(theta[i].data(), new ceres::SubsetManifold(3, held));
    if (fit_options.prior_width_log > 0)
      for (int k = 0; k < 3; ++k)
        if (!is_held(held, k))
          problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LogPrior, 1, 3>(
                                       new LogPrior{k, prior_centre[k], fit_options.prior_width_log}),
                                   nullptr, theta[i].data());
    for (int k = 0; k < 3; ++k) {
      if (is_held(held, k)) continue;
      problem.SetParameterLowerBound(theta[i].data(), k, lower[k]);
      problem.SetParameterUpperBound(theta[i].data(), k, upper[k]);
    }
  }
  if (options.fit_centre) {
    if (options.prior_sd_m > 0)
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<CentrePrior, 2, 2>(new CentrePrior{start, options.prior_sd_m}), nullptr,
          centre);
    for (int k = 0; k < 2; ++k) {
      problem.SetParameterLowerBound(centre, k, start(k) - options.max_offset_m);
      problem.SetParameterUpperBound(centre, k, start(k) + options.max_offset_m);
    }
  } else {
    problem.SetParameterBlockConstant(centre);
  }
  if (fit_rim) {
    if (options.rim_weight_prior_sd > 0)
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<RimWeightPrior, 1, 1>(new RimWeightPrior{0.0, options.rim_weight_prior_sd}),
          nullptr, rim);
    // The pressure non-negative everywhere, less two difference steps so that the Jacobian's stay inside.
    const RimWeightRange range = rim_weight_range(object.outline->footprint());
    const double margin = 2 * SharedCentreResidual::kRimWeightStep;
    rim[0] = std::clamp(rim[0], range.lower + margin, range.upper - margin);
    problem.SetParameterLowerBound(rim, 0, range.lower + margin);
    problem.SetParameterUpperBound(rim, 0, range.upper - margin);
  } else {
    problem.SetParameterBlockConstant(rim);
  }
  ceres::Solver::Options solver;
  solver.max_num_iterations = options.max_iterations;
  solver.logging_type = ceres::SILENT;  // a step to a centre with no planar pressure is refused, not reported
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  CentreOfFrictionFit out;
  out.centre_m << centre[0], centre[1];
  out.rim_weight = rim[0];
  ForecastObject learned = object;
  set_pressure_shape(learned, out.centre_m, out.rim_weight);
  // Standard errors: Ceres' covariance, scaled by the residuals' own variance (as fit_push_parameters).
  ceres::Covariance covariance(fit_covariance_options());
  std::vector<std::pair<const double*, const double*>> blocks;
  if (options.fit_centre) blocks.emplace_back(centre, centre);
  if (fit_rim) blocks.emplace_back(rim, rim);
  for (const auto& t : theta) blocks.emplace_back(t.data(), t.data());
  const int shared = (options.fit_centre ? 2 : 0) + (fit_rim ? 1 : 0);
  const double variance = 2 * summary.final_cost / std::max(1, residual_count - static_cast<int>(3 * n) - shared);
  const bool have_covariance = covariance.Compute(blocks, &problem);
  if (have_covariance) {
    double cov[4] = {0};
    if (options.fit_centre && covariance.GetCovarianceBlock(centre, centre, cov))
      out.standard_error_m << std::sqrt(std::max(0.0, cov[0] * variance)), std::sqrt(std::max(0.0, cov[3] * variance));
    double rim_cov = 0;
    if (fit_rim && covariance.GetCovarianceBlock(rim, rim, &rim_cov))
      out.rim_weight_standard_error = std::sqrt(std::max(0.0, rim_cov * variance));
  }
  for (std::size_t i = 0; i < n; ++i) {
    PushFit f = fits[i];
    f.parameters = ForecastParameters{std::exp(theta[i][0]), std::exp(theta[i][1]), std::exp(theta[i][2])};
    double cov[9] = {0};
    if (have_covariance && theta_covariance(covariance, theta[i].data(), held, cov))
      for (int k = 0; k < 3; ++k)
        f.standard_error(k) = f.parameters.vector()(k) * std::sqrt(std::max(0.0, cov[4 * k] * variance));
    record_fit_errors(cases[i], learned, fit_options.settings, f);
    out.fits.push_back(std::move(f));
  }
  return out;
}

double rim_weight_jackknife_standard_error(const ForecastObject& object, const std::vector<RecordedForecastCase>& cases,
                                           const std::vector<PushFit>& fits, const CentreOfFrictionOptions& options,
                                           const CentreOfFrictionFit& full, int jobs) {
  if (cases.size() != fits.size() || full.fits.size() != fits.size())
    throw std::logic_error("rim_weight_jackknife_standard_error: one fit per case");
  const std::size_t n = cases.size();
  if (!options.fit_rim_weight || !outline_limit_surface(object) || n < 3) return 0;
  // The refits' start: the full fit's rim weight about the object's own centre (the centre prior's), and the full
  // fit's per-push parameters.
  ForecastObject start = object;
  set_pressure_shape(start, object.centre_of_friction_m, full.rim_weight);
  std::vector<double> left_out(n, 0.0);
  parallel_for_index(n, jobs, [&](std::size_t q) {
    std::vector<RecordedForecastCase> others;
    std::vector<PushFit> other_fits;
    for (std::size_t i = 0; i < n; ++i)
      if (i != q) {
        others.push_back(cases[i]);
        other_fits.push_back(full.fits[i]);
      }
    left_out[q] = fit_centre_of_friction(start, others, other_fits, options).rim_weight;
  });
  const double count = static_cast<double>(n);
  double mean = 0, square = 0;
  for (const double w : left_out) mean += w / count;
  for (const double w : left_out) square += (w - mean) * (w - mean);
  return std::sqrt((count - 1) / count * square);
}

ResidualCorrectionChoice residual_correction_named(const std::string& name) {
  if (name == "none") return ResidualCorrectionChoice::None;
  if (name == "loo") return ResidualCorrectionChoice::LeaveOneOut;
  if (name == "chosen") return ResidualCorrectionChoice::Chosen;
  throw InputError("residual correction: 'none', 'loo' or 'chosen', not '" + name + "'");
}

const char* residual_correction_name(ResidualCorrectionChoice choice) {
  switch (choice) {
    case ResidualCorrectionChoice::LeaveOneOut:
      return "loo";
    case ResidualCorrectionChoice::Chosen:
      return "chosen";
    default:
      return "none";
  }
}

CentralForecast central_forecast_named(const std::string& name) {
  if (name == "ensemble_mean") return CentralForecast::EnsembleMean;
  if (name == "median") return CentralForecast::MedianParameters;
  if (name == "ensemble_median") return CentralForecast::EnsembleMedian;
  throw InputError("central forecast: 'ensemble_mean', 'median' or 'ensemble_median', not '" + name + "'");
}

const char* central_forecast_name(CentralForecast c) {
  switch (c) {
    case CentralForecast::EnsembleMean:
      return "ensemble_mean";
    case CentralForecast::MedianParameters:
      return "median";
    case CentralForecast::EnsembleMedian:
      return "ensemble_median";
  }
  return "ensemble_mean";
}

double weighted_median(std::vector<std::pair<double, double>>& value_weight) {
  if (value_weight.empty()) return std::nan("");
  std::sort(value_weight.begin(), value_weight.end());
  double total = 0, acc = 0;
  for (const auto& vw : value_weight) total += vw.second;
  // The mean of the values where the cumulative weight crosses half from below and above.
  double lower = value_weight.back().first, upper = value_weight.back().first;
  for (std::size_t k = 0; k < value_weight.size(); ++k) {
    acc += value_weight[k].second;
    if (acc >= 0.5 * total - 1e-12 * total) {
      lower = value_weight[k].first;
      upper = (acc <= 0.5 * total + 1e-12 * total && k + 1 < value_weight.size()) ? value_weight[k + 1].first : lower;
      break;
    }
  }
  return 0.5 * (lower + upper);
}

Eigen::Vector2d weighted_geometric_median(const Eigen::Ref<const Eigen::Matrix2Xd>& points,
                                          const Eigen::Ref<const Eigen::VectorXd>& weights, double tolerance_m,
                                          int max_iterations, const Eigen::Vector2d* start) {
  const Eigen::Index n = points.cols();
  const double total = weights.sum();
  if (n == 0 || !(total > 0)) return Eigen::Vector2d::Constant(std::nan(""));
  const Eigen::Vector2d mean = points * weights / total;
  Eigen::Vector2d y = start != nullptr && start->allFinite() ? *start : mean;
  double scale = 0;
  for (Eigen::Index i = 0; i < n; ++i) scale = std::max(scale, (points.col(i) - mean).norm());
  // Points closer than `coincide` to y are taken to be at it. Weiszfeld's iterates approach a median that is one of
  // the points only slowly (as for points near a line, whose median is one of them), so each iteration first asks
  // whether the point nearest the iterate is the median (each point asked once).
  const double coincide = 1e-12 * std::max(scale, 1e-300);
  Eigen::Index asked = -1;
  // Whether y is the median with weight `at` there: the others, each pulling with its weight along its unit vector
  // from y, pull less than `at` (Vardi & Zhang 2000); `pull` and the Weiszfeld sums are filled on the way.
  Eigen::Vector2d numerator, pull;
  double denominator = 0;
  auto sums_at = [&](const Eigen::Vector2d& at_point, double& at_weight) {
    numerator.setZero();
    pull.setZero();
    denominator = 0;
    at_weight = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!(weights(i) > 0)) continue;
      const Eigen::Vector2d r = points.col(i) - at_point;
      const double distance = r.norm();
      if (distance <= coincide) {
        at_weight += weights(i);
        continue;
      }
      numerator += weights(i) / distance * points.col(i);
      denominator += weights(i) / distance;
      pull += weights(i) / distance * r;
    }
  };
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    // The point nearest the iterate, when near it: the median if the others pull less than its weight.
    Eigen::Index nearest = -1;
    double nearest_distance = std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!(weights(i) > 0)) continue;
      const double distance = (points.col(i) - y).norm();
      if (distance < nearest_distance) {
        nearest_distance = distance;
        nearest = i;
      }
    }
    if (nearest >= 0 && nearest != asked) {
      asked = nearest;
      const Eigen::Vector2d candidate = points.col(nearest);
      double at = 0;
      sums_at(candidate, at);
      if (!(denominator > 0) || pull.norm() <= at) return candidate;
    }
    double at = 0;
    sums_at(y, at);
    if (!(denominator > 0)) return y;  // every weighted point at the iterate
    Eigen::Vector2d next = numerator / denominator;
    if (at > 0) {
      // At a point of weight `at`: it is the median when the others pull less than its weight; else step off it.
      const double p = pull.norm();
      if (p <= at) return y;
      next = (1 - at / p) * next + (at / p) * y;
    }
    const double step = (next - y).norm();
    y = next;
    if (step < tolerance_m) break;
  }
  return y;
}

namespace {

double central_score(const Eigen::MatrixX3d& mean, const RecordedForecastCase& c, const std::vector<Eigen::Index>& idx);

/// How well `members` (weighted by bandwidth h) forecast the recorded push `c` by their central forecast: its final
/// and trajectory-mean errors, 1 mm and 1 degree alike. What learn chooses its settings by.
double held_out_score(const ForecastObject& object, const std::vector<const PushFit*>& members, double h,
                      const ParameterTrend& trend, const RecordedForecastCase& c, const ForecastSettings& settings,
                      CentralForecast central, ForecastWorkspace& work) {
  std::vector<Eigen::Index> idx;
  const Eigen::VectorXd times = scoring_times(c, idx);
  Eigen::MatrixX3d mean(times.size(), 3);
  Eigen::VectorXd ps(times.size()), ys(times.size());
  ForecastRun run;
  central_and_spread(object, members, h, trend, c.plan, c.start_pose, times, settings, mean, ps, ys, work, run, central,
                     false);
  return central_score(mean, c, idx);
}

/// A central forecast's score against the recorded push `c` at its scoring times (indices `idx`): the final and
/// trajectory-mean errors, 1 mm and 1 degree alike.
double central_score(const Eigen::MatrixX3d& mean, const RecordedForecastCase& c,
                     const std::vector<Eigen::Index>& idx) {
  double pos = 0, yaw = 0;
  for (std::size_t k = 0; k < idx.size(); ++k) {
    pos += (mean.row(static_cast<Eigen::Index>(k)).head<2>() - c.truth.row(idx[k]).head<2>()).norm();
    yaw += std::abs(mean(static_cast<Eigen::Index>(k), 2) - c.truth(idx[k], 2));
  }
  const Eigen::Index last = mean.rows() - 1;
  return 1e3 * (pos / static_cast<double>(idx.size()) +
                (mean.row(last).head<2>() - c.truth.row(idx.back()).head<2>()).norm()) +
         180 / M_PI * (yaw / static_cast<double>(idx.size()) + std::abs(mean(last, 2) - c.truth(idx.back(), 2)));
}

/// The held-out score (held_out_score summed over the learned pushes) of `folds`-fold cross-validation over them (push
/// i in fold i mod folds), each fold forecast by the others' ensemble (all alike): with the centre of friction and/or
/// the pressure's rim weight (`fit_centre`, `fit_rim_weight`) fitted jointly on those others, or with neither the
/// others' own fits about `object`'s own centre and pressure. What learn keeps a learned centre or rim weight by.
double cross_validated_score(const ForecastObject& object, const std::vector<RecordedForecastCase>& cases,
                             const std::vector<PushFit>& fits, const LearnOptions& options, int folds, bool fit_centre,
                             bool fit_rim_weight, ForecastWorkspace& work) {
  CentreOfFrictionOptions cof = options.centre_of_friction;
  cof.fit.settings = options.settings;
  cof.fit_centre = fit_centre;
  cof.fit_rim_weight = fit_rim_weight;
  double total = 0;
  for (int fold = 0; fold < folds; ++fold) {
    std::vector<RecordedForecastCase> train_cases;
    std::vector<PushFit> train_fits;
    std::vector<std::size_t> test;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      if (static_cast<int>(i % static_cast<std::size_t>(folds)) == fold) {
        test.push_back(i);
      } else {
        train_cases.push_back(cases[i]);
        train_fits.push_back(fits[i]);
      }
    }
    if (test.empty() || train_fits.empty()) continue;
    if (!fit_centre && !fit_rim_weight) {
      std::vector<const PushFit*> own_members;
      for (const auto& f : train_fits) own_members.push_back(&f);
      for (std::size_t q : test)
        total += held_out_score(object, own_members, 0, {}, cases[q], options.settings, options.central, work);
      continue;
    }
    const CentreOfFrictionFit fit = fit_centre_of_friction(object, train_cases, train_fits, cof);
    ForecastObject moved = object;
    set_pressure_shape(moved, fit.centre_m, fit.rim_weight);
    std::vector<const PushFit*> learned_members;
    for (const auto& f : fit.fits) learned_members.push_back(&f);
    for (std::size_t q : test)
      total += held_out_score(moved, learned_members, 0, {}, cases[q], options.settings, options.central, work);
  }
  return total;
}

/// Sets how a setting that learn keeps when cross-validation over the learned pushes prefers it is learned (its
/// minimum pushes and folds, LearnOptions): "chosen" (the defaults), "learned" (always: no cross-validation) or `never`
/// (never learned: minimum pushes 0). InputError naming `what` otherwise.
void set_cross_validated_choice(const std::string& choice, const char* what, const char* never, int default_min_pushes,
                                int default_folds, int& min_pushes, int& folds) {
  min_pushes = default_min_pushes;
  folds = default_folds;
  if (choice == "learned") {
    folds = 0;
  } else if (choice == never) {
    min_pushes = 0;
  } else if (choice != "chosen") {
    throw InputError(std::string(what) + ": 'chosen', 'learned' or '" + never + "', not '" + choice + "'");
  }
}

}  // namespace

void set_centre_of_friction_choice(LearnOptions& options, const std::string& choice) {
  const LearnOptions defaults;
  set_cross_validated_choice(choice, "centre of friction", "centroid", defaults.centre_of_friction_min_pushes,
                             defaults.centre_of_friction_folds, options.centre_of_friction_min_pushes,
                             options.centre_of_friction_folds);
}

void set_pressure_shape_choice(LearnOptions& options, const std::string& choice) {
  const LearnOptions defaults;
  set_cross_validated_choice(choice, "pressure shape", "uniform", defaults.pressure_shape_min_pushes,
                             defaults.pressure_shape_folds, options.pressure_shape_min_pushes,
                             options.pressure_shape_folds);
}

void set_trend_choice(LearnOptions& options, const std::string& choice) {
  if (choice == "chosen") {
    options.trend_ridges = kTrendCandidateRidges;
  } else if (choice == "none") {
    options.trend_ridges = {0.0};
  } else {
    throw InputError("parameter trend: 'chosen' or 'none', not '" + choice + "'");
  }
}

void set_similarity_choice(LearnOptions& options, const std::string& choice) {
  if (choice == "chosen") {
    options.similarity_averaged = false;
  } else if (choice == "averaged") {
    options.similarity_averaged = true;
  } else {
    throw InputError("similarity weighting: 'chosen' or 'averaged', not '" + choice + "'");
  }
}

PusherFrictionSource pusher_friction_named(const std::string& name) {
  if (name == "fitted") return PusherFrictionSource::Fitted;
  if (name == "measured") return PusherFrictionSource::Measured;
  throw InputError("pusher friction '" + name + "' is not known: give fitted or measured");
}

const char* pusher_friction_name(PusherFrictionSource source) {
  return source == PusherFrictionSource::Measured ? "measured" : "fitted";
}

namespace {
ObjectModel learn_object_model_from(const ForecastObject& object, const std::string& surface,
                                    const std::string& outline_source, const std::vector<RecordedForecastCase>& cases,
                                    const std::vector<PushFit>& fits, const LearnOptions& options);
}  // namespace

ObjectModel learn_object_model(const ForecastObject& object, const std::string& surface,
                               const std::string& outline_source, const std::vector<RecordedForecastCase>& cases,
                               const std::vector<PushFit>& fits, const LearnOptions& options) {
  if (options.pusher_friction != PusherFrictionSource::Measured || cases.size() != fits.size())
    return learn_object_model_from(object, surface, outline_source, cases, fits, options);
  std::vector<double> measured;
  for (const RecordedForecastCase& c : cases)
    if (std::isfinite(c.measured_pusher_friction)) measured.push_back(c.measured_pusher_friction);
  if (measured.empty()) {
    ObjectModel model = learn_object_model_from(object, surface, outline_source, cases, fits, options);
    model.pusher_friction_method = "fitted per push (no learned push's force sensor measured a sliding contact)";
    return model;
  }
  const double mu_p = median(measured);
  LearnOptions held = options;
  held.centre_of_friction.fit.held_pusher_friction = mu_p;
  FitOptions fit_options = held.centre_of_friction.fit;
  fit_options.settings = options.settings;
  std::vector<PushFit> refitted(fits.size());
  parallel_for_index(fits.size(), options.jobs,
                     [&](std::size_t i) { refitted[i] = fit_push_parameters(cases[i], fit_options); });
  ObjectModel model = learn_object_model_from(object, surface, outline_source, cases, refitted, held);
  std::ostringstream method;
  method << "measured: " << mu_p << ", the median of what " << measured.size() << " of the " << cases.size()
         << " learned pushes' force sensors measured where the contact slid; c and mu_s fitted under it";
  model.pusher_friction_method = method.str();
  return model;
}

namespace {

ObjectModel learn_object_model_from(const ForecastObject& object, const std::string& surface,
                                    const std::string& outline_source, const std::vector<RecordedForecastCase>& cases,
                                    const std::vector<PushFit>& fits, const LearnOptions& options) {
  const ForecastSettings& settings = options.settings;
  std::vector<double> bandwidths = options.bandwidths;
  if (fits.empty()) throw InputError("learn: no push to learn '" + object.name + "' from");
  if (cases.size() != fits.size()) throw std::logic_error("learn_object_model: one case per fit");
  object.validate();
  if (bandwidths.empty()) bandwidths = {0.0};
  if (options.similarity_averaged) bandwidths = {kAveragedBandwidth};
  ObjectModel model;
  model.surface = surface;
  model.object = object;
  model.outline_source = outline_source;
  model.pushes = fits;
  model.settings = settings;
  ForecastWorkspace work;
  const bool enough = options.centre_of_friction_min_pushes > 0 &&
                      fits.size() >= static_cast<std::size_t>(options.centre_of_friction_min_pushes);
  if (options.centre_of_friction_min_pushes > 0 && !enough)
    model.centre_of_friction_method = "the object's own (too few pushes to learn it from)";
  // Cross-validated scores by (folds, centre fitted, rim weight fitted), each computed once.
  std::map<std::tuple<int, bool, bool>, double> scores;
  auto score = [&](int folds, bool fit_centre, bool fit_rim_weight) {
    const auto key = std::make_tuple(folds, fit_centre, fit_rim_weight);
    auto it = scores.find(key);
    if (it == scores.end())
      it = scores
               .emplace(key,
                        cross_validated_score(object, cases, fits, options, folds, fit_centre, fit_rim_weight, work))
               .first;
    return it->second;
  };
  const int centre_folds = options.centre_of_friction_folds;
  const bool better =
      enough && (centre_folds < 2 || score(centre_folds, true, false) < score(centre_folds, false, false));
  if (enough && !better)
    model.centre_of_friction_method = "the object's own (a learned one forecast the learned pushes worse in " +
                                      std::to_string(centre_folds) + "-fold cross-validation)";
  // The pressure's shape (the outline's limit surface only): the rim weight, fitted with the centre as just decided,
  // kept when it forecasts the learned pushes better in cross-validation than the same without it.
  const bool outline = outline_limit_surface(object);
  const bool shape_enough = outline && options.pressure_shape_min_pushes > 0 &&
                            fits.size() >= static_cast<std::size_t>(options.pressure_shape_min_pushes);
  const int shape_folds = options.pressure_shape_folds;
  if (!outline)
    model.pressure_shape_method = "none (the ellipsoid's ratio c stands for it)";
  else if (options.pressure_shape_min_pushes > 0 && !shape_enough)
    model.pressure_shape_method = "uniform (too few pushes to learn the rim weight from)";
  const bool shape =
      shape_enough && (shape_folds < 2 || score(shape_folds, better, true) < score(shape_folds, better, false));
  if (shape_enough && !shape)
    model.pressure_shape_method = "uniform (a learned rim weight forecast the learned pushes worse in " +
                                  std::to_string(shape_folds) + "-fold cross-validation)";
  if (better || shape) {
    CentreOfFrictionOptions cof = options.centre_of_friction;
    cof.fit.settings = settings;
    cof.fit_centre = better;
    cof.fit_rim_weight = shape;
    CentreOfFrictionFit learned = fit_centre_of_friction(object, cases, fits, cof);
    set_pressure_shape(model.object, learned.centre_m, learned.rim_weight);
    if (better) {
      model.centre_of_friction_method = "fitted jointly over the learned pushes, each with its own parameters";
      model.centre_of_friction_standard_error_m = learned.standard_error_m;
      model.centre_of_friction_pushes = static_cast<int>(fits.size());
    }
    if (shape) {
      model.pressure_shape_method = "rim weight fitted jointly over the learned pushes, each with its own parameters" +
                                    std::string(better ? ", with the centre of friction" : "");
      if (options.rim_weight_jackknife)
        model.pressure_rim_weight_standard_error =
            rim_weight_jackknife_standard_error(object, cases, fits, cof, learned, options.jobs);
      // At a bound of its range the fits without one push stay there too: their spread says nothing of how far
      // beyond it the pushes would put w, and the file says so.
      const RimWeightRange range = rim_weight_range(object.outline->footprint());
      const double margin = 2 * SharedCentreResidual::kRimWeightStep + 1e-9;
      if (learned.rim_weight <= range.lower + margin || learned.rim_weight >= range.upper - margin)
        model.pressure_shape_method +=
            std::string("; at the ") + (learned.rim_weight <= range.lower + margin ? "lower" : "upper") +
            " bound of its range (the pressure non-negative everywhere), where its standard error does not measure "
            "how far beyond it the pushes would put it";
      model.pressure_rim_weight_pushes = static_cast<int>(fits.size());
    }
    model.pushes = std::move(learned.fits);
  }
  const std::vector<PushFit>& learned_fits = model.pushes;
  const ForecastObject& learned_object = model.object;
  std::vector<ForecastParameters> all;
  for (const auto& f : learned_fits) all.push_back(f.parameters);
  model.parameters = weighted_median_parameters(all, std::vector<double>(all.size(), 1.0));
  model.central = options.central;
  for (int i = 0; i < 3; ++i) {
    std::vector<double> values;
    for (const auto& f : learned_fits) values.push_back(f.parameters.vector()(i));
    model.push_to_push_sd(i) = values.size() > 1 ? robust_spread(values) : 0.0;
    // The median's standard error under push-to-push scatter, with each push's own identification error added.
    double identification = 0;
    for (const auto& f : learned_fits) identification += f.standard_error(i) * f.standard_error(i);
    const double n = static_cast<double>(values.size());
    model.standard_error(i) =
        std::sqrt(1.2533 * 1.2533 * model.push_to_push_sd(i) * model.push_to_push_sd(i) / n + identification / (n * n));
  }
  auto others_of = [&](std::size_t q) {
    std::vector<const PushFit*> others;
    for (std::size_t i = 0; i < learned_fits.size(); ++i)
      if (i != q) others.push_back(&learned_fits[i]);
    return others;
  };

  // The bandwidth and the trend's ridge weight: the pair whose leave-one-out forecasts of the learned pushes err least
  // (final and trajectory mean, mm and degrees alike), the trend fitted on the others for each left-out push. A trend
  // is kept only when it beats the best pair without one by more than one standard error of their paired per-push
  // differences (the one-standard-error rule: a choice among 12 candidates on a dozen pushes otherwise picks noise).
  std::vector<double> ridges = options.trend_ridges;
  if (ridges.empty()) ridges = {0.0};
  double ridge = 0;
  if (fits.size() >= 4 && bandwidths.size() * ridges.size() > 1) {
    struct Choice {
      double h = 0, ridge = 0, total = std::numeric_limits<double>::infinity();
      std::vector<double> per_push;
    };
    Choice with_trend, without_trend;
    for (double r : ridges) {
      std::vector<ParameterTrend> trends;
      for (std::size_t q = 0; q < fits.size(); ++q) trends.push_back(fit_trend(others_of(q), r));
      for (double h : bandwidths) {
        Choice c{h, r, 0, {}};
        for (std::size_t q = 0; q < fits.size(); ++q) {
          c.per_push.push_back(
              held_out_score(learned_object, others_of(q), h, trends[q], cases[q], settings, options.central, work));
          c.total += c.per_push.back();
        }
        Choice& best = r > 0 ? with_trend : without_trend;
        if (c.total < best.total - 1e-9) best = std::move(c);
      }
    }
    const Choice* chosen = &without_trend;
    if (without_trend.per_push.empty()) {
      chosen = &with_trend;
    } else if (!with_trend.per_push.empty() && with_trend.total < without_trend.total - 1e-9) {
      const double n = static_cast<double>(fits.size());
      double mean = 0, square = 0;
      for (std::size_t q = 0; q < fits.size(); ++q) {
        const double d = without_trend.per_push[q] - with_trend.per_push[q];
        mean += d / n;
        square += d * d / n;
      }
      const double standard_error = std::sqrt(std::max(0.0, square - mean * mean) / std::max(1.0, n - 1));
      if (mean > standard_error) chosen = &with_trend;
    }
    model.similarity_bandwidth = chosen->h;
    ridge = chosen->ridge;
  } else {
    model.similarity_bandwidth = bandwidths.size() == 1 ? bandwidths.front() : 0.0;
    ridge = ridges.size() == 1 ? ridges.front() : 0.0;
  }
  model.similarity_averaged = options.similarity_averaged;
  if (model.similarity_averaged) model.similarity_bandwidth = 0;
  std::vector<const PushFit*> everyone;
  for (const auto& f : learned_fits) everyone.push_back(&f);
  model.trend = fit_trend(everyone, ridge);
  model.residual_shrinkage = kResidualShrinkage;
  model.residual_correction = false;
  model.residual_correction_method = "none";
  if (fits.size() >= 3) {
    // Each learned push forecast by the others (their central forecast and spread at its scoring times), and its
    // leave-one-out final error in its plan's frame.
    const std::size_t n = fits.size();
    std::vector<std::vector<Eigen::Index>> idxs(n);
    std::vector<Eigen::VectorXd> times_of(n), ps_of(n), ys_of(n);
    std::vector<Eigen::MatrixX3d> mean_of(n);
    for (std::size_t q = 0; q < n; ++q) {
      const RecordedForecastCase& c = cases[q];
      times_of[q] = scoring_times(c, idxs[q]);
      const Eigen::Index m = times_of[q].size();
      mean_of[q].resize(m, 3);
      ps_of[q].resize(m);
      ys_of[q].resize(m);
      ForecastRun run;
      const std::vector<const PushFit*> others = others_of(q);
      central_and_spread(learned_object, others, weighting_bandwidth(model), fit_trend(others, model.trend.ridge),
                         c.plan, c.start_pose, times_of[q], settings, mean_of[q], ps_of[q], ys_of[q], work, run,
                         options.central);
      model.pushes[q].loo_final_error =
          plan_frame_error(c.plan, mean_of[q].row(m - 1).transpose(), c.truth.row(idxs[q].back()).transpose());
    }
    // The residual correction: each left-out push's forecast shifted by the others' leave-one-out errors (computed
    // with ensembles that held the left-out push: an approximation of the nested leave-one-out, which would cost n^2
    // forecasts); the regions are calibrated on the forecasts kept.
    if (options.residual_correction != ResidualCorrectionChoice::None) {
      std::vector<Eigen::MatrixX3d> corrected = mean_of;
      std::vector<double> w;
      double plain_score = 0, corrected_score = 0;
      for (std::size_t q = 0; q < n; ++q) {
        const RecordedForecastCase& c = cases[q];
        const std::vector<const PushFit*> others = others_of(q);
        member_weights(others, weighting_bandwidth(model), describe_push(learned_object, c.plan, c.start_pose), w);
        apply_residual_shift(residual_shift(others, w, model.residual_shrinkage), c.plan, times_of[q], corrected[q]);
        plain_score += central_score(mean_of[q], c, idxs[q]);
        corrected_score += central_score(corrected[q], c, idxs[q]);
      }
      const bool keep =
          options.residual_correction == ResidualCorrectionChoice::LeaveOneOut || corrected_score < plain_score;
      std::ostringstream method;
      method.precision(4);
      method << "leave-one-out final errors of the learned pushes, similarity-weighted, shrunk by n_eff / (n_eff + "
             << model.residual_shrinkage << "); learned pushes' leave-one-out score (final and trajectory mm + deg "
             << "summed) " << plain_score << " without, " << corrected_score << " with it";
      if (keep) {
        mean_of = std::move(corrected);
        model.residual_correction = true;
        model.residual_correction_method = method.str();
      } else {
        model.residual_correction_method = "none (" + method.str() + ")";
      }
    }
    std::vector<std::pair<double, double>> pos_ratio[3], yaw_ratio[3];
    for (std::size_t q = 0; q < n; ++q) {
      const RecordedForecastCase& c = cases[q];
      const std::vector<Eigen::Index>& idx = idxs[q];
      const Eigen::VectorXd& times = times_of[q];
      const Eigen::MatrixX3d& mean = mean_of[q];
      const Eigen::VectorXd& ps = ps_of[q];
      const Eigen::VectorXd& ys = ys_of[q];
      const double weight = 1.0 / static_cast<double>(idx.size());
      for (std::size_t k = 0; k < idx.size(); ++k) {
        const Eigen::Index e = static_cast<Eigen::Index>(k);
        const double pos_err = (mean.row(e).head<2>() - c.truth.row(idx[k]).head<2>()).norm();
        const double yaw_err = std::abs(mean(e, 2) - c.truth(idx[k], 2));
        const int stage = RegionCalibration::stage(times(e), c.plan.end_time_s());
        pos_ratio[stage].emplace_back(pos_err / std::hypot(ps(e), model.regions.position_floor_m), weight);
        yaw_ratio[stage].emplace_back(yaw_err / std::hypot(ys(e), model.regions.yaw_floor_rad), weight);
      }
    }
    // The split-conformal level for n held-out pushes, 0.9 (1 + 1/n): a quantile of n pushes' errors falls short of
    // the population's by about one push (the pushes, not their correlated samples, are the independent draws).
    const double level = std::min(1.0, 0.9 * (1.0 + 1.0 / static_cast<double>(fits.size())));
    for (int stage = 0; stage < 3; ++stage) {
      if (pos_ratio[stage].empty()) continue;
      model.regions.position_scale[static_cast<std::size_t>(stage)] = weighted_quantile(pos_ratio[stage], level);
      model.regions.yaw_scale[static_cast<std::size_t>(stage)] = weighted_quantile(yaw_ratio[stage], level);
    }
    model.regions.pushes = static_cast<int>(fits.size());
  } else {
    model.regions.method = "not calibrated (fewer than 3 pushes): the normal 90 % quantile on the ensemble's spread";
    if (options.residual_correction != ResidualCorrectionChoice::None)
      model.residual_correction_method = "none (fewer than 3 pushes: no leave-one-out errors)";
  }
  return model;
}

}  // namespace

ForecastParameters central_parameters(const ObjectModel& model, const PushDescriptor& descriptor) {
  std::vector<const PushFit*> members;
  std::vector<ForecastParameters> parameters;
  for (const auto& f : model.pushes) {
    members.push_back(&f);
    parameters.push_back(parameters_along_trend(f, model.trend, descriptor));
  }
  if (members.empty()) return model.parameters;
  std::vector<double> w;
  member_weights(members, weighting_bandwidth(model), descriptor, w);
  return weighted_median_parameters(parameters, w);
}

ParameterTrend fit_parameter_trend(const std::vector<PushFit>& fits, double ridge) {
  std::vector<const PushFit*> members;
  for (const auto& f : fits) members.push_back(&f);
  return fit_trend(members, ridge);
}

Eigen::Matrix<double, kTrendFeatures, 1> trend_features(const PushDescriptor& d) {
  Eigen::Matrix<double, kTrendFeatures, 1> f;
  f << d.angle_rad / kDescriptorAngle_rad, d.contact_body_m.x() / kDescriptorContact_m,
      d.contact_body_m.y() / kDescriptorContact_m, d.log_speed / kDescriptorLogSpeed;
  return f;
}

PushDescriptor describe_push(const ForecastObject& object, const TipPlan& plan, const Eigen::Vector3d& pose0) {
  PushDescriptor d;
  const Eigen::Rotation2Dd R(pose0(2));
  int hint = -1;
  const Outline::Closest c = object.outline->closest(R.inverse() * (plan.start_m() - pose0.head<2>()), hint);
  d.contact_body_m = c.point_m;
  const Eigen::Vector2d direction = R.inverse() * plan.direction();
  const Eigen::Vector2d inward = -c.normal;
  d.angle_rad = std::atan2(inward.x() * direction.y() - inward.y() * direction.x(), inward.dot(direction));
  d.log_speed = std::log(std::max(plan.speed_m_s(), 1e-6));
  return d;
}

double descriptor_distance2(const PushDescriptor& a, const PushDescriptor& b) {
  const double da = (a.angle_rad - b.angle_rad) / kDescriptorAngle_rad,
               dc = (a.contact_body_m - b.contact_body_m).norm() / kDescriptorContact_m,
               dv = (a.log_speed - b.log_speed) / kDescriptorLogSpeed;
  return da * da + dc * dc + dv * dv;
}

nlohmann::json object_model_to_json(const ObjectModel& m) {
  nlohmann::json j;
  j["format"] = "pushpred-object-model";
  j["version"] = kObjectModelVersion;
  j["units"] = "SI: metres, radians, kilograms; body frame of the outline (origin at the tracked centre)";
  nlohmann::json outline;
  const ForecastOutline& o = *m.object.outline;
  if (m.outline_source.rfind("shape table: ", 0) == 0 || m.outline_source.rfind("data folder: ", 0) == 0) {
    outline["kind"] = "shape_table";
    outline["shape"] = m.object.name;
  } else if (!o.is_polygon()) {
    outline["kind"] = o.semi_axis_a_m() == o.semi_axis_b_m() ? "circle" : "ellipse";
    if (o.semi_axis_a_m() == o.semi_axis_b_m())
      outline["radius_m"] = o.semi_axis_a_m();
    else
      outline["semi_axes_m"] = {o.semi_axis_a_m(), o.semi_axis_b_m()};
  } else {
    outline["kind"] = "polygon";
    nlohmann::json v = nlohmann::json::array();
    for (const auto& p : o.vertices_m()) v.push_back({p.x(), p.y()});
    outline["vertices_m"] = v;
  }
  outline["source"] = m.outline_source;
  j["object"] = {{"name", m.object.name},
                 {"surface", m.surface},
                 {"mass_kg", m.object.mass_kg},
                 {"inertia_kgm2", m.object.inertia_kgm2},
                 {"centre_of_friction_m", {m.object.centre_of_friction_m.x(), m.object.centre_of_friction_m.y()}},
                 {"limit_surface", limit_surface_name(m.object.limit_surface)},
                 {"outline", outline}};
  j["object"]["centre_of_friction"] = {
      {"learned_from_pushes", m.centre_of_friction_pushes},
      {"standard_error_m", {m.centre_of_friction_standard_error_m.x(), m.centre_of_friction_standard_error_m.y()}},
      {"method", m.centre_of_friction_method}};
  j["object"]["pressure_shape"] = {
      {"rim_weight", m.object.pressure_rim_weight},
      {"standard_error", m.pressure_rim_weight_standard_error},
      {"learned_from_pushes", m.pressure_rim_weight_pushes},
      {"method", m.pressure_shape_method},
      {"definition",
       "outline limit surface only: pressure ~ (1 + rim_weight (|r - centroid|^2 / <|r - centroid|^2> - 1)), tilted "
       "by a plane so that its centre lies at centre_of_friction_m; 0 uniform, > 0 loads the rim, < 0 the middle; "
       "standard_error: the jackknife's over the learned pushes (each left out in turn, rim_weight refitted on the "
       "others), 0 when rim_weight is not learned"}};
  nlohmann::json params;
  for (int i = 0; i < 3; ++i)
    params[ForecastParameters::name(i)] = {{"value", m.parameters.vector()(i)},
                                           {"standard_error", m.standard_error(i)},
                                           {"push_to_push_sd", m.push_to_push_sd(i)}};
  j["parameters"] = params;
  nlohmann::json pushes = nlohmann::json::array();
  for (const auto& f : m.pushes) {
    nlohmann::json p{{"name", f.name}};
    for (int i = 0; i < 3; ++i) {
      p[ForecastParameters::name(i)] = f.parameters.vector()(i);
      p[std::string(ForecastParameters::name(i)) + "_standard_error"] = f.standard_error(i);
    }
    p["descriptor"] = {{"contact_body_m", {f.descriptor.contact_body_m.x(), f.descriptor.contact_body_m.y()}},
                       {"angle_rad", f.descriptor.angle_rad},
                       {"speed_m_s", std::exp(f.descriptor.log_speed)}};
    p["fit_rms_position_m"] = f.rms_position_m;
    p["fit_rms_yaw_rad"] = f.rms_yaw_rad;
    p["loo_final_error"] = {f.loo_final_error(0), f.loo_final_error(1), f.loo_final_error(2)};
    pushes.push_back(p);
  }
  j["pushes"] = pushes;
  j["similarity_bandwidth"] = m.similarity_bandwidth;
  j["similarity_weighting"] = m.similarity_averaged ? "averaged" : "chosen";
  nlohmann::json slopes = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (int k = 0; k < kTrendFeatures; ++k) row.push_back(m.trend.slope(i, k));
    slopes.push_back(row);
  }
  j["parameter_trend"] = {{"ridge", m.trend.ridge},
                          {"slope", slopes},
                          {"max_shift_log", m.trend.max_shift_log},
                          {"features", "angle / 20 deg, contact x / 15 mm, contact y / 15 mm, ln(speed [m/s])"},
                          {"rows", "ln pusher_friction, ln torque_ratio_m, ln support_friction"}};
  j["central"] = central_forecast_name(m.central);
  j["pusher_friction"] = {
      {"method", m.pusher_friction_method},
      {"definition",
       "where the pushes' rod friction (pusher_friction) comes from: each push's own fit, or the median of what the "
       "learned pushes' force sensors measured where the contact slid, held in every push's fit"}};
  j["residual_correction"] = {
      {"applied", m.residual_correction},
      {"shrinkage_k", m.residual_shrinkage},
      {"method", m.residual_correction_method},
      {"definition",
       "applied: the central forecast minus the similarity-weighted mean of the pushes' loo_final_error (each push's "
       "leave-one-out forecast minus its recorded final pose, in its plan's frame: along the push [m], across it "
       "counter-clockwise [m], yaw [rad]), shrunk by n_eff / (n_eff + shrinkage_k), times the tip's progress along "
       "the plan (0 at its start, 1 from its end on)"}};
  j["regions"] = {{"level", 0.9},
                  {"position_scale", m.regions.position_scale},
                  {"yaw_scale", m.regions.yaw_scale},
                  {"scale_stages", "thirds of the planned push by plan time; the last holds the slide and the rest"},
                  {"position_floor_m", m.regions.position_floor_m},
                  {"yaw_floor_rad", m.regions.yaw_floor_rad},
                  {"calibration_pushes", m.regions.pushes},
                  {"method", m.regions.method}};
  j["settings"] = {{"rod_radius_m", m.settings.rod_radius_m},
                   {"max_tip_step_m", m.settings.max_tip_step_m},
                   {"slide_step_s", m.settings.slide_step_s}};
  return j;
}

ObjectModel object_model_from_json(const nlohmann::json& j, const std::string& source,
                                   const std::filesystem::path& data_folder) {
  auto fail = [&](const std::string& what) { return InputError(about(source, what)); };
  if (!j.is_object()) throw fail("not a JSON object");
  if (!j.contains("format") || j.at("format") != "pushpred-object-model")
    throw fail("not a pushpred object model ('format' must be \"pushpred-object-model\")");
  if (!j.contains("version") || !j.at("version").is_number_integer()) throw fail("'version' must be an integer");
  ObjectModel m;
  m.version = j.at("version").get<int>();
  if (m.version < 1 || m.version > kObjectModelVersion)
    throw fail("version " + std::to_string(m.version) + " is not one this pushpred reads (1 to " +
               std::to_string(kObjectModelVersion) + ")");
  if (!j.contains("object") || !j.at("object").is_object()) throw fail("'object' must be an object");
  const nlohmann::json& o = j.at("object");
  try {
    m.object.name = o.value("name", std::string("object"));
    m.surface = o.value("surface", std::string("unknown"));
    m.object.mass_kg = number_at(o, "mass_kg", "object");
    m.object.inertia_kgm2 = number_at(o, "inertia_kgm2", "object");
    if (o.contains("centre_of_friction_m")) {
      const auto& cof = o.at("centre_of_friction_m");
      if (!cof.is_array() || cof.size() != 2 || !cof[0].is_number() || !cof[1].is_number())
        throw InputError("object: 'centre_of_friction_m' must be [x, y]");
      m.object.centre_of_friction_m << cof[0].get<double>(), cof[1].get<double>();
    }
    if (o.contains("centre_of_friction")) {  // version 2 on; optional
      const auto& cof = o.at("centre_of_friction");
      if (!cof.is_object()) throw InputError("object: 'centre_of_friction' must be an object");
      m.centre_of_friction_pushes = cof.value("learned_from_pushes", 0);
      m.centre_of_friction_method = cof.value("method", m.centre_of_friction_method);
      if (m.centre_of_friction_pushes < 0)
        throw InputError("object: centre_of_friction: 'learned_from_pushes' must not be negative");
      if (cof.contains("standard_error_m")) {
        const auto& se = cof.at("standard_error_m");
        if (!se.is_array() || se.size() != 2 || !se[0].is_number() || !se[1].is_number())
          throw InputError("object: centre_of_friction: 'standard_error_m' must be [x, y]");
        m.centre_of_friction_standard_error_m << se[0].get<double>(), se[1].get<double>();
      }
    }
    if (!o.contains("outline") || !o.at("outline").is_object()) throw InputError("object: 'outline' must be an object");
    const nlohmann::json& ol = o.at("outline");
    const std::string kind = ol.value("kind", std::string());
    if (kind == "shape_table") {
      const std::string shape = ol.value("shape", std::string());
      const ShapeInfo& info = ShapeTable::known().find(shape);
      m.object.outline = dataset_forecast_object(info, data_folder).outline;
      m.outline_source = info.has_outline() ? "shape table: " + shape : "data folder: butter_outline.csv";
    } else if (kind == "circle") {
      const double r = number_at(ol, "radius_m", "object outline");
      m.object.outline = std::make_shared<const ForecastOutline>(ForecastOutline::ellipse(r, r));
      m.outline_source = "circle";
    } else if (kind == "ellipse") {
      const auto& ax = ol.contains("semi_axes_m") ? ol.at("semi_axes_m") : nlohmann::json();
      if (!ax.is_array() || ax.size() != 2 || !ax[0].is_number() || !ax[1].is_number())
        throw InputError("object outline: 'semi_axes_m' must be [a, b]");
      m.object.outline =
          std::make_shared<const ForecastOutline>(ForecastOutline::ellipse(ax[0].get<double>(), ax[1].get<double>()));
      m.outline_source = "ellipse";
    } else if (kind == "polygon") {
      const auto& vs = ol.contains("vertices_m") ? ol.at("vertices_m") : nlohmann::json();
      if (!vs.is_array()) throw InputError("object outline: 'vertices_m' must be a list of [x, y]");
      std::vector<Eigen::Vector2d> v;
      for (const auto& p : vs) {
        if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
          throw InputError("object outline: every vertex must be [x, y]");
        v.emplace_back(p[0].get<double>(), p[1].get<double>());
      }
      m.object.outline = std::make_shared<const ForecastOutline>(ForecastOutline::polygon(std::move(v)));
      m.outline_source = ol.value("source", std::string("polygon"));
    } else {
      throw InputError("object outline: 'kind' must be shape_table, polygon, circle or ellipse, got '" + kind + "'");
    }
    if (o.contains("limit_surface")) {  // version 4 on; optional (absent: the ellipsoid)
      if (!o.at("limit_surface").is_string())
        throw InputError("object: 'limit_surface' must be \"ellipsoid\" or \"outline\"");
      try {
        m.object.limit_surface = limit_surface_named(o.at("limit_surface").get<std::string>());
      } catch (const InputError& e) {
        throw InputError(std::string("object: 'limit_surface': ") + e.what());
      }
    }
    if (o.contains("pressure_shape")) {  // version 5 on; optional (absent: uniform)
      const auto& ps = o.at("pressure_shape");
      if (!ps.is_object()) throw InputError("object: 'pressure_shape' must be an object");
      const double w = number_at(ps, "rim_weight", "object: pressure_shape");
      const RimWeightRange range = rim_weight_range(m.object.outline->footprint());
      if (m.object.limit_surface != LimitSurfaceKind::Outline && w != 0)
        throw InputError("object: pressure_shape: 'rim_weight' must be 0 with the ellipsoid limit surface, got " +
                         std::to_string(w));
      if (!range.contains(w))
        throw InputError("object: pressure_shape: 'rim_weight' " + std::to_string(w) + " lies outside [" +
                         std::to_string(range.lower) + ", " + std::to_string(range.upper) +
                         "], where the pressure stays non-negative on this outline");
      m.object.pressure_rim_weight = w;
      if (ps.contains("standard_error"))
        m.pressure_rim_weight_standard_error = number_at(ps, "standard_error", "object: pressure_shape");
      m.pressure_rim_weight_pushes = ps.value("learned_from_pushes", 0);
      m.pressure_shape_method = ps.value("method", m.pressure_shape_method);
      if (m.pressure_rim_weight_pushes < 0 || m.pressure_rim_weight_standard_error < 0)
        throw InputError("object: pressure_shape: 'learned_from_pushes' and 'standard_error' must not be negative");
    }
    use_limit_surface(m.object, m.object.limit_surface);
    m.object.validate();
    if (!j.contains("parameters") || !j.at("parameters").is_object())
      throw InputError("'parameters' must be an object");
    Eigen::Vector3d value, se, sd;
    for (int i = 0; i < 3; ++i) {
      const char* name = ForecastParameters::name(i);
      const auto& p = j.at("parameters");
      if (!p.contains(name)) throw InputError(std::string("parameters: '") + name + "' is missing");
      value(i) = number_at(p.at(name), "value", std::string("parameters: ") + name);
      se(i) = p.at(name).contains("standard_error") ? number_at(p.at(name), "standard_error", name) : 0.0;
      sd(i) = p.at(name).contains("push_to_push_sd") ? number_at(p.at(name), "push_to_push_sd", name) : 0.0;
    }
    m.parameters = ForecastParameters::from_vector(value);
    m.parameters.validate();
    m.standard_error = se;
    m.push_to_push_sd = sd;
    if (j.contains("pushes")) {
      if (!j.at("pushes").is_array()) throw InputError("'pushes' must be a list");
      for (const auto& p : j.at("pushes")) {
        PushFit f;
        f.name = p.value("name", std::string());
        Eigen::Vector3d v;
        for (int i = 0; i < 3; ++i) v(i) = number_at(p, ForecastParameters::name(i), "pushes: " + f.name);
        f.parameters = ForecastParameters::from_vector(v);
        f.parameters.validate();
        if (p.contains("descriptor")) {
          const auto& d = p.at("descriptor");
          const auto& cp = d.contains("contact_body_m") ? d.at("contact_body_m") : nlohmann::json();
          if (!cp.is_array() || cp.size() != 2 || !cp[0].is_number() || !cp[1].is_number())
            throw InputError("pushes: " + f.name + ": descriptor 'contact_body_m' must be [x, y]");
          f.descriptor.contact_body_m << cp[0].get<double>(), cp[1].get<double>();
          f.descriptor.angle_rad = number_at(d, "angle_rad", "pushes: " + f.name + ": descriptor");
          const double speed = number_at(d, "speed_m_s", "pushes: " + f.name + ": descriptor");
          require_positive_finite(speed, "pushes: " + f.name + ": descriptor speed_m_s");
          f.descriptor.log_speed = std::log(speed);
        }
        if (p.contains("loo_final_error")) {  // version 7 on; optional (absent: 0)
          const auto& e = p.at("loo_final_error");
          if (!e.is_array() || e.size() != 3)
            throw InputError("pushes: " + f.name + ": 'loo_final_error' must be [along_m, across_m, yaw_rad]");
          for (std::size_t i = 0; i < 3; ++i) {
            if (!e[i].is_number() || !std::isfinite(e[i].get<double>()))
              throw InputError("pushes: " + f.name + ": 'loo_final_error' must be finite numbers");
            f.loo_final_error(static_cast<Eigen::Index>(i)) = e[i].get<double>();
          }
        }
        m.pushes.push_back(f);
      }
    }
    if (j.contains("similarity_bandwidth")) {
      m.similarity_bandwidth = number_at(j, "similarity_bandwidth", "model");
      if (m.similarity_bandwidth < 0) throw InputError("'similarity_bandwidth' must not be negative");
    }
    if (j.contains("similarity_weighting")) {  // version 6 on; optional (absent: one chosen bandwidth)
      const auto& sw = j.at("similarity_weighting");
      if (!sw.is_string() || (sw.get<std::string>() != "averaged" && sw.get<std::string>() != "chosen"))
        throw InputError("'similarity_weighting' must be \"chosen\" or \"averaged\"");
      m.similarity_averaged = sw.get<std::string>() == "averaged";
    }
    if (j.contains("parameter_trend")) {  // version 3 on; optional
      const auto& t = j.at("parameter_trend");
      m.trend.ridge = number_at(t, "ridge", "parameter_trend");
      m.trend.max_shift_log = number_at(t, "max_shift_log", "parameter_trend");
      if (m.trend.ridge < 0 || m.trend.max_shift_log < 0)
        throw InputError("parameter_trend: 'ridge' and 'max_shift_log' must not be negative");
      const auto& rows = t.contains("slope") ? t.at("slope") : nlohmann::json();
      if (!rows.is_array() || rows.size() != 3)
        throw InputError("parameter_trend: 'slope' must be 3 rows of " + std::to_string(kTrendFeatures) + " numbers");
      for (std::size_t i = 0; i < 3; ++i) {
        if (!rows[i].is_array() || rows[i].size() != static_cast<std::size_t>(kTrendFeatures))
          throw InputError("parameter_trend: 'slope' must be 3 rows of " + std::to_string(kTrendFeatures) + " numbers");
        for (std::size_t k = 0; k < static_cast<std::size_t>(kTrendFeatures); ++k) {
          if (!rows[i][k].is_number() || !std::isfinite(rows[i][k].get<double>()))
            throw InputError("parameter_trend: every slope must be a finite number");
          m.trend.slope(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = rows[i][k].get<double>();
        }
      }
    }
    if (j.contains("central")) {
      if (!j.at("central").is_string())
        throw InputError("'central' must be \"ensemble_mean\", \"median\" or \"ensemble_median\"");
      m.central = central_forecast_named(j.at("central").get<std::string>());
    }
    if (j.contains("pusher_friction") && j.at("pusher_friction").is_object())  // optional (absent: fitted)
      m.pusher_friction_method = j.at("pusher_friction").value("method", m.pusher_friction_method);
    if (j.contains("residual_correction")) {  // version 7 on; optional (absent: not applied)
      const auto& rc = j.at("residual_correction");
      if (!rc.is_object() || !rc.contains("applied") || !rc.at("applied").is_boolean())
        throw InputError("residual_correction: 'applied' must be true or false");
      m.residual_correction = rc.at("applied").get<bool>();
      m.residual_shrinkage = number_at(rc, "shrinkage_k", "residual_correction");
      if (!std::isfinite(m.residual_shrinkage) || m.residual_shrinkage < 0)
        throw InputError("residual_correction: 'shrinkage_k' must be finite and not negative");
      m.residual_correction_method = rc.value("method", m.residual_correction_method);
    }
    if (j.contains("regions")) {
      const auto& r = j.at("regions");
      for (const char* key : {"position_scale", "yaw_scale"}) {
        const auto& v = r.contains(key) ? r.at(key) : nlohmann::json();
        if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
          throw InputError(std::string("regions: '") + key + "' must be three numbers (one per third of the push)");
        auto& target = std::string(key) == "position_scale" ? m.regions.position_scale : m.regions.yaw_scale;
        for (std::size_t i = 0; i < 3; ++i) {
          target[i] = v[i].get<double>();
          if (!std::isfinite(target[i]) || target[i] < 0)
            throw InputError(std::string("regions: '") + key + "' must be finite and not negative");
        }
      }
      m.regions.position_floor_m = number_at(r, "position_floor_m", "regions");
      m.regions.yaw_floor_rad = number_at(r, "yaw_floor_rad", "regions");
      m.regions.pushes = r.value("calibration_pushes", 0);
      m.regions.method = r.value("method", m.regions.method);
      if (!(m.regions.position_floor_m >= 0) || !(m.regions.yaw_floor_rad >= 0))
        throw InputError("regions: floors must not be negative");
    }
    if (j.contains("settings")) {
      const auto& s = j.at("settings");
      if (s.contains("rod_radius_m")) m.settings.rod_radius_m = number_at(s, "rod_radius_m", "settings");
      require_positive_finite(m.settings.rod_radius_m, "settings: rod_radius_m");
    }
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("malformed: ") + e.what());
  } catch (const InputError& e) {
    throw fail(e.what());
  }
  return m;
}

ObjectModel read_object_model(const std::filesystem::path& path, const std::filesystem::path& data_folder) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(about(path.string(), "is a folder, not an object model"));
  std::ifstream in(path);
  if (!in) throw InputError(about(path.string(), "cannot read the object model (missing or unreadable)"));
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(about(path.string(), std::string("not valid JSON: ") + e.what()));
  }
  return object_model_from_json(j, path.string(), data_folder);
}

void forecast_distribution_into(const ObjectModel& model, const TipPlan& plan, const Eigen::Vector3d& pose0,
                                const Eigen::VectorXd& times, ForecastDistribution& out, ForecastWorkspace& work) {
  const Eigen::Index n = times.size();
  if (out.mean.rows() != n) out.mean.resize(n, 3);
  if (out.position_spread_m.size() != n) {
    out.position_spread_m.resize(n);
    out.yaw_spread_rad.resize(n);
    out.position_radius_m.resize(n);
    out.yaw_halfwidth_rad.resize(n);
  }
  thread_local std::vector<const PushFit*> members;
  members.clear();
  for (const auto& f : model.pushes) members.push_back(&f);
  if (members.empty()) {
    out.run = forecast_into(model.object, model.parameters, plan, pose0, times, out.mean, model.settings);
    out.position_spread_m.setZero();
    out.yaw_spread_rad.setZero();
  } else {
    central_and_spread(model.object, members, weighting_bandwidth(model), model.trend, plan, pose0, times,
                       model.settings, out.mean, out.position_spread_m, out.yaw_spread_rad, work, out.run,
                       model.central);
    if (model.residual_correction) {
      thread_local std::vector<double> w;
      member_weights(members, weighting_bandwidth(model), describe_push(model.object, plan, pose0), w);
      apply_residual_shift(residual_shift(members, w, model.residual_shrinkage), plan, times, out.mean);
    }
  }
  const RegionCalibration& r = model.regions;
  for (Eigen::Index k = 0; k < n; ++k) {
    const std::size_t stage = static_cast<std::size_t>(RegionCalibration::stage(times(k), plan.end_time_s()));
    out.position_radius_m(k) = r.position_scale[stage] * std::hypot(out.position_spread_m(k), r.position_floor_m);
    out.yaw_halfwidth_rad(k) = r.yaw_scale[stage] * std::hypot(out.yaw_spread_rad(k), r.yaw_floor_rad);
  }
}

ForecastDistribution forecast_distribution(const ObjectModel& model, const TipPlan& plan, const Eigen::Vector3d& pose0,
                                           const Eigen::VectorXd& times, bool keep_members) {
  model.object.validate();
  model.parameters.validate();
  if (!pose0.allFinite()) throw InputError("forecast: start pose must be finite");
  check_plausible_pose(pose0, "forecast: start pose");
  check_tip_starts_outside(model.object, plan, pose0, "forecast");
  for (Eigen::Index k = 1; k < times.size(); ++k)
    if (!(times(k) >= times(k - 1))) throw InputError("forecast: output times must not decrease");
  ForecastDistribution d;
  d.times_s = times;
  ForecastWorkspace work;
  forecast_distribution_into(model, plan, pose0, times, d, work);
  if (keep_members) {
    const PushDescriptor described = describe_push(model.object, plan, pose0);
    for (const auto& f : model.pushes)
      d.members.push_back(forecast_poses(model.object, parameters_along_trend(f, model.trend, described), plan, pose0,
                                         times, model.settings));
  }
  return d;
}

BatchForecast forecast_batch(const ObjectModel& model, const std::vector<TipPlan>& plans,
                             const Eigen::Vector3d& pose0) {
  model.object.validate();
  if (!pose0.allFinite()) throw InputError("forecast: start pose must be finite");
  check_plausible_pose(pose0, "forecast: start pose");
  BatchForecast b;
  const Eigen::Index n = static_cast<Eigen::Index>(plans.size());
  b.final_pose.resize(n, 3);
  b.final_position_radius_m.resize(n);
  b.final_yaw_halfwidth_rad.resize(n);
  b.rest_time_s.resize(n);
  const Eigen::VectorXd final_time = Eigen::VectorXd::Constant(1, std::numeric_limits<double>::infinity());
  ForecastDistribution d;
  ForecastWorkspace work;
  for (Eigen::Index i = 0; i < n; ++i) {
    const TipPlan& plan = plans[static_cast<std::size_t>(i)];
    check_tip_starts_outside(model.object, plan, pose0, "forecast", static_cast<long>(i));
    forecast_distribution_into(model, plan, pose0, final_time, d, work);
    b.final_pose.row(i) = d.mean.row(0);
    b.final_position_radius_m(i) = d.position_radius_m(0);
    b.final_yaw_halfwidth_rad(i) = d.yaw_halfwidth_rad(0);
    b.rest_time_s(i) = d.run.rest_time_s;
  }
  return b;
}

Eigen::VectorXd forecast_output_times(const ObjectModel& model, const TipPlan& plan, const Eigen::Vector3d& pose0,
                                      double step_s, double after_s) {
  require_positive_finite(step_s, "forecast: output step");
  const double end = forecast_rest_time_s(model.object, model.parameters, plan, pose0, model.settings) + after_s;
  // At most a 600 s push at 2500 Hz (PlausibilityLimits): an output step of 1e-9 s would ask for billions of rows.
  constexpr double kMaxRows = 1.5e6;
  if (!(end / step_s < kMaxRows)) {
    char text[160];
    std::snprintf(text, sizeof text, "forecast: an output step of %.3g s over %.3g s gives more than %.3g rows", step_s,
                  end, kMaxRows);
    throw InputError(text);
  }
  const Eigen::Index n = static_cast<Eigen::Index>(std::floor(end / step_s)) + 1;
  Eigen::VectorXd t(n);
  for (Eigen::Index k = 0; k < n; ++k) t(k) = static_cast<double>(k) * step_s;
  return t;
}

}  // namespace pushpred
