#define BOOST_TEST_MODULE prediction
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/prediction/prediction_system.hpp"
#include "test_support.hpp"

using namespace pushpred;

namespace {

/// A planned input that changes every 0.1 s: [f_x, f_y, torque].
PlannedForce staircase_plan(double t0, int steps) {
  Eigen::VectorXd t(steps);
  Eigen::MatrixXd v(steps, 3);
  for (int k = 0; k < steps; ++k) {
    t(k) = t0 + 0.1 * k;
    v.row(k) << 1.0 + 0.5 * k, -0.3 * k, 0.01 * std::cos(k);
  }
  return {SampledSignal(t, v, Hold::Zero), t0, t0 + 0.1 * steps, 10.0};
}

/// Newton's law for a piecewise-constant input, integrated in closed form step by step.
Eigen::Vector3d newton_closed_form(const PlannedForce& plan, const Eigen::Vector3d& mass, Eigen::Vector3d pose,
                                   Eigen::Vector3d velocity, double t_end) {
  const auto& t = plan.signal.times();
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    const double a = t(k), b = std::min(k + 1 < t.size() ? t(k + 1) : plan.t1_s, t_end);
    if (b <= a) break;
    const Eigen::Vector3d acc = plan.signal.values().row(k).transpose().cwiseQuotient(mass);
    const double dt = b - a;
    pose += velocity * dt + 0.5 * acc * dt * dt;
    velocity += acc * dt;
  }
  return pose;
}

/// An extra term of the kind the diagnosis adds: a constant force.
class ConstantPush final : public GeneralizedForceTerm {
 public:
  std::string name() const override { return "constant push"; }
  void add(const IntegrationInterval&, double, const PlanarState&, const Eigen::Vector3d&,
           Eigen::Vector3d& generalized_force) const override {
    generalized_force(0) += 0.1;
  }
};

/// A plan whose force hovers about the friction: below it, at it and above it, turning from step to step.
PlannedForce plan_about_friction(double friction_N, int steps) {
  Eigen::VectorXd t(steps);
  Eigen::MatrixXd v(steps, 3);
  const double ratio[] = {1.6, 0.7, 1.0, 1.3, 0.2, 2.0, 0.95, 1.05};
  for (int k = 0; k < steps; ++k) {
    t(k) = 0.1 * k;
    const double angle = 0.7 * k;
    v.row(k) << ratio[k % 8] * friction_N * std::cos(angle), ratio[k % 8] * friction_N * std::sin(angle),
        0.002 * std::sin(k);
  }
  return {SampledSignal(t, v, Hold::Zero), 0.0, 0.1 * steps, 10.0};
}

}  // namespace

BOOST_AUTO_TEST_SUITE(prediction_system)

BOOST_AUTO_TEST_CASE(prediction_with_zero_disturbance_reproduces_newtons_law) {
  const PlannedForce plan = staircase_plan(2.0, 8);
  PredictionModel model;
  model.mass_kg = 1.045;
  model.inertia_kgm2 = 0.001808;
  const Eigen::Vector3d pose0(0.3, -0.02, 0.5), vel0(0.01, 0.0, -0.2);
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(41, 2.0, 2.8);
  const Eigen::MatrixX3d poses = predict_poses(model, plan, pose0, vel0, times);
  const Eigen::Vector3d mass(model.mass_kg, model.mass_kg, model.inertia_kgm2);
  for (Eigen::Index j = 0; j < times.size(); ++j) {
    const Eigen::Vector3d exact = newton_closed_form(plan, mass, pose0, vel0, times(j));
    BOOST_TEST_REQUIRE((poses.row(j).transpose() - exact).norm() < 1e-7 * (1.0 + exact.norm()));
  }
}

BOOST_AUTO_TEST_CASE(a_relation_that_cancels_the_input_leaves_the_object_coasting) {
  // beta = -1, eps = 0: the unknown force cancels the push exactly, so the object keeps its initial velocity.
  PredictionModel model;
  model.mass_kg = 1.0;
  model.inertia_kgm2 = 0.002;
  model.beta = Eigen::Vector3d::Constant(-1.0);
  const Eigen::Vector3d pose0(0.1, 0.2, 0.0), vel0(0.02, -0.01, 0.1);
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(5, 0.1, 0.5);
  const Eigen::MatrixX3d poses = predict_poses(model, staircase_plan(0.0, 5), pose0, vel0, times);
  for (Eigen::Index j = 0; j < times.size(); ++j)
    BOOST_TEST_REQUIRE((poses.row(j).transpose() - (pose0 + vel0 * times(j))).norm() < 1e-8);
}

BOOST_AUTO_TEST_CASE(coulomb_friction_stops_a_coasting_object_after_v_squared_over_2_mu_g) {
  PredictionModel model;
  model.mass_kg = 1.0;
  model.inertia_kgm2 = 0.002;
  const double mu = 0.14, v0 = 0.1;
  model.coulomb_force_N = mu * model.mass_kg * 9.81;
  model.coulomb_speed_scale_m_s = 1e-5;
  PlannedForce none{SampledSignal(Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Zero(1, 3), Hold::Zero), 0.0, 1.0, 10};
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(3, 0.2, 1.0);
  const Eigen::MatrixX3d poses = predict_poses(model, none, Eigen::Vector3d::Zero(), Eigen::Vector3d(v0, 0, 0), times);
  const double stop = v0 * v0 / (2 * mu * 9.81);
  BOOST_TEST(poses(2, 0) == stop, boost::test_tools::tolerance(1e-3));
  BOOST_TEST(std::abs(poses(2, 1)) < 1e-12);
}

BOOST_AUTO_TEST_CASE(a_bad_model_is_a_clear_error) {
  PredictionModel model;
  model.mass_kg = -1.0;
  model.inertia_kgm2 = 0.001;
  BOOST_CHECK_THROW(predict_poses(model, staircase_plan(0, 2), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                  Eigen::VectorXd::Constant(1, 0.1)),
                    InputError);
}

BOOST_AUTO_TEST_CASE(the_exact_path_reproduces_newtons_law) {
  const PlannedForce plan = staircase_plan(2.0, 8);
  PredictionModel model;
  model.mass_kg = 1.045;
  model.inertia_kgm2 = 0.001808;
  const Eigen::Vector3d pose0(0.3, -0.02, 0.5), vel0(0.01, 0.0, -0.2);
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(41, 2.0, 2.8);  // every fifth one on a plan sample
  const Eigen::MatrixX3d poses = predict_poses_exactly(model, plan, pose0, vel0, times);
  const Eigen::Vector3d mass(model.mass_kg, model.mass_kg, model.inertia_kgm2);
  for (Eigen::Index j = 0; j < times.size(); ++j) {
    const Eigen::Vector3d exact = newton_closed_form(plan, mass, pose0, vel0, times(j));
    BOOST_TEST_REQUIRE((poses.row(j).transpose() - exact).norm() < 1e-12 * (1.0 + exact.norm()));
  }
}

BOOST_AUTO_TEST_CASE(the_exact_path_of_the_relation_model_equals_cvode) {
  // beta and eps on every channel, an initial velocity, output times on, between and past the plan's samples, and a
  // start between two samples (the sample before the start is held from it): CVODE at tight tolerances agrees.
  PredictionModel model;
  model.mass_kg = 0.837;
  model.inertia_kgm2 = 0.0011;
  model.beta = Eigen::Vector3d(-0.45, -0.8, 0.3);
  model.eps = Eigen::Vector3d(-0.2, 0.15, -0.004);
  for (const double start : {0.0, 0.037}) {
    PlannedForce plan = staircase_plan(0.0, 7);
    plan.t0_s = start;
    plan.t1_s = 0.9;  // past the last sample (0.6): its value is held
    const Eigen::Vector3d pose0(0.05, 0.1, -0.3), vel0(0.02, -0.01, 0.4);
    Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(226, start, 0.9);
    times(3) = times(2);  // a repeated output time
    IntegratorOptions tight;
    tight.relative_tolerance = 1e-12;
    tight.absolute_tolerance = 1e-14;
    const Eigen::MatrixX3d exact = predict_poses_exactly(model, plan, pose0, vel0, times);
    const Eigen::MatrixX3d cvode = predict_poses(model, plan, pose0, vel0, times, tight);
    const double scale = exact.cwiseAbs().maxCoeff();
    BOOST_TEST((exact - cvode).cwiseAbs().maxCoeff() < 1e-9 * scale, "start " << start);
  }
}

BOOST_AUTO_TEST_CASE(the_closed_form_of_the_simple_model_is_cvodes_as_the_regularisation_vanishes) {
  // The `simple` baseline's law: CVODE integrates it regularised over v_s; the closed form is the law itself. Their
  // difference shrinks with v_s (the regularised body creeps at about v_s where the real one is held or stops).
  PredictionModel model;
  model.mass_kg = 0.837;
  model.inertia_kgm2 = 0.0011;
  model.coulomb_force_N = 0.14 * model.mass_kg * 9.81;
  const PlannedForce plan = plan_about_friction(model.coulomb_force_N, 12);
  const Eigen::Vector3d pose0(0.05, 0.1, -0.3);
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(301, 0.0, 1.2);
  const Eigen::MatrixX3d exact = predict_poses_exactly(model, plan, pose0, Eigen::Vector3d::Zero(), times);
  IntegratorOptions tight;
  tight.relative_tolerance = 1e-10;
  tight.absolute_tolerance = 1e-13;
  double previous = INFINITY;
  for (const double scale : {1e-4, 1e-5, 1e-6}) {
    model.coulomb_speed_scale_m_s = scale;
    const Eigen::MatrixX3d cvode = predict_poses(model, plan, pose0, Eigen::Vector3d::Zero(), times, tight);
    const double difference = (exact.leftCols<2>() - cvode.leftCols<2>()).cwiseAbs().maxCoeff();
    BOOST_TEST_MESSAGE("v_s " << scale << " m/s: largest difference " << difference << " m");
    BOOST_TEST(difference < 0.5 * previous, "v_s " << scale);
    BOOST_TEST((exact.col(2) - cvode.col(2)).cwiseAbs().maxCoeff() < 1e-9);  // rotation: no friction
    previous = difference;
  }
  BOOST_TEST(previous < 1e-6);  // 1 um over a slide of several cm
  BOOST_TEST((exact.row(times.size() - 1) - exact.row(0)).head<2>().norm() > 0.02);
}

BOOST_AUTO_TEST_CASE(the_exact_path_refuses_what_it_cannot_predict_exactly) {
  PredictionModel model;
  model.mass_kg = 1.0;
  model.inertia_kgm2 = 0.002;
  const PlannedForce plan = staircase_plan(0.0, 3);
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  PredictionModel friction = model;
  friction.coulomb_force_N = 1.0;
  BOOST_TEST(has_closed_form(model));
  BOOST_TEST(has_closed_form(friction));
  PredictionModel extra = model;
  extra.extra_terms.push_back(std::make_shared<ConstantPush>());
  BOOST_TEST(!has_closed_form(extra));
  BOOST_CHECK_THROW(predict_poses_exactly(extra, plan, zero, zero, Eigen::VectorXd::Constant(1, 0.1)), InputError);
  Eigen::VectorXd decreasing(2);
  decreasing << 0.2, 0.1;
  BOOST_CHECK_THROW(predict_poses_exactly(model, plan, zero, zero, decreasing), InputError);
  BOOST_CHECK_THROW(predict_poses_exactly(model, plan, zero, zero, Eigen::VectorXd::Constant(1, -0.1)), InputError);
  BOOST_CHECK_THROW(predict_poses_exactly(model, plan, zero, zero, Eigen::VectorXd::Constant(1, std::nan(""))),
                    InputError);
  BOOST_CHECK_THROW(predict_poses_exactly(model, plan, Eigen::Vector3d::Constant(std::nan("")), zero,
                                          Eigen::VectorXd::Constant(1, 0.1)),
                    InputError);
}

BOOST_AUTO_TEST_SUITE_END()
