#pragma once
// The prediction phase as a continuous system: a planar rigid body driven by the planned input and by a model
// of the unknown force. State [x, y, theta, vx, vy, omega] in {R} (SI; see synchronised_push.hpp). Per channel
// c (x, y, rotation), with u the planned input and M = (m, m, I):
//
//     M_c * accel_c = u_c + beta_c u_c + eps_c              (the paper's eq. for the prediction phase)
//                     - friction_c(velocity)                (Coulomb, for the simple baseline and diagnosis)
//                     + sum of extra terms                  (effects added by diagnosis or by a user)
//
// With beta = eps = 0 and no friction this is Newton's law under the planned force.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "pushpred/prediction/planned_force.hpp"
#include "pushpred/systems/continuous_system.hpp"
#include "pushpred/systems/cvode_integrator.hpp"

namespace pushpred {

using PlanarState = Eigen::Matrix<double, 6, 1>;  ///< x, y [m], theta [rad], vx, vy [m/s], omega [rad/s]

/// A force term a user or the diagnosis adds to the prediction model: adds its generalized force
/// [f_x, f_y] [N], torque [N m] (world frame, torque about the tracked centre) given the time [s], state and
/// planned input. `interval` is the integrator's jump-free interval around t_s (IntegrationInterval), for a term
/// that holds a zero-order-held signal of its own on the plan's times and must read it as held inside the interval,
/// also at its end (SampledSignal::evaluate_within); other terms ignore it. Must not allocate; keeps no state.
class GeneralizedForceTerm {
 public:
  virtual ~GeneralizedForceTerm() = default;
  virtual std::string name() const = 0;
  virtual void add(const IntegrationInterval& interval, double t_s, const PlanarState& state,
                   const Eigen::Vector3d& planned_input, Eigen::Vector3d& generalized_force) const = 0;
};

struct PredictionModel {
  double mass_kg = 0;
  double inertia_kgm2 = 0;
  Eigen::Vector3d beta = Eigen::Vector3d::Zero();  ///< per channel [-]
  Eigen::Vector3d eps = Eigen::Vector3d::Zero();   ///< per channel [N, N, N m]
  /// Coulomb friction of magnitude coulomb_force_N opposing the translational velocity (0: none). CVODE
  /// (PredictionSystem) integrates it regularised as v / sqrt(|v|^2 + coulomb_speed_scale^2)
  /// (ellipsoidal_limit_surface_wrench with c = 0, mechanics/support_friction.hpp) so the dynamics stay smooth, which
  /// lets a body at rest creep under any force; predict_poses_exactly solves the law itself, static friction included.
  double coulomb_force_N = 0;
  double coulomb_speed_scale_m_s = 1e-3;
  std::vector<std::shared_ptr<const GeneralizedForceTerm>> extra_terms;

  /// Throws InputError for a non-positive mass or inertia or non-finite parameters.
  void validate() const;
};

/// The paper's relation model for an object of `shape` (its mass and inertia) with the relation beta, eps: what
/// `dob` and `dob_velinit` predict with (beta = eps = 0: Newton's law under the planned force).
PredictionModel relation_prediction_model(const ShapeInfo& shape, const Eigen::Vector3d& beta,
                                          const Eigen::Vector3d& eps);

class PredictionSystem final : public ContinuousSystem {
 public:
  PredictionSystem(PredictionModel model, PlannedForce plan);
  int state_size() const override { return 6; }
  /// The plan's force as held inside `interval`; the extra terms get the same interval.
  void derivative(const IntegrationInterval& interval, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                  Eigen::Ref<Eigen::VectorXd> xdot) const override;
  /// Newton's law under a held force (the relation model) is a double integrator, not stiff: Adams. Coulomb
  /// friction, regularised over v_s = 1 mm/s, pulls a slow object's velocity to rest at mu g / v_s (1400 1/s for
  /// the `simple` baseline) against 0.1 s plan steps, and the diagnosis's force laws are regularised alike: BDF.
  bool stiff() const override { return model_.coulomb_force_N > 0 || !model_.extra_terms.empty(); }
  bool has_jacobian() const override;
  void jacobian(const IntegrationInterval& interval, double t, const Eigen::Ref<const Eigen::VectorXd>& x,
                Eigen::Ref<Eigen::MatrixXd> J) const override;
  std::vector<double> discontinuities(double t0, double t1) const override { return plan_.signal.jumps(t0, t1); }

 private:
  PredictionModel model_;
  PlannedForce plan_;
};

/// Predicted poses (n x 3: x, y, theta) at `output_times_s` from `pose0` and `velocity0` at plan.t0_s, by CVODE.
Eigen::MatrixX3d predict_poses(const PredictionModel& model, const PlannedForce& plan, const Eigen::Vector3d& pose0,
                               const Eigen::Vector3d& velocity0, const Eigen::VectorXd& output_times_s,
                               const IntegratorOptions& integrator = {});

/// True when `model` has no extra terms: the paper's relation model, with or without Coulomb friction, which
/// predict_poses_exactly solves in closed form.
bool has_closed_form(const PredictionModel& model);

/// The poses of predict_poses for a model without extra terms (has_closed_form), in closed form from plan sample to
/// plan sample and to each output time: the fast path of the study's dob, dob_velinit and simple methods, with
/// predict_poses (CVODE) as the cross-check (tests/prediction). Per plan step the input is constant, so
/// - the relation model alone is a double integrator, whose exact discretisation exp([[A, B], [0, 0]] dt) is
///   pose + v dt + a dt^2 / 2 and v + a dt with a = (u + beta u + eps) / M: the same poses as CVODE to rounding;
/// - with Coulomb friction the translation is slide_under_coulomb_friction (mechanics/coulomb_slide.hpp), the law
///   itself rather than its regularisation over coulomb_speed_scale_m_s, which CVODE needs: the two agree as that
///   scale goes to zero, and differ where the regularised body creeps (a force below the friction moves a body at
///   rest in CVODE's model, not in this one). Rotation stays the double integrator.
/// One allocation (the result). Throws InputError for a model with extra terms or not valid, a plan without 3
/// channels or not zero-order held, a non-finite start, or output times that are not finite, precede plan.t0_s or
/// decrease.
Eigen::MatrixX3d predict_poses_exactly(const PredictionModel& model, const PlannedForce& plan,
                                       const Eigen::Vector3d& pose0, const Eigen::Vector3d& velocity0,
                                       const Eigen::VectorXd& output_times_s);

}  // namespace pushpred
