// The exact discretisation, the reference for every CVODE path: closed forms, then agreement with CVODE.
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/systems/cvode_integrator.hpp"
#include "pushpred/systems/exact_discretisation.hpp"
#include "pushpred/systems/linear_system.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(exact_discretisation)

BOOST_AUTO_TEST_CASE(zero_order_hold_matches_the_scalar_closed_form) {
  const double a = -3.0, b = 2.0, dt = 0.05;
  const DiscreteStep s = discretise_exactly(Eigen::MatrixXd::Constant(1, 1, a), Eigen::MatrixXd::Constant(1, 1, b), dt,
                                            Hold::Zero);
  BOOST_TEST(s.phi(0, 0) == std::exp(a * dt), boost::test_tools::tolerance(1e-14));
  BOOST_TEST(s.gamma_from(0, 0) == b * (std::exp(a * dt) - 1) / a, boost::test_tools::tolerance(1e-14));
  BOOST_TEST(s.gamma_to(0, 0) == 0.0);
}

BOOST_AUTO_TEST_CASE(first_order_hold_matches_the_double_integrator_under_a_ramp) {
  // x'' = u, u linear from u0 to u1 over dt: x gains v0 dt + dt^2 (u0 / 3 + u1 / 6), v gains dt (u0 + u1) / 2.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 2), B = Eigen::MatrixXd::Zero(2, 1);
  A(0, 1) = 1;
  B(1, 0) = 1;
  const double dt = 0.3;
  const DiscreteStep s = discretise_exactly(A, B, dt, Hold::First);
  BOOST_TEST(s.phi(0, 1) == dt, boost::test_tools::tolerance(1e-14));
  BOOST_TEST(s.gamma_from(0, 0) == dt * dt / 3, boost::test_tools::tolerance(1e-13));
  BOOST_TEST(s.gamma_to(0, 0) == dt * dt / 6, boost::test_tools::tolerance(1e-13));
  BOOST_TEST(s.gamma_from(1, 0) == dt / 2, boost::test_tools::tolerance(1e-13));
  BOOST_TEST(s.gamma_to(1, 0) == dt / 2, boost::test_tools::tolerance(1e-13));
}

BOOST_AUTO_TEST_CASE(cvode_and_the_exact_discretisation_agree_under_both_holds) {
  // A damped oscillator and an integrator, driven by two rough sampled inputs.
  Eigen::MatrixXd A(3, 3), B(3, 2);
  A << 0, 1, 0, -400, -12, 0, 1, 0, 0;
  B << 0, 0, 400, 0, 0, 1;
  const Eigen::Index n = 101;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(n, 0.0, 0.4);
  Eigen::MatrixXd u(n, 2);
  for (Eigen::Index k = 0; k < n; ++k) u.row(k) << std::sin(0.7 * k * k), std::cos(1.3 * k);
  const Eigen::Vector3d x0(0.1, -1.0, 0.0);
  IntegratorOptions o;
  o.relative_tolerance = 1e-10;
  o.absolute_tolerance = 1e-12;
  for (Hold hold : {Hold::Zero, Hold::First}) {
    const SampledSignal input(t, u, hold);
    const Eigen::MatrixXd exact = propagate_exactly(A, B, x0, input);
    const LinearSystem system(A, B, input);
    CvodeIntegrator integrator(system, o);
    const Eigen::MatrixXd cvode = integrator.solve(t(0), x0, t);
    BOOST_TEST_INFO(hold_name(hold) << "-order hold");
    BOOST_TEST((cvode - exact).cwiseAbs().maxCoeff() < 1e-7 * exact.cwiseAbs().maxCoeff());
  }
}

BOOST_AUTO_TEST_CASE(inputs_with_different_holds_are_superposed) {
  // A double integrator driven by a ramp held first-order and a force held zero-order: exact in closed form.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 2), B(2, 2);
  A(0, 1) = 1;
  B << 0, 0, 1, 1;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(6, 0.0, 0.5);
  Eigen::MatrixXd ramp(6, 1), steps(6, 1);
  for (int k = 0; k < 6; ++k) {
    ramp(k, 0) = 2.0 * t(k);  // u1 = 2 t exactly under first-order hold
    steps(k, 0) = (k % 2) ? 1.0 : -1.0;
  }
  const LinearSystem system(A, B, {SampledSignal(t, ramp, Hold::First), SampledSignal(t, steps, Hold::Zero)});
  const Eigen::MatrixXd X = propagate_exactly(system, Eigen::Vector2d::Zero());
  double x = 0, v = 0;
  for (int k = 0; k < 5; ++k) {
    const double h = 0.1, t0 = t(k), a = steps(k, 0);
    // x'' = 2 t + a on [t0, t0 + h]
    x += v * h + a * h * h / 2 + (t0 * h * h + h * h * h / 3);
    v += a * h + ((t0 + h) * (t0 + h) - t0 * t0);
    BOOST_TEST(X(k + 1, 0) == x, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(X(k + 1, 1) == v, boost::test_tools::tolerance(1e-12));
  }
  const LinearSystem mismatched(A, B, {SampledSignal(t, ramp, Hold::First), SampledSignal(t * 2, steps, Hold::Zero)});
  BOOST_CHECK_THROW(propagate_exactly(mismatched, Eigen::Vector2d::Zero()), InputError);
}

BOOST_AUTO_TEST_CASE(a_bad_step_is_a_clear_error) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Zero(1, 1), B = Eigen::MatrixXd::Ones(1, 1);
  BOOST_CHECK_THROW(discretise_exactly(A, B, 0.0, Hold::Zero), InputError);
  BOOST_CHECK_THROW(discretise_exactly(A, Eigen::MatrixXd::Ones(2, 1), 0.1, Hold::Zero), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
