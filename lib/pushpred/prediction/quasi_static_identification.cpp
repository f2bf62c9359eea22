#include "pushpred/prediction/quasi_static_identification.hpp"

#include <ceres/ceres.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pushpred/core/error.hpp"
#include "pushpred/core/robust_statistics.hpp"
#include "pushpred/mechanics/support_friction.hpp"
#include "pushpred/prediction/quasi_static_contact.hpp"

namespace pushpred {
namespace {

Eigen::Vector2d perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

/// One contact sample's kinematics: the measured twist against the quasi-static motion, for (mu_p, c, delta) with
/// delta the CoF's offset from the shape table's centroid (body frame). Differentiated automatically
/// (quasi_static_motion_of): difference quotients took five evaluations of the motion per sample and Jacobian.
struct KinematicResidual {
  Eigen::Vector2d point_from_centre, n, tip_velocity, centre_velocity, centroid;
  Eigen::Matrix2d rotation;  ///< R(yaw), body to world
  double omega = 0, c0 = 0, sigma = 1;
  template <typename T>
  bool operator()(const T* mu_p, const T* c, const T* delta, T* r) const {
    const T bx = centroid.x() + delta[0], by = centroid.y() + delta[1];
    const T ax = rotation(0, 0) * bx + rotation(0, 1) * by, ay = rotation(1, 0) * bx + rotation(1, 1) * by;
    const Eigen::Matrix<T, 2, 1> contact_from_cof(point_from_centre.x() - ax, point_from_centre.y() - ay);
    const BasicQuasiStaticMotion<T> m = quasi_static_motion_of<T>(contact_from_cof, n, tip_velocity, mu_p[0], c[0]);
    r[0] = (centre_velocity.x() - omega * ay - m.velocity_m_s.x()) / sigma;
    r[1] = (centre_velocity.y() + omega * ax - m.velocity_m_s.y()) / sigma;
    r[2] = c0 * (omega - m.omega_rad_s) / sigma;
    return true;
  }
};

/// A residual with the CoF at the shape table's centroid (delta = 0, not a parameter): the default, where the offset
/// is not identified. The same values as Residual's with delta held at zero, with a smaller Jet and one parameter
/// block fewer per sample.
template <class Residual>
struct AtCentroid {
  Residual residual;
  template <typename T>
  bool operator()(const T* a, const T* b, T* r) const {
    const T zero[2] = {T(0), T(0)};
    return residual(a, b, zero, r);
  }
};

/// One sliding sample's wrench on the ellipsoidal limit surface (mechanics/support_friction.hpp):
/// sqrt(|f|^2 + (m / c)^2) = mu_s m g, m about the CoF.
struct ForceResidual {
  Eigen::Vector2d force, centroid;
  Eigen::Matrix2d rotation;  ///< R(yaw), body to world
  double torque_about_centre = 0, weight = 0, sigma = 1;
  template <typename T>
  bool operator()(const T* c, const T* mu_s, const T* delta, T* r) const {
    const T bx = T(centroid.x()) + delta[0], by = T(centroid.y()) + delta[1];
    const T ax = rotation(0, 0) * bx + rotation(0, 1) * by, ay = rotation(1, 0) * bx + rotation(1, 1) * by;
    const T m = T(torque_about_centre) - (ax * T(force.y()) - ay * T(force.x()));
    r[0] = (ellipsoidal_limit_surface_force(T(force.x()), T(force.y()), m, c[0]) - mu_s[0] * T(weight)) / T(sigma);
    return true;
  }
};

struct PriorComponent {
  int axis = 0;
  double mean = 0, sigma = 1;
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    r[0] = (theta[axis] - T(mean)) / T(sigma);
    return true;
  }
};

struct PriorResidual {
  double mean = 0, sigma = 1;
  template <typename T>
  bool operator()(const T* theta, T* r) const {
    r[0] = (theta[0] - T(mean)) / T(sigma);
    return true;
  }
};

}  // namespace

const std::array<const char*, 4>& QuasiStaticIdentification::names() {
  static const std::array<const char*, 4> n{"pusher_friction", "torque_ratio_m", "support_friction", "contact_offset_m"};
  return n;
}

namespace {

/// The covariance options of the plain fit (no prior): dense SVD, a rank-deficient Jacobian is an error (null space
/// rank 0) below a reciprocal condition number of 1e-14. Its standard deviations and its correlations use the same.
ceres::Covariance::Options plain_fit_covariance_options() {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.null_space_rank = 0;
  co.min_reciprocal_condition_number = 1e-14;
  return co;
}

/// The fit's covariance of (mu_p, c, mu_s): `standard_deviation` squared on the diagonal (as the fit reported it),
/// and off it the covariances Ceres computes at the optimum between the blocks that are not `fixed`, with `options`
/// (those the fit's own standard deviations came from). A separate computation, so that the standard deviations the
/// fit reported stay exactly what they were; zero off the diagonal where it cannot be computed.
Eigen::Matrix3d fit_covariance_of(ceres::Problem& problem, double* const blocks[3], const bool fixed[3],
                                  const Eigen::Vector3d& standard_deviation, const ceres::Covariance::Options& options) {
  Eigen::Matrix3d covariance = standard_deviation.cwiseAbs2().asDiagonal();
  std::vector<std::pair<const double*, const double*>> pairs;
  std::vector<std::pair<int, int>> indices;
  for (int p = 0; p < 3; ++p)
    for (int q = p + 1; q < 3; ++q)
      if (!fixed[p] && !fixed[q]) {
        pairs.emplace_back(blocks[p], blocks[q]);
        indices.emplace_back(p, q);
      }
  if (pairs.empty()) return covariance;
  ceres::Covariance off_diagonal(options);
  if (!off_diagonal.Compute(pairs, &problem)) return covariance;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    double value = 0;
    off_diagonal.GetCovarianceBlock(pairs[k].first, pairs[k].second, &value);
    const auto [p, q] = indices[k];
    covariance(p, q) = covariance(q, p) = value;
  }
  return covariance;
}

/// Where nothing has been identified yet: every parameter at its default, saying so.
QuasiStaticIdentification nothing_identified(const QuasiStaticParameters& defaults, long intervals) {
  QuasiStaticIdentification id;
  id.parameters = defaults;
  id.intervals = intervals;
  for (auto& s : id.sources) s = "default: no contact sample identified yet";
  return id;
}

/// The contact offset of the identified samples: the upper median of their rod-outline gaps, with a robust standard
/// error (1.4826 times the median absolute deviation over sqrt(n)), so that a few samples off the tracked outline do
/// not move it. predict_quasi_static_phase replaces it by the gap at the phase's start where the rod touches there.
void identify_contact_offset(const std::vector<double>& gaps_m, QuasiStaticIdentification& id) {
  id.parameters.contact_offset_m = upper_median(gaps_m);
  std::vector<double> dev;
  for (double g : gaps_m) dev.push_back(std::abs(g - id.parameters.contact_offset_m));
  id.std(3) = 1.4826 * upper_median(dev) / std::sqrt(static_cast<double>(gaps_m.size()));
  id.sources[3] = "identified";
}

/// Too few samples for a fit: mu_p, c and mu_s keep their defaults, and their sources say how few there were.
void keep_defaults_for_too_few_samples(QuasiStaticIdentification& id, int min_samples) {
  char why[160];
  std::snprintf(why, sizeof why, "default: %ld contact samples with a moving tip, fewer than %d", id.kinematic_samples,
                min_samples);
  for (int p = 0; p < 3; ++p) id.sources[static_cast<size_t>(p)] = why;
}

ceres::Problem::Options problem_options() {
  ceres::Problem::Options o;
  o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;  // the Fit's one Huber loss
  return o;
}

ceres::Solver::Options solver_options() {
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = 100;
  // No projected line search after each successful step of the bounded problem (Ceres does one by default): it
  // cost a third of the fit for no change beyond the solver's tolerances (docs/performance.md).
  solver.max_num_line_search_step_size_iterations = 0;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  return solver;
}

/// The source of a parameter fitted with the prior: "default: ..." where its posterior standard deviation stays
/// near the prior's, so that a value the prior alone holds is not mistaken for a measured one.
std::string source_under_prior(double posterior_std, double prior_std, double dominated_fraction,
                               bool mu_p_without_sliding) {
  if (!(posterior_std > dominated_fraction * prior_std)) return "identified";
  char why[200];
  std::snprintf(why, sizeof why, "default: the data add little to the prior (posterior std %.2g of the prior's %.2g)%s",
                posterior_std, prior_std, mu_p_without_sliding ? "; no sample slid, so mu_p is only bounded below" : "");
  return why;
}

/// A parameter the plain fit holds at its default from now on, and why (parameter -1: none).
struct Undetermined {
  int parameter = -1;
  std::string reason;
};

/// The free parameter the data leave without sensitivity: its column of the Jacobian, scaled by its value, at most
/// 1e-6 of the largest (the smallest such). Such a column makes the information J^T J (near) singular: with every
/// sample sticking, mu_p is only bounded below.
Undetermined insensitive_parameter(ceres::Problem& problem, double* const blocks[3], const bool fixed[3]) {
  ceres::Problem::EvaluateOptions eo;
  for (int p = 0; p < 3; ++p)
    if (!fixed[p]) eo.parameter_blocks.push_back(blocks[p]);
  ceres::CRSMatrix jacobian;
  problem.Evaluate(eo, nullptr, nullptr, nullptr, &jacobian);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(jacobian.num_rows, jacobian.num_cols);
  for (int r = 0; r < jacobian.num_rows; ++r)
    for (int k = jacobian.rows[static_cast<size_t>(r)]; k < jacobian.rows[static_cast<size_t>(r) + 1]; ++k)
      J(r, jacobian.cols[static_cast<size_t>(k)]) = jacobian.values[static_cast<size_t>(k)];
  int col = 0;
  for (int p = 0; p < 3; ++p)
    if (!fixed[p]) J.col(col++) *= std::max(std::abs(*blocks[p]), 1e-12);
  const Eigen::VectorXd column_norm = J.colwise().norm();
  Undetermined u;
  double smallest = 1e-6 * column_norm.maxCoeff();
  col = 0;
  for (int p = 0; p < 3; ++p) {
    if (fixed[p]) continue;
    if (!(column_norm(col) > smallest)) {
      u.parameter = p;
      smallest = column_norm(col);
    }
    ++col;
  }
  if (u.parameter >= 0)
    u.reason = u.parameter == 0 ? "default: every contact sample stuck, so mu_p is only bounded below"
                                : "default: the data do not determine it (no sensitivity)";
  return u;
}

/// The free parameter the data determine worst, where its standard deviation exceeds half its value (the largest
/// such ratio), or the last free one where the covariance is singular. `stdev` receives the free parameters'
/// standard deviations where the covariance exists: they are the fit's if every parameter is determined.
Undetermined least_determined_parameter(ceres::Problem& problem, double* const blocks[3], const bool fixed[3],
                                        Eigen::Vector3d& stdev) {
  ceres::Covariance covariance(plain_fit_covariance_options());
  std::vector<std::pair<const double*, const double*>> pairs;
  for (int p = 0; p < 3; ++p)
    if (!fixed[p]) pairs.emplace_back(blocks[p], blocks[p]);
  Undetermined u;
  if (!covariance.Compute(pairs, &problem)) {
    for (int p = 0; p < 3; ++p)
      if (!fixed[p]) u.parameter = p;
    u.reason = "default: the data do not determine it (singular covariance)";
    return u;
  }
  double worst_ratio = 0.5;
  for (int p = 0; p < 3; ++p) {
    if (fixed[p]) continue;
    double var = 0;
    covariance.GetCovarianceBlock(blocks[p], blocks[p], &var);
    stdev(p) = std::sqrt(std::max(0.0, var));
    const double ratio = stdev(p) / std::max(std::abs(*blocks[p]), 1e-12);
    if (!std::isfinite(ratio) || ratio > worst_ratio) {
      u.parameter = p;
      worst_ratio = std::isfinite(ratio) ? ratio : 1e300;
    }
  }
  if (u.parameter < 0) return u;
  char why[160];
  std::snprintf(why, sizeof why, "default: the data do not determine it (fit %.3g, std %.2g)", *blocks[u.parameter],
                stdev(u.parameter));
  u.reason = why;
  return u;
}

/// identify()'s fit: one Ceres problem over the contact samples, of mu_p and c from the kinematics and of c and mu_s
/// from the force (they share c, so they are fitted together), optionally with delta, the CoF's offset. A template
/// only because the estimator's Sample is private to it: identify() names it.
template <class Sample>
class Fit {
 public:
  Fit(const std::vector<Sample>& samples, const QuasiStaticIdentificationOptions& options,
      const QuasiStaticParameters& defaults, const SynchronisedPush& push, QuasiStaticIdentification& id)
      : samples_(samples),
        options_(options),
        defaults_(defaults),
        centroid_(push.shape.centroid_m),
        id_(id),
        uniform_torque_ratio_m_(defaults.torque_ratio_m),
        weight_(push.shape.mass_kg * defaults.gravity_m_s2),
        centre_fixed_(!options.use_prior || !(options.prior_centre_offset_std_m > 0)),
        mu_p_(defaults.pusher_friction),
        c_(defaults.torque_ratio_m),
        mu_s_(defaults.support_friction) {
    problem_.AddParameterBlock(&mu_p_, 1);
    problem_.AddParameterBlock(&c_, 1);
    problem_.AddParameterBlock(&mu_s_, 1);
    problem_.AddParameterBlock(delta_, 2);
    if (centre_fixed_) problem_.SetParameterBlockConstant(delta_);
  }

  /// The residuals of every sample whose tip pushes into the object; counts them in `id`.
  void add_samples() {
    for (const Sample& s : samples_) {
      if (!pushes_into_object(s)) continue;
      add_kinematic_residual(s);
      ++id_.kinematic_samples;
      // Only a sliding object's wrench is on the limit surface.
      if (s.moving) {
        add_force_residual(s);
        ++id_.force_samples;
      }
    }
  }

  void solve_with_prior() {
    bound_to_physical_ranges();
    const double prior_std[3] = {options_.prior_pusher_friction_std,
                                 options_.prior_torque_ratio_fraction * uniform_torque_ratio_m_,
                                 options_.prior_support_friction_std};
    add_prior(prior_std);
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options(), &problem_, &summary);
    // Counted before the sources are written: mu_p's says whether any sample slid.
    count_sliding_samples();
    read_posterior(prior_std);
    record_parameters();
    id_.centre_offset_m = Eigen::Vector2d(delta_[0], delta_[1]);
    if (id_.sliding_samples == 0 && id_.sources[0] == "identified")
      id_.sources[0] = "default: no sample slid, so mu_p is only bounded below";
  }

  /// Without the prior, the value the fit gives a parameter the data leave undetermined is arbitrary: such a
  /// parameter is held at its physical default instead (its source says why), and the others are fitted again.
  void solve_dropping_undetermined() {
    double* blocks[3] = {&mu_p_, &c_, &mu_s_};
    const double defaults[3] = {defaults_.pusher_friction, defaults_.torque_ratio_m, defaults_.support_friction};
    bool fixed[3] = {false, false, id_.force_samples == 0};
    std::string reason[3] = {"", "", "default: the object never slid while the sensor read contact"};
    if (fixed[2]) problem_.SetParameterBlockConstant(&mu_s_);
    bound_to_physical_ranges();
    Eigen::Vector3d stdev = Eigen::Vector3d::Zero();
    for (int attempt = 0; attempt < 4; ++attempt) {
      ceres::Solver::Summary summary;
      ceres::Solve(solver_options(), &problem_, &summary);
      if (fixed[0] && fixed[1] && fixed[2]) break;
      Undetermined u = insensitive_parameter(problem_, blocks, fixed);
      if (u.parameter < 0) u = least_determined_parameter(problem_, blocks, fixed, stdev);
      if (u.parameter < 0) break;
      const int p = u.parameter;
      reason[p] = std::move(u.reason);
      fixed[p] = true;
      *blocks[p] = defaults[p];
      stdev(p) = 0;
      problem_.SetParameterBlockConstant(blocks[p]);
    }
    record_parameters();
    for (int p = 0; p < 3; ++p) {
      id_.std(p) = fixed[p] ? 0.0 : stdev(p);
      id_.sources[static_cast<size_t>(p)] = fixed[p] ? reason[p] : "identified";
    }
    id_.fit_covariance = fit_covariance_of(problem_, blocks, fixed, id_.std.head<3>(), plain_fit_covariance_options());
    count_sliding_samples();
  }

 private:
  /// A tip too slow, or moving off the object, carries no information on how the push moves it.
  bool pushes_into_object(const Sample& s) const {
    return !(s.tip_velocity_m_s.norm() < options_.min_tip_speed_m_s) && s.inward_normal.dot(s.tip_velocity_m_s) > 0;
  }

  void add_kinematic_residual(const Sample& s) {
    const KinematicResidual k{s.point_from_centre_m,
                              s.inward_normal,
                              s.tip_velocity_m_s,
                              s.centre_velocity_m_s,
                              centroid_,
                              Eigen::Rotation2Dd(s.yaw_rad).toRotationMatrix(),
                              s.omega_rad_s,
                              uniform_torque_ratio_m_,
                              options_.velocity_noise_m_s};
    if (centre_fixed_) {
      problem_.AddResidualBlock(new ceres::AutoDiffCostFunction<AtCentroid<KinematicResidual>, 3, 1, 1>(
                                    new AtCentroid<KinematicResidual>{k}),
                                &huber_, &mu_p_, &c_);
    } else {
      problem_.AddResidualBlock(
          new ceres::AutoDiffCostFunction<KinematicResidual, 3, 1, 1, 2>(new KinematicResidual(k)),
          &huber_, &mu_p_, &c_, delta_);
    }
  }

  void add_force_residual(const Sample& s) {
    const ForceResidual f{s.force_vector_N, centroid_, Eigen::Rotation2Dd(s.yaw_rad).toRotationMatrix(),
                          s.torque_about_centre_Nm, weight_, options_.force_noise_N};
    if (centre_fixed_)
      problem_.AddResidualBlock(
          new ceres::AutoDiffCostFunction<AtCentroid<ForceResidual>, 1, 1, 1>(new AtCentroid<ForceResidual>{f}),
          &huber_, &c_, &mu_s_);
    else
      problem_.AddResidualBlock(new ceres::AutoDiffCostFunction<ForceResidual, 1, 1, 1, 2>(new ForceResidual(f)),
                                &huber_, &c_, &mu_s_, delta_);
  }

  // Bounds that only exclude the unphysical: dry friction between the rod, the objects and the supports of such rigs
  // lies well inside 0.02-1.5 (the dataset's supports and objects measure about 0.1-0.5); c, the limit surface's
  // torque ratio, runs from 0 (all pressure at the CoF) to the footprint's largest radius, and the pressure of a
  // rigid object on a flat support keeps it within a factor of about 3 of its uniform-pressure value c0.
  void bound_to_physical_ranges() {
    problem_.SetParameterLowerBound(&mu_p_, 0, 0.02);
    problem_.SetParameterUpperBound(&mu_p_, 0, 1.5);
    problem_.SetParameterLowerBound(&c_, 0, 0.3 * uniform_torque_ratio_m_);
    problem_.SetParameterUpperBound(&c_, 0, 3.0 * uniform_torque_ratio_m_);
    problem_.SetParameterLowerBound(&mu_s_, 0, 0.02);
    problem_.SetParameterUpperBound(&mu_s_, 0, 1.5);
  }

  /// A Gaussian prior about the defaults, so that a few samples inform without overturning physics.
  void add_prior(const double prior_std[3]) {
    const double prior_mean[3] = {defaults_.pusher_friction, uniform_torque_ratio_m_, defaults_.support_friction};
    double* theta[3] = {&mu_p_, &c_, &mu_s_};
    if (options_.prior_centre_offset_std_m > 0) {
      for (int axis = 0; axis < 2; ++axis)
        problem_.AddResidualBlock(new ceres::AutoDiffCostFunction<PriorComponent, 1, 2>(
                                      new PriorComponent{axis, 0.0, options_.prior_centre_offset_std_m}),
                                  nullptr, delta_);
    }
    for (int p = 0; p < 3; ++p) {
      problem_.AddResidualBlock(
          new ceres::AutoDiffCostFunction<PriorResidual, 1, 1>(new PriorResidual{prior_mean[p], prior_std[p]}),
          nullptr, theta[p]);
    }
  }

  /// The posterior's standard deviations, correlations and sources from one covariance computation (a second, as
  /// fit_covariance_of makes, would repeat the dense SVD for the same values). Without a covariance, a parameter
  /// keeps its prior's standard deviation.
  void read_posterior(const double prior_std[3]) {
    const double* theta[3] = {&mu_p_, &c_, &mu_s_};
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    ceres::Covariance covariance(co);
    std::vector<std::pair<const double*, const double*>> pairs;
    for (const double* b : theta) pairs.emplace_back(b, b);
    for (int p = 0; p < 3; ++p)
      for (int q = p + 1; q < 3; ++q) pairs.emplace_back(theta[p], theta[q]);
    if (!centre_fixed_) pairs.emplace_back(delta_, delta_);
    const bool have_covariance = covariance.Compute(pairs, &problem_);
    if (!centre_fixed_) read_offset_posterior(covariance, have_covariance);
    for (int p = 0; p < 3; ++p) {
      double var = prior_std[p] * prior_std[p];
      if (have_covariance) covariance.GetCovarianceBlock(theta[p], theta[p], &var);
      id_.std(p) = std::sqrt(std::max(0.0, var));
      id_.sources[static_cast<size_t>(p)] = source_under_prior(
          id_.std(p), prior_std[p], options_.prior_dominated_fraction, p == 0 && id_.sliding_samples == 0);
    }
    id_.fit_covariance = id_.std.head<3>().cwiseAbs2().asDiagonal();
    if (!have_covariance) return;
    for (int p = 0; p < 3; ++p)
      for (int q = p + 1; q < 3; ++q) {
        double value = 0;
        covariance.GetCovarianceBlock(theta[p], theta[q], &value);
        id_.fit_covariance(p, q) = id_.fit_covariance(q, p) = value;
      }
  }

  void read_offset_posterior(const ceres::Covariance& covariance, bool have_covariance) {
    double cov[4] = {0, 0, 0, 0};
    if (have_covariance) covariance.GetCovarianceBlock(delta_, delta_, cov);
    id_.centre_offset_std_m = Eigen::Vector2d(std::sqrt(std::max(0.0, cov[0])), std::sqrt(std::max(0.0, cov[3])));
    id_.centre_offset_source =
        id_.centre_offset_std_m.maxCoeff() > options_.prior_dominated_fraction * options_.prior_centre_offset_std_m
            ? "default: the data add little to the prior"
            : "identified";
  }

  void record_parameters() {
    id_.parameters.pusher_friction = mu_p_;
    id_.parameters.torque_ratio_m = c_;
    id_.parameters.support_friction = mu_s_;
  }

  /// Samples the fitted model has sliding along the contact: what determines mu_p.
  void count_sliding_samples() {
    id_.sliding_samples = 0;
    for (const Sample& s : samples_) {
      if (!pushes_into_object(s)) continue;
      const QuasiStaticMotion m =
          quasi_static_motion(s.contact_from_cof_m, s.inward_normal, s.tip_velocity_m_s, mu_p_, c_);
      if (m.mode == ContactMode::SlidingLeft || m.mode == ContactMode::SlidingRight) ++id_.sliding_samples;
    }
  }

  const std::vector<Sample>& samples_;
  const QuasiStaticIdentificationOptions& options_;
  const QuasiStaticParameters& defaults_;
  const Eigen::Vector2d centroid_;
  QuasiStaticIdentification& id_;
  const double uniform_torque_ratio_m_, weight_;
  /// The CoF stays at the shape table's centroid unless the prior gives its offset a spread.
  const bool centre_fixed_;
  double mu_p_, c_, mu_s_;
  double delta_[2] = {0, 0};
  // One loss shared by every residual (declared before the problem, which refers to it): a loss per residual
  // block was an allocation per sample and fit.
  ceres::HuberLoss huber_{1.0};
  ceres::Problem problem_{problem_options()};
};

}  // namespace

QuasiStaticEstimator::QuasiStaticEstimator(QuasiStaticIdentificationOptions options) : options_(std::move(options)) {
  if (!(options_.difference_half_window_s > 0) || !(options_.velocity_noise_m_s > 0) || !(options_.force_noise_N > 0) ||
      !(options_.min_tip_speed_m_s >= 0) || !(options_.min_object_speed_m_s >= 0) || options_.min_samples < 1)
    throw InputError("quasi-static identification: windows, noise levels and sample counts must be positive");
}

void QuasiStaticEstimator::reset(const SynchronisedPush& push) {
  push_ = &push;
  samples_.clear();
  gaps_m_.clear();
  intervals_ = 0;
  defaults_ = options_.defaults;
  const bool outline_known = has_listed_outline(push.shape);
  outline_ = outline_known ? shape_outline(push.shape) : nullptr;
  if (!(defaults_.torque_ratio_m > 0) || defaults_.torque_ratio_m == QuasiStaticParameters().torque_ratio_m) {
    defaults_.torque_ratio_m =
        outline_known ? uniform_pressure_torque_ratio(make_footprint(Outline(push.shape)), push.shape.centroid_m)
                      : 0.94 * std::sqrt(push.shape.inertia_kgm2 / push.shape.mass_kg);
  }
}

void QuasiStaticEstimator::add_interval(const TimeInterval& interval) {
  if (!push_) throw InputError("quasi-static identification: reset with a push before adding intervals");
  const SynchronisedPush& push = *push_;
  if (!(interval.t1_s > interval.t0_s) || interval.t0_s < -1e-9 || interval.t1_s > push.duration_s() + 1e-9)
    throw InputError(about(push.source, "quasi-static identification: interval outside the push"));
  ++intervals_;
  const Eigen::Index h = std::max<Eigen::Index>(1, std::lround(options_.difference_half_window_s * push.rate_hz));
  const Eigen::Index lookback = static_cast<Eigen::Index>(std::lround(0.1 * push.rate_hz));
  Eigen::Index i0 = push.index_at(interval.t0_s), i1 = push.index_at(interval.t1_s);
  if (push.t_s(i1) > interval.t1_s + 1e-9) --i1;
  const Eigen::Index settle = static_cast<Eigen::Index>(std::lround(options_.contact_settling_s * push.rate_hz));
  for (Eigen::Index i = i0; i <= i1; ++i) {
    if (!push.in_contact[static_cast<size_t>(i)]) continue;
    // Not within the settling time of a contact's onset: the object accelerates from rest there, which the
    // quasi-static model leaves out.
    bool settled = true;
    for (Eigen::Index j = std::max<Eigen::Index>(0, i - settle); j < i && settled; ++j)
      settled = push.in_contact[static_cast<size_t>(j)] != 0;
    if (!settled || i < settle) continue;
    // Central differences inside the interval only: identification never reads beyond what has been measured.
    const Eigen::Index a = std::max(i0, i - h), b = std::min(i1, i + h);
    if (b <= a) continue;
    const double dt = push.t_s(b) - push.t_s(a);
    const Eigen::Vector2d tip_velocity = (push.tip_m.row(b) - push.tip_m.row(a)).transpose() / dt;
    const Eigen::Rotation2Dd R(push.pose(i, 2));
    Sample s;
    s.omega_rad_s = (push.pose(b, 2) - push.pose(a, 2)) / dt;
    const Eigen::Vector2d centre_velocity = (push.pose.row(b) - push.pose.row(a)).head<2>().transpose() / dt;
    s.object_velocity_m_s = centre_velocity + s.omega_rad_s * perp(R * push.shape.centroid_m);
    s.tip_velocity_m_s = tip_velocity;
    Eigen::Vector2d point_body, normal_out_body;
    if (outline_) {
      const Outline::Closest c = outline_->closest(body_frame_tip(push, i));
      gaps_m_.push_back(c.signed_distance_m - kPusherRadius_m);
      point_body = c.point_m;
      normal_out_body = c.normal;
    } else {
      if (!(tip_velocity.norm() > 0)) continue;
      normal_out_body = local_outward_normal(push, i, tip_velocity.normalized(), lookback);
      point_body = body_frame_tip(push, i) - kPusherRadius_m * normal_out_body;
    }
    s.inward_normal = -(R * normal_out_body);
    s.point_from_centre_m = R * point_body;
    s.centre_velocity_m_s = centre_velocity;
    s.yaw_rad = push.pose(i, 2);
    s.contact_from_cof_m = R * (point_body - push.shape.centroid_m);
    s.moving = s.object_velocity_m_s.norm() > options_.min_object_speed_m_s;
    s.force_vector_N = push.force_N.row(i).transpose();
    s.torque_about_centre_Nm = push.torque_about_centre_Nm(i);
    samples_.push_back(s);
  }
}

void QuasiStaticEstimator::reset() {
  push_ = nullptr;
  outline_ = nullptr;
  samples_.clear();
  gaps_m_.clear();
  intervals_ = 0;
}

void QuasiStaticEstimator::add_interval(const IdentificationInterval& interval) {
  if (!push_) reset(interval.push);
  // The estimator keeps a pointer to its push (the samples and the outline are of that push), so one push at a time.
  if (push_ != &interval.push)
    throw InputError(about(interval.push.source, "quasi-static identification: an interval of another push than " +
                                                     push_->source + "; reset() before identifying a new push"));
  add_interval(interval.interval);
}

std::string QuasiStaticEstimator::not_ready_reason() const {
  return push_ ? "" : "no push yet: feed an interval of one (or reset(push))";
}

ParameterEstimate QuasiStaticEstimator::current_estimate() const {
  const QuasiStaticIdentification id = identify();
  ParameterEstimate e;
  e.estimator = name();
  for (const char* n : QuasiStaticIdentification::names()) e.names.emplace_back(n);
  e.units = {"", "m", "", "m"};
  e.value = Eigen::Vector4d(id.parameters.pusher_friction, id.parameters.torque_ratio_m, id.parameters.support_friction,
                            id.parameters.contact_offset_m);
  e.covariance = Eigen::MatrixXd::Zero(4, 4);
  e.covariance.topLeftCorner<3, 3>() = id.fit_covariance;
  e.covariance(3, 3) = id.std(3) * id.std(3);
  e.sources.assign(id.sources.begin(), id.sources.end());
  e.samples = id.kinematic_samples;
  e.intervals = id.intervals;
  return e;
}

QuasiStaticIdentification QuasiStaticEstimator::identify() const {
  QuasiStaticIdentification id = nothing_identified(defaults_, intervals_);
  if (!push_) return id;
  if (outline_ && !gaps_m_.empty()) identify_contact_offset(gaps_m_, id);
  Fit<Sample> fit(samples_, options_, defaults_, *push_, id);
  fit.add_samples();
  if (id.kinematic_samples < options_.min_samples) {
    keep_defaults_for_too_few_samples(id, options_.min_samples);
    return id;
  }
  if (options_.use_prior)
    fit.solve_with_prior();
  else
    fit.solve_dropping_undetermined();
  return id;
}

}  // namespace pushpred
