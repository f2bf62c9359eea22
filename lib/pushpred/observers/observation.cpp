#include "pushpred/observers/observation.hpp"

#include "pushpred/observers/resimulation.hpp"

namespace pushpred {

Observation observe_push(const SynchronisedPush& push, const ObservationOptions& options) {
  const double t1 = options.t_end_s < 0 ? push.duration_s() : options.t_end_s;
  const QFilterObserver dob(options.observer);
  PidReconstructionOptions pid_options;
  pid_options.integrator = options.observer.integrator;
  const PidForceReconstruction pid(options.pid_gains, pid_options);
  Observation o;
  o.source = push.source;
  o.dob = dob.estimate(push, options.t_start_s, t1);
  o.pid = pid.estimate(push, options.t_start_s, t1);
  o.measured_pose = push.pose.middleRows(push.index_at(o.dob.t_s(0)), o.dob.t_s.size());
  o.resimulated_dob = resimulate_pose(push, o.dob, options.observer.integrator);
  o.resimulated_pid = resimulate_pose(push, o.pid, options.observer.integrator);
  o.rms_dob = rms_difference(o.dob.d_hat, Eigen::MatrixX3d::Zero(o.dob.d_hat.rows(), 3));
  o.rms_dob_minus_pid = rms_difference(o.dob.d_hat, o.pid.d_hat);
  o.rms_resimulation_dob = rms_difference(o.resimulated_dob, o.measured_pose);
  o.rms_resimulation_pid = rms_difference(o.resimulated_pid, o.measured_pose);
  return o;
}

}  // namespace pushpred
