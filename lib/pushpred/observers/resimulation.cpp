#include "pushpred/observers/resimulation.hpp"

#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/systems/linear_system.hpp"

namespace pushpred {

Eigen::MatrixX3d resimulate_pose(const SynchronisedPush& push, const DisturbanceEstimate& e,
                                 const IntegratorOptions& integrator_options) {
  const Eigen::Index n = e.t_s.size();
  if (n < 2 || e.d_hat.rows() != n || e.u.rows() != n || e.total.rows() != n || e.velocity.rows() != n)
    throw InputError(about(push.source, "re-simulation: the estimate holds fewer than two samples or ragged columns"));
  const Eigen::Index first = push.index_at(e.t_s(0));
  if (first + n > push.size() || std::abs(push.t_s(first) - e.t_s(0)) > 1e-9 ||
      std::abs(push.t_s(first + n - 1) - e.t_s(n - 1)) > 1e-9)
    throw InputError(about(push.source, "re-simulation: the estimate's times are not a slice of this push's grid"));
  // total(k) is the mean over [t_{k-1}, t_k]: zero-order-held from t_{k-1}.
  const LinearSystem system = double_integrator(
      e.nominal_inertia, SampledSignal(e.t_s.head(n - 1), e.total.bottomRows(n - 1), Hold::Zero));
  Eigen::VectorXd x0(6);
  x0.head<3>() = push.pose.row(first).transpose();
  x0.tail<3>() = e.velocity.row(0).transpose();
  return integrate(system, integrator_options, e.t_s(0), x0, e.t_s).leftCols<3>();
}

Eigen::RowVector3d rms_difference(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b) {
  if (a.rows() != b.rows() || a.rows() == 0) throw InputError("rms difference: sizes differ or are empty");
  return ((a - b).array().square().colwise().sum() / static_cast<double>(a.rows())).sqrt();
}

}  // namespace pushpred
