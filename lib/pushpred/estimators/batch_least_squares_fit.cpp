#include "pushpred/estimators/batch_least_squares_fit.hpp"

#include <ceres/autodiff_cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

/// One sample of one channel, divided by the channel's scale s: r / s with r = d - (beta u + eps).
struct RelationResidual {
  RelationResidual(double u, double d, double inv_scale) : u(u), d(d), inv_scale(inv_scale) {}
  template <typename T>
  bool operator()(const T* x, T* r) const {
    r[0] = (T(d) - x[0] * T(u) - x[1]) * inv_scale;
    return true;
  }
  double u, d, inv_scale;
};

/// One sample of all three channels, each residual divided by its channel's weight scale sqrt(3) s_c, so that
/// the block's squared norm is the mean over the channels of (r_c / s_c)^2.
struct JointRelationResidual {
  template <typename T>
  bool operator()(const T* x0, const T* x1, const T* x2, T* r) const {
    r[0] = (T(d[0]) - x0[0] * T(u[0]) - x0[1]) * inv_scale[0];
    r[1] = (T(d[1]) - x1[0] * T(u[1]) - x1[1]) * inv_scale[1];
    r[2] = (T(d[2]) - x2[0] * T(u[2]) - x2[1]) * inv_scale[2];
    return true;
  }
  double u[3], d[3], inv_scale[3];
};

std::unique_ptr<ceres::LossFunction> make_loss(RobustLoss loss, double scale) {
  switch (loss) {
    case RobustLoss::Huber: return std::make_unique<ceres::HuberLoss>(scale);
    case RobustLoss::Cauchy: return std::make_unique<ceres::CauchyLoss>(scale);
    case RobustLoss::None: break;
  }
  return nullptr;
}

/// rho(s), rho'(s), rho''(s) of a Ceres loss at s = |f|^2 (the quadratic loss for none).
void evaluate_loss(const ceres::LossFunction* loss, double s, double rho[3]) {
  if (loss) {
    loss->Evaluate(s, rho);
  } else {
    rho[0] = s;
    rho[1] = 1.0;
    rho[2] = 0.0;
  }
}

/// Tuning constants for 95 % asymptotic efficiency under Gaussian residuals (Huber 1981; Holland & Welsch 1977).
double efficiency_constant(RobustLoss loss) { return loss == RobustLoss::Cauchy ? 2.385 : 1.345; }

/// 1.4826 x the median absolute deviation from the median: the residual std for Gaussian residuals.
double robust_std(const Eigen::VectorXd& r) {
  std::vector<double> v(r.data(), r.data() + r.size());
  const auto median = [](std::vector<double>& w) {
    const std::size_t m = w.size() / 2;
    std::nth_element(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(m), w.end());
    double med = w[m];
    if (w.size() % 2 == 0) med = 0.5 * (med + *std::max_element(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(m)));
    return med;
  };
  const double centre = median(v);
  for (double& x : v) x = std::abs(x - centre);
  return 1.4826 * median(v);
}

/// The channel's data and the pieces of its fit that do not depend on the loss.
struct ChannelFit {
  ChannelFit(const std::vector<double>& u_data, const std::vector<double>& d_data)
      : u(u_data.data(), static_cast<Eigen::Index>(u_data.size())),
        d(d_data.data(), static_cast<Eigen::Index>(d_data.size())) {}
  Eigen::Map<const Eigen::VectorXd> u, d;
  Eigen::Matrix2d inverse_information;  ///< (H^T H)^-1 from the QR factor of H
  Eigen::Vector2d least_squares;        ///< the closed-form least-squares (beta, eps)
  double least_squares_std = 0;
  Eigen::Vector2d x;                    ///< the Ceres parameter block
  double scale = 1;                     ///< loss scale (per channel) or weight scale (joint)
};

/// The names of the channels whose input does not vary enough to identify beta and eps ("" when none).
std::string unidentifiable_channels(const std::vector<ChannelFit>& ch, Eigen::Index n) {
  std::string flat;
  for (int c = 0; c < 3; ++c) {
    Eigen::Matrix2d a;
    a << ch[c].u.squaredNorm(), ch[c].u.sum(), ch[c].u.sum(), static_cast<double>(n);
    if (!relation_identifiable(a)) flat += std::string(flat.empty() ? "" : ", ") + relation_channel_name(c);
  }
  return flat;
}

/// Closed-form least squares: the start of robust fits, the source of automatic scales, and (H^T H)^-1. The plain
/// fit starts from `previous` (when there is one) and is scaled by the least-squares residual std, which does not
/// move its minimum.
void fit_least_squares(std::vector<ChannelFit>& ch, Eigen::Index n, const BatchFitOptions& options,
                       const RelationParameters* previous) {
  Eigen::MatrixX2d h(n, 2);
  h.col(1).setOnes();
  for (int c = 0; c < 3; ++c) {
    ChannelFit& f = ch[c];
    h.col(0) = f.u;
    const Eigen::HouseholderQR<Eigen::MatrixX2d> qr(h);
    f.least_squares = qr.solve(f.d);
    f.least_squares_std = std::sqrt((f.d - h * f.least_squares).squaredNorm() / static_cast<double>(n - 2));
    const Eigen::Matrix2d r = qr.matrixQR().topRows<2>().triangularView<Eigen::Upper>();
    const Eigen::Matrix2d r_inv = r.triangularView<Eigen::Upper>().solve(Eigen::Matrix2d::Identity());
    f.inverse_information = r_inv * r_inv.transpose();
    if (options.loss == RobustLoss::None) {
      f.x = previous ? Eigen::Vector2d(previous->beta(c), previous->eps(c)) : Eigen::Vector2d::Zero();
      f.scale = f.least_squares_std > 0 ? f.least_squares_std : 1.0;
    } else {
      f.x = f.least_squares;
      f.scale = options.loss_scale(c);
    }
  }
}

/// d - (beta u + eps) at the channel's current parameters.
Eigen::VectorXd residuals(const ChannelFit& f) { return f.d.array() - f.x(0) * f.u.array() - f.x(1); }

double automatic_scale(const ChannelFit& f, Eigen::Index n, RobustLoss loss) {
  const Eigen::VectorXd r = residuals(f);
  double s = robust_std(r);
  if (!(s > 0)) s = std::sqrt(r.squaredNorm() / static_cast<double>(n - 2));  // most samples fit exactly
  if (!(s > 0)) s = 1.0;                                                      // all do: any scale will do
  return efficiency_constant(loss) * s;
}

/// Residuals enter Ceres divided by their channel's scale (times sqrt 3 jointly), so the loss acts at 1.
double block_scale(const BatchFitOptions& options) { return options.joint ? std::sqrt(3.0) : 1.0; }

/// What a solve names in its error and where it counts its iterations.
struct SolveContext {
  const std::string& estimator;
  long intervals;
  int& iterations;
};

/// One Ceres solve from the channels' current parameters (jointly or per channel); throws SolverError when Ceres
/// finds no usable solution.
void solve_relation(std::vector<ChannelFit>& ch, Eigen::Index n, const BatchFitOptions& options,
                    const SolveContext& context) {
  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  std::vector<std::unique_ptr<ceres::LossFunction>> losses;
  std::vector<std::unique_ptr<ceres::Problem>> problems;
  for (int i = 0; i < (options.joint ? 1 : 3); ++i) problems.push_back(std::make_unique<ceres::Problem>(po));
  if (options.joint) {
    losses.push_back(make_loss(options.loss, 1.0));
    double inv_scale[3];
    for (int c = 0; c < 3; ++c) inv_scale[c] = 1.0 / (block_scale(options) * ch[c].scale);
    for (Eigen::Index k = 0; k < n; ++k) {
      auto* functor = new JointRelationResidual;
      for (int c = 0; c < 3; ++c) {
        functor->u[c] = ch[c].u(k);
        functor->d[c] = ch[c].d(k);
        functor->inv_scale[c] = inv_scale[c];
      }
      problems[0]->AddResidualBlock(new ceres::AutoDiffCostFunction<JointRelationResidual, 3, 2, 2, 2>(functor),
                                    losses[0].get(), ch[0].x.data(), ch[1].x.data(), ch[2].x.data());
    }
  } else {
    for (int c = 0; c < 3; ++c) {
      losses.push_back(make_loss(options.loss, 1.0));
      const double inv_scale = 1.0 / ch[c].scale;
      for (Eigen::Index k = 0; k < n; ++k)
        problems[c]->AddResidualBlock(new ceres::AutoDiffCostFunction<RelationResidual, 1, 2>(
                                          new RelationResidual(ch[c].u(k), ch[c].d(k), inv_scale)),
                                      losses[c].get(), ch[c].x.data());
    }
  }
  for (std::size_t i = 0; i < problems.size(); ++i) {
    ceres::Solver::Summary summary;
    ceres::Solve(options.solver, problems[i].get(), &summary);
    context.iterations += static_cast<int>(summary.iterations.size());
    if (!summary.IsSolutionUsable()) {
      const std::string which =
          options.joint ? std::string() : std::string(" for channel ") + relation_channel_name(static_cast<int>(i));
      throw SolverError(context.estimator + ": Ceres found no usable solution" + which + " over " +
                        std::to_string(context.intervals) + " interval(s): " + summary.message);
    }
  }
}

/// The solve, with automatic loss scales where asked: from the least-squares residuals first, then once more
/// from the robust fit's.
void solve_with_scales(std::vector<ChannelFit>& ch, Eigen::Index n, const BatchFitOptions& options,
                       const SolveContext& context) {
  bool automatic = false;
  for (int c = 0; c < 3; ++c)
    if (options.loss != RobustLoss::None && options.loss_scale(c) == 0.0) {
      ch[c].scale = automatic_scale(ch[c], n, options.loss);
      automatic = true;
    }
  solve_relation(ch, n, options, context);
  if (automatic) {
    // The least-squares residuals are spread by the outliers' pull on the fit; the robust fit's are not.
    for (int c = 0; c < 3; ++c)
      if (options.loss_scale(c) == 0.0) ch[c].scale = automatic_scale(ch[c], n, options.loss);
    solve_relation(ch, n, options, context);
  }
}

/// The fitted parameters, their residual std and their covariance.
void set_fitted_parameters(const std::vector<ChannelFit>& ch, Eigen::Index n, const BatchFitOptions& options,
                           RelationParameters& p) {
  // Huber's asymptotic covariance of an M-estimator, per channel, with psi the derivative of the sample's
  // loss with respect to its residual r (in the residual's unit) and psi' its derivative:
  //   cov = K^2 [sum psi^2 / (n - 2)] / mean(psi')^2 (H^T H)^-1,  K = 1 + (2 / n) var(psi') / mean(psi')^2,
  // which is s^2 (H^T H)^-1 for the quadratic loss (psi = r, psi' = 1).
  std::array<Eigen::VectorXd, 3> r;
  for (int c = 0; c < 3; ++c) r[c] = residuals(ch[c]);
  // The loss sees q_k = |f_k|^2 with f_kc = r_kc / (block_scale s_c): one channel's f^2 per channel, the sum
  // of the three jointly. d/dr of the sample's cost, in the residual's unit, is rho'(q) r; its derivative is
  // rho'(q) + 2 rho''(q) f_c^2.
  Eigen::MatrixX3d f2(n, 3);
  for (int c = 0; c < 3; ++c) f2.col(c) = (r[c] / (block_scale(options) * ch[c].scale)).array().square().matrix();
  const auto loss = make_loss(options.loss, 1.0);
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd psi(n), dpsi(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      double rho[3];
      evaluate_loss(loss.get(), options.joint ? f2.row(k).sum() : f2(k, c), rho);
      psi(k) = rho[1] * r[c](k);
      dpsi(k) = rho[1] + 2.0 * rho[2] * f2(k, c);
    }
    const double m = dpsi.mean();
    const double var_dpsi = (dpsi.array() - m).square().mean();
    const double k_factor = 1.0 + 2.0 / static_cast<double>(n) * var_dpsi / (m * m);
    const double factor = k_factor * k_factor * psi.squaredNorm() / static_cast<double>(n - 2) / (m * m);
    p.beta(c) = ch[c].x(0);
    p.eps(c) = ch[c].x(1);
    // A redescending loss (Cauchy) can leave mean psi' <= 0 on wild data: no asymptotic covariance then.
    p.covariance[c] = m > 0 ? Eigen::Matrix2d(factor * ch[c].inverse_information)
                            : Eigen::Matrix2d::Constant(std::numeric_limits<double>::quiet_NaN());
    p.residual_std(c) = std::sqrt(r[c].squaredNorm() / static_cast<double>(n - 2));
    p.loss_scale(c) = options.loss == RobustLoss::None ? 0.0 : ch[c].scale;
  }
}

}  // namespace

ceres::Solver::Options default_batch_solver_options() {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  // Stop on the step size alone: a relative cost change or gradient test stops Levenberg-Marquardt while
  // the parameters are still sqrt(tolerance) of their std away from the minimum, far from machine precision.
  o.function_tolerance = 0.0;
  o.gradient_tolerance = 0.0;
  o.parameter_tolerance = 1e-14;
  o.max_num_iterations = 200;
  o.initial_trust_region_radius = 1e12;  // the problem is linear or nearly so: start with Gauss-Newton steps
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  return o;
}

BatchLeastSquaresFit::BatchLeastSquaresFit(BatchFitOptions options) : options_(std::move(options)) {
  for (int c = 0; c < 3; ++c)
    if (!(options_.loss_scale(c) >= 0.0) || !std::isfinite(options_.loss_scale(c)))
      throw InputError(name() + ": loss scale of channel " + relation_channel_name(c) +
                       " must be finite and not negative (0 = automatic)");
  std::string error;
  if (!options_.solver.IsValid(&error)) throw InputError(name() + ": invalid Ceres solver options: " + error);
}

std::string BatchLeastSquaresFit::name() const {
  std::string n = options_.joint ? "batch_joint" : "batch";
  if (options_.loss == RobustLoss::Huber) n += "_huber";
  if (options_.loss == RobustLoss::Cauchy) n += "_cauchy";
  return n;
}

void BatchLeastSquaresFit::reset() {
  for (int c = 0; c < 3; ++c) {
    u_[c].clear();
    d_[c].clear();
  }
  intervals_ = 0;
  not_ready_ = "no identification interval fed yet";
  fit_ = {};
  last_iterations_ = 0;
}

std::unique_ptr<RelationEstimator> BatchLeastSquaresFit::clone() const {
  return std::make_unique<BatchLeastSquaresFit>(*this);
}

std::string BatchLeastSquaresFit::not_ready_reason() const { return not_ready_; }

RelationParameters BatchLeastSquaresFit::current_parameters() const { return fit_; }

void BatchLeastSquaresFit::add_checked_interval(const Eigen::Ref<const Eigen::MatrixX3d>& u,
                                                const Eigen::Ref<const Eigen::MatrixX3d>& d_hat) {
  const std::size_t before = u_[0].size();
  for (int c = 0; c < 3; ++c) {
    u_[c].insert(u_[c].end(), u.col(c).data(), u.col(c).data() + u.rows());
    d_[c].insert(d_[c].end(), d_hat.col(c).data(), d_hat.col(c).data() + d_hat.rows());
  }
  ++intervals_;
  try {
    refit();
  } catch (...) {
    // A failed refit leaves the estimator as it was before this interval.
    for (int c = 0; c < 3; ++c) {
      u_[c].resize(before);
      d_[c].resize(before);
    }
    --intervals_;
    throw;
  }
}

void BatchLeastSquaresFit::refit() {
  const Eigen::Index n = static_cast<Eigen::Index>(u_[0].size());
  last_iterations_ = 0;
  std::vector<ChannelFit> ch;
  for (int c = 0; c < 3; ++c) ch.emplace_back(u_[c], d_[c]);
  const std::string flat = unidentifiable_channels(ch, n);
  if (!flat.empty()) {
    not_ready_ = input_not_varied_reason(flat, intervals_);
    return;
  }
  if (n < 3) {
    not_ready_ = "needs at least 3 samples for a residual variance, has " + std::to_string(n);
    return;
  }
  const bool had_fit = not_ready_.empty();
  fit_least_squares(ch, n, options_, had_fit ? &fit_ : nullptr);
  const std::string estimator = name();
  solve_with_scales(ch, n, options_, SolveContext{estimator, intervals_, last_iterations_});

  RelationParameters p;
  p.estimator = estimator;
  p.samples = n;
  p.effective_samples = static_cast<double>(n);
  p.intervals = intervals_;
  set_fitted_parameters(ch, n, options_, p);
  fit_ = p;
  not_ready_.clear();
}

}  // namespace pushpred
