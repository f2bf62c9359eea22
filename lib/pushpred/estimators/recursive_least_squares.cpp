#include "pushpred/estimators/recursive_least_squares.hpp"

#include <Eigen/Cholesky>
#include <cmath>

#include "pushpred/core/error.hpp"

namespace pushpred {
namespace {

/// H^T H for H = [u 1]: [[sum u^2, sum u], [sum u, n]].
Eigen::Matrix2d information_of(const Eigen::Ref<const Eigen::VectorXd>& u) {
  Eigen::Matrix2d a;
  a(0, 0) = u.squaredNorm();
  a(0, 1) = a(1, 0) = u.sum();
  a(1, 1) = static_cast<double>(u.size());
  return a;
}

}  // namespace

RecursiveLeastSquares::RecursiveLeastSquares(RlsOptions options) : options_(options) {
  if (!(options_.forgetting > 0.0 && options_.forgetting <= 1.0))
    throw InputError("rls: forgetting factor must lie in (0, 1], got " + std::to_string(options_.forgetting));
}

std::string RecursiveLeastSquares::name() const { return options_.forgetting < 1.0 ? "rls_forget" : "rls"; }

void RecursiveLeastSquares::reset() {
  channels_ = {};
  samples_ = 0;
  intervals_ = 0;
  effective_samples_ = 0;
}

std::unique_ptr<RelationEstimator> RecursiveLeastSquares::clone() const {
  return std::make_unique<RecursiveLeastSquares>(*this);
}

std::string RecursiveLeastSquares::not_ready_reason() const {
  if (intervals_ == 0) return "no identification interval fed yet";
  std::string flat;
  for (int c = 0; c < 3; ++c)
    if (!channels_[c].initialised) flat += std::string(flat.empty() ? "" : ", ") + relation_channel_name(c);
  if (!flat.empty()) return input_not_varied_reason(flat, intervals_);
  if (samples_ < 3) return "needs at least 3 samples for a residual variance, has " + std::to_string(samples_);
  // N_eff - tr(P M) is positive in exact arithmetic once 3 samples are in; guard against rounding.
  for (const Channel& ch : channels_)
    if (!(residual_dof(ch) > 0.0))
      return "the forgetting factor leaves " + std::to_string(effective_samples_) +
             " effective samples, too few for a residual variance";
  return {};
}

void RecursiveLeastSquares::add_checked_interval(const Eigen::Ref<const Eigen::MatrixX3d>& u,
                                                 const Eigen::Ref<const Eigen::MatrixX3d>& d_hat) {
  const double lambda = options_.forgetting;
  ++intervals_;
  samples_ += u.rows();
  effective_samples_ = lambda * effective_samples_ + static_cast<double>(u.rows());
  for (int c = 0; c < 3; ++c) {
    Channel& ch = channels_[c];
    const auto uc = u.col(c);
    const auto dc = d_hat.col(c);
    // P_{k+1}^-1 = lambda P_k^-1 + H^T H (Initialise: P^-1 = H^T H, from zero)
    const Eigen::Matrix2d a = information_of(uc);
    ch.information = lambda * ch.information + a;
    ch.squared_weight_information = lambda * lambda * ch.squared_weight_information + a;
    ch.htd = lambda * ch.htd + Eigen::Vector2d(uc.dot(dc), dc.sum());
    ch.dtd = lambda * ch.dtd + dc.squaredNorm();
    if (ch.initialised) {
      // Update: K_{k+1} (d - H x_k) = P_{k+1} H^T e with e = d - H x_k, the a-priori residuals; the n x 2 gain
      // is never formed.
      Eigen::Vector2d ht_e = Eigen::Vector2d::Zero();
      for (Eigen::Index k = 0; k < uc.size(); ++k) {
        const double e = dc(k) - ch.x(0) * uc(k) - ch.x(1);
        ht_e(0) += uc(k) * e;
        ht_e(1) += e;
      }
      ch.x += ch.information.ldlt().solve(ht_e);  // x_{k+1} = x_k + K_{k+1} (d - H x_k); Re-initialise
    } else if (relation_identifiable(ch.information)) {
      // Initialise: x = P H^T d, over everything gathered (for a good first interval: that interval alone).
      ch.x = ch.information.ldlt().solve(ch.htd);
      ch.initialised = true;
    }
  }
}

double RecursiveLeastSquares::residual_dof(const Channel& ch) const {
  // E[sum w r^2] = s^2 (sum w - tr(P M)) for a weighted fit; n - 2 for lambda = 1.
  return effective_samples_ - ch.information.ldlt().solve(ch.squared_weight_information).trace();
}

RelationParameters RecursiveLeastSquares::current_parameters() const {
  RelationParameters p;
  p.estimator = name();
  p.samples = samples_;
  p.effective_samples = effective_samples_;
  p.intervals = intervals_;
  for (int c = 0; c < 3; ++c) {
    const Channel& ch = channels_[c];
    p.beta(c) = ch.x(0);
    p.eps(c) = ch.x(1);
    const Eigen::Matrix2d pm = ch.information.ldlt().solve(ch.squared_weight_information);  // P M
    const Eigen::Matrix2d p_matrix = ch.information.ldlt().solve(Eigen::Matrix2d::Identity());
    const double dof = residual_dof(ch);  // unbiased residual variance of a weighted fit
    const double rss = ch.dtd - 2.0 * ch.x.dot(ch.htd) + ch.x.dot(ch.information * ch.x);
    const double variance = std::max(rss, 0.0) / dof;
    // Covariance of the weighted estimate under white residuals: s^2 P M P (= s^2 P for lambda = 1).
    Eigen::Matrix2d cov = variance * pm * p_matrix;
    p.covariance[c] = 0.5 * (cov + cov.transpose());
    p.residual_std(c) = std::sqrt(variance);
  }
  return p;
}

}  // namespace pushpred
