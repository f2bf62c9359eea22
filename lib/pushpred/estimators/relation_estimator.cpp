#include "pushpred/estimators/relation_estimator.hpp"

#include <Eigen/QR>
#include <cmath>
#include <functional>

#include "pushpred/core/error.hpp"
#include "pushpred/estimators/batch_least_squares_fit.hpp"
#include "pushpred/estimators/recursive_least_squares.hpp"

namespace pushpred {

Eigen::Vector3d RelationParameters::beta_std() const {
  return {std::sqrt(covariance[0](0, 0)), std::sqrt(covariance[1](0, 0)), std::sqrt(covariance[2](0, 0))};
}

Eigen::Vector3d RelationParameters::eps_std() const {
  return {std::sqrt(covariance[0](1, 1)), std::sqrt(covariance[1](1, 1)), std::sqrt(covariance[2](1, 1))};
}

const char* relation_channel_name(int channel) {
  static const char* const names[3] = {"x", "y", "rotation"};
  return channel >= 0 && channel < 3 ? names[channel] : "?";
}

std::string input_not_varied_reason(const std::string& channels, long intervals) {
  return "the input of channel(s) " + channels + " has not varied over the " + std::to_string(intervals) +
         " interval(s) fed so far (frozen force sensor or no contact?), so beta and eps cannot be told apart";
}

void check_relation_interval(const std::string& who, const Eigen::Ref<const Eigen::MatrixX3d>& u,
                             const Eigen::Ref<const Eigen::MatrixX3d>& d_hat) {
  if (u.rows() != d_hat.rows())
    throw InputError(who + ": identification interval has " + std::to_string(u.rows()) + " rows of u but " +
                     std::to_string(d_hat.rows()) + " of d_hat");
  if (u.rows() == 0) throw InputError(who + ": empty identification interval");
  for (int c = 0; c < 3; ++c)
    for (Eigen::Index k = 0; k < u.rows(); ++k)
      if (!std::isfinite(u(k, c)) || !std::isfinite(d_hat(k, c)))
        throw InputError(who + ": identification interval holds a non-finite " +
                         (std::isfinite(u(k, c)) ? "d_hat" : "u") + " at row " + std::to_string(k) +
                         ", channel " + relation_channel_name(c));
}

void RelationEstimator::add_interval(const Eigen::Ref<const Eigen::MatrixX3d>& u,
                                     const Eigen::Ref<const Eigen::MatrixX3d>& d_hat) {
  check_relation_interval(name(), u, d_hat);
  add_checked_interval(u, d_hat);
}

RelationParameters RelationEstimator::parameters() const {
  const std::string reason = not_ready_reason();
  if (!reason.empty()) throw InputError(name() + ": not ready: " + reason);
  return current_parameters();
}

ParameterEstimate RelationEstimator::current_estimate() const { return as_parameter_estimate(current_parameters()); }

ParameterEstimate as_parameter_estimate(const RelationParameters& relation) {
  ParameterEstimate e;
  e.estimator = relation.estimator;
  e.value = Eigen::VectorXd::Zero(6);
  e.covariance = Eigen::MatrixXd::Zero(6, 6);
  static const char* const force_units[3] = {"N", "N", "N m"};
  for (int c = 0; c < 3; ++c) {
    const std::string channel = relation_channel_name(c);
    e.names.insert(e.names.end(), {"beta_" + channel, "eps_" + channel});
    e.units.insert(e.units.end(), {"", force_units[c]});
    e.value.segment<2>(2 * c) << relation.beta(c), relation.eps(c);
    e.covariance.block<2, 2>(2 * c, 2 * c) = relation.covariance[static_cast<std::size_t>(c)];
  }
  e.sources.assign(6, "identified");
  e.samples = relation.samples;
  e.intervals = relation.intervals;
  return e;
}

bool relation_identifiable(const Eigen::Matrix2d& a) {
  const double det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  return std::isfinite(det) && det > kMinRelativeExcitation * a(0, 0) * a(1, 1);
}

RelationParameters least_squares_relation(const Eigen::Ref<const Eigen::MatrixX3d>& u,
                                          const Eigen::Ref<const Eigen::MatrixX3d>& d_hat) {
  const std::string who = "least squares";
  check_relation_interval(who, u, d_hat);
  const Eigen::Index n = u.rows();
  if (n < 3) throw InputError(who + ": needs at least 3 samples for a residual variance, has " + std::to_string(n));
  RelationParameters p;
  p.estimator = "least_squares";
  p.samples = n;
  p.effective_samples = static_cast<double>(n);
  p.intervals = 1;
  Eigen::MatrixX2d h(n, 2);
  h.col(1).setOnes();
  for (int c = 0; c < 3; ++c) {
    h.col(0) = u.col(c);
    const Eigen::Matrix2d information = h.transpose() * h;
    if (!relation_identifiable(information))
      throw InputError(who + ": the input of channel " + relation_channel_name(c) +
                       " does not vary, so beta and eps cannot be told apart");
    const Eigen::HouseholderQR<Eigen::MatrixX2d> qr(h);
    const Eigen::Vector2d x = qr.solve(d_hat.col(c));
    const double rss = (d_hat.col(c) - h * x).squaredNorm();
    const double variance = rss / static_cast<double>(n - 2);
    // (H^T H)^-1 = R^-1 R^-T from the QR factor, without forming H^T H.
    const Eigen::Matrix2d r = qr.matrixQR().topRows<2>().triangularView<Eigen::Upper>();
    const Eigen::Matrix2d r_inv = r.triangularView<Eigen::Upper>().solve(Eigen::Matrix2d::Identity());
    p.beta(c) = x(0);
    p.eps(c) = x(1);
    p.covariance[c] = variance * r_inv * r_inv.transpose();
    p.residual_std(c) = std::sqrt(variance);
  }
  return p;
}

namespace {

using Factory = std::function<std::unique_ptr<RelationEstimator>()>;

const std::vector<std::pair<std::string, Factory>>& factories() {
  static const std::vector<std::pair<std::string, Factory>> list = [] {
    std::vector<std::pair<std::string, Factory>> l;
    l.emplace_back("rls", [] { return std::make_unique<RecursiveLeastSquares>(); });
    l.emplace_back("rls_forget", [] {
      RlsOptions o;
      o.forgetting = 0.5;  // docs/estimators.md: each older identification interval weighs half the next
      return std::make_unique<RecursiveLeastSquares>(o);
    });
    for (const bool joint : {false, true})
      for (const RobustLoss loss : {RobustLoss::None, RobustLoss::Huber, RobustLoss::Cauchy}) {
        BatchFitOptions o;
        o.joint = joint;
        o.loss = loss;
        const std::string name = BatchLeastSquaresFit(o).name();
        l.emplace_back(name, [o] { return std::make_unique<BatchLeastSquaresFit>(o); });
      }
    return l;
  }();
  return list;
}

}  // namespace

std::vector<std::string> relation_estimator_names() {
  std::vector<std::string> names;
  for (const auto& [name, make] : factories()) names.push_back(name);
  return names;
}

std::unique_ptr<RelationEstimator> make_relation_estimator(const std::string& name) {
  for (const auto& [known, make] : factories())
    if (known == name) return make();
  std::string list;
  for (const auto& n : relation_estimator_names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("unknown relation estimator '" + name + "' (known: " + list + ")");
}

}  // namespace pushpred
