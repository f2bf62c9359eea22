#pragma once
// Recursive least squares for the relation d_hat = beta u + eps, per channel, exactly as the paper's
// identification phase (section III-B, after Crassidis & Junkins):
//   Initialise (first interval):  H = [u 1],  P^-1 = H^T H,  x = P H^T d
//   Update (each later interval): P^-1 <- lambda P^-1 + H^T H,  K = P H^T,  x <- x + K (d - H x)
//   Re-initialise: the updated P^-1 and x become the current ones.
// The forgetting factor lambda in (0, 1] is applied once per identification interval (not per sample), so an
// interval i intervals old weighs lambda^i; lambda = 1 is the paper's algorithm and equals the batch
// least-squares fit of all intervals. P is never formed: P v is a 2 x 2 LDLT solve with P^-1.
// A channel whose input has not varied yet (frozen force sensor, no contact: H^T H singular) is not
// initialised; its weighted H^T H and H^T d are gathered until H^T H is invertible, Initialise then runs on
// all of them, and until then the estimator is not ready() and says why.
// Beside the paper's P^-1 and x, each channel keeps the weighted sums H^T d and d^T d, for the residual
// variance (the paper gives no covariance): rss = d^T d - 2 x^T H^T d + x^T P^-1 x, exact whatever the
// conditioning of the first intervals.
#include <array>

#include "pushpred/estimators/relation_estimator.hpp"

namespace pushpred {

struct RlsOptions {
  double forgetting = 1.0;  ///< lambda in (0, 1], applied per identification interval
};

class RecursiveLeastSquares final : public RelationEstimator {
 public:
  /// Throws InputError for a forgetting factor outside (0, 1]. The name is "rls" without forgetting and
  /// "rls_forget" with it.
  explicit RecursiveLeastSquares(RlsOptions options = {});

  std::string name() const override;
  std::string not_ready_reason() const override;
  void reset() override;
  std::unique_ptr<RelationEstimator> clone() const override;
  const RlsOptions& options() const { return options_; }

 protected:
  void add_checked_interval(const Eigen::Ref<const Eigen::MatrixX3d>& u,
                            const Eigen::Ref<const Eigen::MatrixX3d>& d_hat) override;
  RelationParameters current_parameters() const override;

 private:
  struct Channel {
    bool initialised = false;
    Eigen::Matrix2d information = Eigen::Matrix2d::Zero();  ///< P^-1, the weighted H^T H
    /// Sum of squared weights times H^T H (lambda^2 recursion): with forgetting the estimate's covariance is
    /// s^2 P M P, not s^2 P.
    Eigen::Matrix2d squared_weight_information = Eigen::Matrix2d::Zero();
    Eigen::Vector2d x = Eigen::Vector2d::Zero();    ///< (beta, eps)
    Eigen::Vector2d htd = Eigen::Vector2d::Zero();  ///< weighted H^T d
    double dtd = 0;                                  ///< weighted d^T d
  };
  void update(Channel& channel, const Eigen::Ref<const Eigen::VectorXd>& u,
              const Eigen::Ref<const Eigen::VectorXd>& d) const;

  /// N_eff - tr(P M): the residuals' degrees of freedom (n - 2 without forgetting).
  double residual_dof(const Channel& channel) const;

  RlsOptions options_;
  std::array<Channel, 3> channels_;
  long samples_ = 0;
  long intervals_ = 0;
  double effective_samples_ = 0;
};

}  // namespace pushpred
