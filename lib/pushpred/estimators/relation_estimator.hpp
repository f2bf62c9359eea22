#pragma once
// Estimators of the paper's linear relation (section III-B) between the applied input and the estimated
// disturbance, one relation per channel c (0 = x force, 1 = y force, 2 = rotation; frames, units and signs as
// stated in preprocessing/synchronised_push.hpp):
//
//     d_hat_c(t_k) = beta_c u_c(t_k) + eps_c,    regressor row h_k = [u_c(t_k)  1],  x_c = (beta_c, eps_c).
//
// beta is dimensionless, eps is in the channel's unit (N, N, N m). An estimator is fed the identification
// intervals one after another (add_interval) and can be asked for the current parameters and their covariance
// at any point. Apps choose one by name through make_relation_estimator(); docs/estimators.md explains how the
// estimators differ and how to choose. Every relation estimator is also an OnlineParameterEstimator
// (online_parameter_estimator.hpp), the interface it shares with the quasi-static model's identification.
#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/estimators/online_parameter_estimator.hpp"

namespace pushpred {

/// What an estimator knows about the relation after the intervals fed so far.
struct RelationParameters {
  std::string estimator;                           ///< name of the estimator that made it
  Eigen::Vector3d beta = Eigen::Vector3d::Zero();  ///< per channel [-]
  Eigen::Vector3d eps = Eigen::Vector3d::Zero();   ///< per channel [N, N, N m]
  /// Per channel, the covariance of (beta, eps): [[beta^2, beta eps], [beta eps, eps^2]] in the units above.
  std::array<Eigen::Matrix2d, 3> covariance{Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero(),
                                            Eigen::Matrix2d::Zero()};
  /// Per channel, the standard deviation of the fit's residuals d_hat - (beta u + eps) [N, N, N m]
  /// (forgetting-weighted for RLS with forgetting; robust fits include their outliers here).
  Eigen::Vector3d residual_std = Eigen::Vector3d::Zero();
  long samples = 0;               ///< samples fed so far
  double effective_samples = 0;   ///< sum of the samples' forgetting weights (= samples without forgetting)
  long intervals = 0;             ///< identification intervals fed so far
  /// Robust fits: the loss scale used per channel [N, N, N m] (zero for the plain quadratic loss).
  Eigen::Vector3d loss_scale = Eigen::Vector3d::Zero();

  Eigen::Vector3d beta_std() const;  ///< sqrt of the covariances' (0, 0) entries
  Eigen::Vector3d eps_std() const;   ///< sqrt of the covariances' (1, 1) entries
};

/// The relation estimators' interface. add_interval checks its input (same row count, at least one row, finite
/// values; InputError otherwise) before the estimator sees it. Through OnlineParameterEstimator, an interval is
/// the observer's output on it, and estimate() holds the six parameters beta_x, eps_x, beta_y, eps_y,
/// beta_rotation, eps_rotation (as_parameter_estimate).
class RelationEstimator : public OnlineParameterEstimator {
 public:
  /// Feeds one identification interval: u and d_hat are n x 3, one row per sample, channels as above.
  void add_interval(const Eigen::Ref<const Eigen::MatrixX3d>& u, const Eigen::Ref<const Eigen::MatrixX3d>& d_hat);
  /// Feeds an observer's output over one identification interval (its u and d_hat).
  /// The common interface's interval: its observer output (the relation reads nothing else of the push).
  void add_interval(const IdentificationInterval& interval) override { add_interval(interval.observer_u, interval.observer_d_hat); }

  // not_ready_reason() (OnlineParameterEstimator) is empty when parameters() can be asked; otherwise why not (e.g.
  // the input has been constant so far, so beta cannot be told apart from eps). reset() forgets every interval
  // fed so far; the options stay.

  /// The current parameters; throws InputError "NAME: not ready: REASON" when not ready().
  RelationParameters parameters() const;

  virtual std::unique_ptr<RelationEstimator> clone() const = 0;

 protected:
  /// Called with checked input.
  virtual void add_checked_interval(const Eigen::Ref<const Eigen::MatrixX3d>& u,
                                    const Eigen::Ref<const Eigen::MatrixX3d>& d_hat) = 0;
  /// Called only when ready().
  virtual RelationParameters current_parameters() const = 0;
  ParameterEstimate current_estimate() const override;
};

/// The relation as the common interface's estimate: parameters beta_c, eps_c per channel c (x, y, rotation), units
/// "", N, "", N, "", N m; the covariance is block diagonal, one (beta_c, eps_c) block per channel (the channels are
/// fitted apart, and RelationParameters keeps no covariance between them); every source "identified".
ParameterEstimate as_parameter_estimate(const RelationParameters& relation);

/// Names accepted by make_relation_estimator: "rls", "rls_forget", "batch", "batch_huber", "batch_cauchy",
/// "batch_joint", "batch_joint_huber", "batch_joint_cauchy".
std::vector<std::string> relation_estimator_names();
/// The estimator called `name` with its default options; throws InputError naming the known ones otherwise.
std::unique_ptr<RelationEstimator> make_relation_estimator(const std::string& name);

// Building blocks shared by the estimators, exposed for tests.

/// 1 - cos^2 of the angle between the regressor columns u and 1 below which beta and eps are taken as not
/// identifiable: the input has (numerically) not varied. Scale-free, so the same for N and N m.
inline constexpr double kMinRelativeExcitation = 1e-10;

/// Whether the (possibly forgetting-weighted) information matrix A = H^T H = [[sum u^2, sum u], [sum u, n]]
/// determines (beta, eps): det A > kMinRelativeExcitation * A00 * A11.
bool relation_identifiable(const Eigen::Matrix2d& information);

/// The reference batch least-squares fit of all rows at once, per channel, by Householder QR of H (no normal
/// equations): x = argmin |H x - d|, residual variance s^2 = |H x - d|^2 / (n - 2), covariance s^2 (H^T H)^-1.
/// Throws InputError for fewer than 3 rows, a channel whose input does not vary, or bad input.
RelationParameters least_squares_relation(const Eigen::Ref<const Eigen::MatrixX3d>& u,
                                          const Eigen::Ref<const Eigen::MatrixX3d>& d_hat);

/// Throws InputError naming `who` unless u and d_hat have the same, non-zero number of rows and finite values.
void check_relation_interval(const std::string& who, const Eigen::Ref<const Eigen::MatrixX3d>& u,
                             const Eigen::Ref<const Eigen::MatrixX3d>& d_hat);

/// "x", "y", "rotation".
const char* relation_channel_name(int channel);

/// The not-ready reason for channels (e.g. "x, y") whose input has not varied over `intervals` intervals.
std::string input_not_varied_reason(const std::string& channels, long intervals);

}  // namespace pushpred
