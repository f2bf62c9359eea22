#pragma once
// Simulates one push described by a PushScenario and records it the way the MCube rig does: the physics of
// PushedObjectSystem integrated by CvodeIntegrator (BDF), sampled by the three jittered, noisy sensor streams
// of SensorModel, with Unix time stamps and wrapped yaw, in the dataset's HDF5 layout and file naming — so that
// every other command reads a simulated push exactly like a real one.
//
// Timeline (simulation clock, 0 at the recording's start = Unix time scenario.start_unix_s): the object rests
// with the rod `approach_gap_m` from its outline; at rest_before_s the rod starts along its path; after it stops
// the recording goes on for rest_after_s. The rod starts at the scenario's contact side and position and moves
// along the inward normal rotated by the push angle (outline.hpp: the dataset's side convention).
// Signs and frames of what is written: reading/recording.hpp (sensor reads the reaction on the pusher).
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "pushpred/reading/recording.hpp"
#include "pushpred/simulation/pushed_object_system.hpp"
#include "pushpred/simulation/scenario.hpp"
#include "pushpred/simulation/sensor_model.hpp"
#include "pushpred/systems/cvode_integrator.hpp"

namespace pushpred {

struct SimulatedPush {
  PushScenario scenario;
  /// The three streams as the rig would store them: stamps may be slightly out of order, as in real files.
  Recording recording;

  // Truth, on the simulation clock, at every instant a sensor sampled the object or the force (sorted).
  Eigen::VectorXd t_s;
  Eigen::MatrixX3d tracked_pose;          ///< tracked centre x, y [m], yaw [rad] (unwrapped), world
  Eigen::MatrixX3d mass_centre_velocity;  ///< vX, vY [m/s], omega [rad/s]
  Eigen::MatrixX2d force_on_object_N;     ///< the rod's force on the object, world
  /// The force the sensor reads the reaction of, world: the contact force, or a compliant pusher's spring force.
  Eigen::MatrixX2d sensed_force_N;
  std::vector<char> touching;
  double push_start_s = 0, push_end_s = 0;  ///< the rod's motion
  double rod_peak_speed_m_s = 0;
  CvodeIntegrator::Stats solver;
};

/// Simulates `scenario` (validated first; InputError when invalid, SolverError when CVODE fails).
SimulatedPush simulate_push(const PushScenario& scenario, const SensorModel& sensors = SensorModel::mcube());

/// The friction patch's share of the support's wrench per unit of its excess (scenario.hpp's position_friction) at
/// each recorded state of `sim` (rows as sim.t_s): force [N] (world) and torque about the mass centre [N m] that the
/// patch adds when its friction is mu (1 + 1) rather than mu, whatever excess `sim` was simulated with. The truth a
/// position-friction diagnosis is measured against: the support's friction is linear in the patch's excess at given
/// states (pushed_object_system.hpp: each element's mu (1 + excess x its smoothed share inside the disk)).
Eigen::MatrixX3d patch_wrench_per_excess(const SimulatedPush& sim);

/// The streams of `raw` as a reader returns them (sorted, repeated stamps dropped, repairs listed), for using a
/// simulated push in memory without writing it.
Recording as_read(const Recording& raw);

/// Where `pushpred simulate --out OUT` writes: OUT itself, or OUT/push_filename(...) when OUT is a folder (an
/// existing one, or a path ending in '/').
std::filesystem::path simulated_output_path(const PushScenario& scenario, const std::filesystem::path& out);

/// A clean scenario repeating the real push at `real_path`: shape, speed, side, position and angle from its
/// file name; initial pose, approach gap, push length and rest times from its data; its start time.
PushScenario scenario_like_recording(const std::filesystem::path& real_path, double surface_friction,
                                     double contact_friction = RodContact().friction);

}  // namespace pushpred
