#pragma once
// The relation d_hat = beta u + eps fitted by Ceres over all identification data fed so far (refitted at every
// add_interval), with an optional robust loss. One residual block per sample, so that a robust loss judges
// samples one by one.
// - Per channel (joint = false): three independent problems, residual f_k = r_k / s_c with
//   r_k = d_k - (beta u_k + eps) and s_c the channel's scale (the loss scale; for the plain loss the
//   least-squares residual std, which does not move the minimum), loss rho_1(f^2) (Huber or Cauchy at 1):
//   the same minimum as rho at scale s_c on r.
// - Jointly (joint = true): one problem over the six parameters, one 3-vector residual block per sample,
//   f_k = (r_kc / (sqrt(3) s_c))_c, loss rho_1(|f_k|^2). The plain-loss minimum is the per-channel one; a robust
//   loss then down-weights a sample as a whole when the RMS over the channels of r_c / s_c exceeds 1 (a pose
//   or force glitch spoils all three channels at once).
// Start: the plain fit starts from the previous fit (zero at first); robust fits start from the plain
// least-squares fit, the usual start of an M-estimator. Automatic loss scale (loss_scale entry 0): k times the
// normalised median absolute deviation of the least-squares residuals, k = 1.345 (Huber) or 2.385 (Cauchy),
// 95 % efficiency under Gaussian noise; then re-estimated once from the first robust fit's residuals.
// Covariance: Huber's (1981) asymptotic M-estimator covariance, which is s^2 (H^T H)^-1 for the plain loss;
// docs/estimators.md states the formula.
#include <ceres/solver.h>

#include <vector>

#include "pushpred/estimators/relation_estimator.hpp"

namespace pushpred {

enum class RobustLoss { None, Huber, Cauchy };

/// Ceres options used by default: DENSE_QR, Levenberg-Marquardt, tolerances tight enough that the plain fit
/// agrees with the closed-form least squares to about 1e-10 relative, single thread, silent.
ceres::Solver::Options default_batch_solver_options();

struct BatchFitOptions {
  RobustLoss loss = RobustLoss::None;
  /// Per channel [N, N, N m]; 0 picks the scale automatically (see above). Ignored for the plain loss.
  Eigen::Vector3d loss_scale = Eigen::Vector3d::Zero();
  bool joint = false;
  ceres::Solver::Options solver = default_batch_solver_options();
};

class BatchLeastSquaresFit final : public RelationEstimator {
 public:
  /// Throws InputError for a negative or non-finite loss scale or invalid Ceres options. The name is
  /// "batch", then "_joint" when joint, then "_huber" or "_cauchy".
  explicit BatchLeastSquaresFit(BatchFitOptions options = {});

  std::string name() const override;
  std::string not_ready_reason() const override;
  void reset() override;
  std::unique_ptr<RelationEstimator> clone() const override;
  const BatchFitOptions& options() const { return options_; }
  /// Ceres iterations of the last refit, summed over its solves (for tests and benchmarks).
  int last_iterations() const { return last_iterations_; }

 protected:
  /// Appends the interval and refits; throws SolverError when Ceres returns no usable solution.
  void add_checked_interval(const Eigen::Ref<const Eigen::MatrixX3d>& u,
                            const Eigen::Ref<const Eigen::MatrixX3d>& d_hat) override;
  RelationParameters current_parameters() const override;

 private:
  void refit();

  BatchFitOptions options_;
  std::vector<double> u_[3], d_[3];  ///< all samples so far, per channel
  long intervals_ = 0;
  std::string not_ready_ = "no identification interval fed yet";
  RelationParameters fit_;
  int last_iterations_ = 0;
};

}  // namespace pushpred
