#include "pushpred/prediction/prediction_system.hpp"

#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/coulomb_slide.hpp"
#include "pushpred/mechanics/support_friction.hpp"

namespace pushpred {

void PredictionModel::validate() const {
  if (!(mass_kg > 0) || !std::isfinite(mass_kg)) throw InputError("prediction model: mass must be positive");
  if (!(inertia_kgm2 > 0) || !std::isfinite(inertia_kgm2))
    throw InputError("prediction model: inertia must be positive");
  if (!beta.allFinite() || !eps.allFinite()) throw InputError("prediction model: beta and eps must be finite");
  if (!(coulomb_force_N >= 0) || !(coulomb_speed_scale_m_s > 0))
    throw InputError("prediction model: Coulomb force must be >= 0 and its speed scale > 0");
}

PredictionModel relation_prediction_model(const ShapeInfo& shape, const Eigen::Vector3d& beta,
                                          const Eigen::Vector3d& eps) {
  PredictionModel model;
  model.mass_kg = shape.mass_kg;
  model.inertia_kgm2 = shape.inertia_kgm2;
  model.beta = beta;
  model.eps = eps;
  return model;
}

PredictionSystem::PredictionSystem(PredictionModel model, PlannedForce plan)
    : model_(std::move(model)), plan_(std::move(plan)) {
  model_.validate();
  if (plan_.signal.channels() != 3) throw InputError("planned force must have 3 channels");
}

void PredictionSystem::derivative(const IntegrationInterval& interval, double t,
                                  const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> xdot) const {
  Eigen::Vector3d u;
  plan_.signal.evaluate_within(t, interval.t0_s, interval.t1_s, u);
  Eigen::Vector3d f = u + model_.beta.cwiseProduct(u) + model_.eps;
  if (model_.coulomb_force_N > 0) {
    // Whole-body Coulomb friction: the ellipsoidal limit surface with c = 0 (a force against the velocity, no torque).
    f.head<2>() += ellipsoidal_limit_surface_wrench(x.segment<2>(3), 0.0, model_.coulomb_force_N, 0.0,
                                                    model_.coulomb_speed_scale_m_s)
                       .head<2>();
  }
  if (!model_.extra_terms.empty()) {
    const PlanarState s = x;
    for (const auto& term : model_.extra_terms) term->add(interval, t, s, u, f);
  }
  xdot.head<3>() = x.tail<3>();
  xdot(3) = f(0) / model_.mass_kg;
  xdot(4) = f(1) / model_.mass_kg;
  xdot(5) = f(2) / model_.inertia_kgm2;
}

// The extra terms have no Jacobian of their own: with them CVODE takes difference quotients.
bool PredictionSystem::has_jacobian() const { return model_.extra_terms.empty(); }

void PredictionSystem::jacobian(const IntegrationInterval&, double, const Eigen::Ref<const Eigen::VectorXd>& x,
                                Eigen::Ref<Eigen::MatrixXd> J) const {
  // The kinematics, and the regularised Coulomb friction f = -F v / sqrt(|v|^2 + s^2) on the velocity:
  // df/dv = -F ((|v|^2 + s^2) I - v v^T) / (|v|^2 + s^2)^(3/2).
  J.setZero();
  J(0, 3) = J(1, 4) = J(2, 5) = 1.0;
  if (model_.coulomb_force_N > 0) {
    const double vx = x(3), vy = x(4), s2 = model_.coulomb_speed_scale_m_s * model_.coulomb_speed_scale_m_s;
    const double r2 = vx * vx + vy * vy + s2;
    const double c = -model_.coulomb_force_N / (r2 * std::sqrt(r2) * model_.mass_kg);
    J(3, 3) = c * (r2 - vx * vx);
    J(3, 4) = J(4, 3) = -c * vx * vy;
    J(4, 4) = c * (r2 - vy * vy);
  }
}

Eigen::MatrixX3d predict_poses(const PredictionModel& model, const PlannedForce& plan, const Eigen::Vector3d& pose0,
                               const Eigen::Vector3d& velocity0, const Eigen::VectorXd& output_times,
                               const IntegratorOptions& integrator) {
  const PredictionSystem system(model, plan);
  Eigen::VectorXd x0(6);
  x0 << pose0, velocity0;
  const Eigen::MatrixXd states = integrate(system, integrator, plan.t0_s, x0, output_times);
  return states.leftCols<3>();
}

bool has_closed_form(const PredictionModel& model) { return model.extra_terms.empty(); }

Eigen::MatrixX3d predict_poses_exactly(const PredictionModel& model, const PlannedForce& plan,
                                       const Eigen::Vector3d& pose0, const Eigen::Vector3d& velocity0,
                                       const Eigen::VectorXd& output_times) {
  model.validate();
  if (!has_closed_form(model))
    throw InputError("prediction model: the closed-form path takes no extra terms (CVODE integrates those)");
  if (plan.signal.channels() != 3) throw InputError("planned force must have 3 channels");
  if (plan.signal.hold() != Hold::Zero) throw InputError("planned force: the closed-form path needs a zero-order hold");
  if (!pose0.allFinite() || !velocity0.allFinite())
    throw InputError("prediction: initial pose or velocity holds NaN or infinity");
  check_output_times("prediction", plan.t0_s, output_times);
  const Eigen::VectorXd& t = plan.signal.times();
  const Eigen::MatrixXd& u = plan.signal.values();
  // The generalized force held from plan sample k on; Coulomb friction, if any, acts on its translational part
  // (before the first sample the first value is held, as SampledSignal does).
  const auto force = [&](Eigen::Index k) -> Eigen::Vector3d {
    const Eigen::Vector3d uk = u.row(k).transpose();
    return uk + model.beta.cwiseProduct(uk) + model.eps;
  };
  // The state dt after one with generalized force g: translation by the Coulomb slide (with zero friction, the
  // double integrator), rotation by the double integrator.
  const auto advance = [&](const Eigen::Vector3d& pose, const Eigen::Vector3d& velocity, const Eigen::Vector3d& g,
                           double dt, Eigen::Vector3d& pose_out, Eigen::Vector3d& velocity_out) {
    const Eigen::Vector3d a(g(0) / model.mass_kg, g(1) / model.mass_kg, g(2) / model.inertia_kgm2);
    pose_out = pose + velocity * dt + 0.5 * dt * dt * a;
    velocity_out = velocity + dt * a;
    if (model.coulomb_force_N > 0) {
      const PlanarSlide slide = slide_under_coulomb_friction({pose.head<2>(), velocity.head<2>()}, g.head<2>(),
                                                             model.coulomb_force_N, model.mass_kg, dt);
      pose_out.head<2>() = slide.position_m;
      velocity_out.head<2>() = slide.velocity_m_s;
    }
  };
  Eigen::MatrixX3d poses(output_times.size(), 3);
  Eigen::Index k = 0;  // the plan segment the state below starts in
  double tk = plan.t0_s;
  Eigen::Vector3d pk = pose0, vk = velocity0, gk = force(0), pose, velocity;
  for (Eigen::Index j = 0; j < output_times.size(); ++j) {
    const double tj = output_times(j);
    // Step over every plan sample at or before tj: the held value changes there.
    while (k + 1 < t.size() && t(k + 1) <= tj) {
      if (t(k + 1) > tk) {
        advance(pk, vk, gk, t(k + 1) - tk, pose, velocity);
        pk = pose;
        vk = velocity;
        tk = t(k + 1);
      }
      ++k;
      gk = force(k);
    }
    advance(pk, vk, gk, tj - tk, pose, velocity);
    poses.row(j) = pose.transpose();
  }
  return poses;
}

}  // namespace pushpred
