// The closed-form Coulomb slide against what is known without it: static friction holding a body, the collinear
// slides of a school textbook, an independent fine-step integration of the law while the body keeps sliding, and
// the group property of an exact solution (sliding dt1 and then dt2 is sliding dt1 + dt2), which holds across
// stops and at |f| = F only if every branch is right. CVODE on the regularised law is the cross-check in
// tests/prediction (test_prediction_system.cpp).
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/coulomb_slide.hpp"

using namespace pushpred;

namespace {

const double kMass = 0.837, kFriction = 0.14 * 0.837 * 9.81;

/// The unregularised law by classical Runge-Kutta at a fixed small step, for a body that does not come near rest.
PlanarSlide runge_kutta(PlanarSlide s, const Eigen::Vector2d& f, double friction, double mass, double dt, int steps) {
  const auto accel = [&](const Eigen::Vector2d& v) -> Eigen::Vector2d { return (f - friction * v / v.norm()) / mass; };
  const double h = dt / steps;
  for (int i = 0; i < steps; ++i) {
    const Eigen::Vector2d v = s.velocity_m_s;
    const Eigen::Vector2d k1v = accel(v), k1x = v;
    const Eigen::Vector2d k2v = accel(v + 0.5 * h * k1v), k2x = v + 0.5 * h * k1v;
    const Eigen::Vector2d k3v = accel(v + 0.5 * h * k2v), k3x = v + 0.5 * h * k2v;
    const Eigen::Vector2d k4v = accel(v + h * k3v), k4x = v + h * k3v;
    s.velocity_m_s += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    s.position_m += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
  }
  return s;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(coulomb_slide)

BOOST_AUTO_TEST_CASE(static_friction_holds_a_body_at_rest_under_a_force_below_it) {
  const PlanarSlide start{Eigen::Vector2d(0.1, -0.2), Eigen::Vector2d::Zero()};
  const PlanarSlide end = slide_under_coulomb_friction(
      start, Eigen::Vector2d(0.6, -0.7) * kFriction / std::hypot(0.6, 0.7) * 0.999, kFriction, kMass, 0.1);
  BOOST_TEST((end.position_m - start.position_m).norm() == 0.0);
  BOOST_TEST(end.velocity_m_s.norm() == 0.0);
}

BOOST_AUTO_TEST_CASE(a_force_above_friction_starts_a_resting_body_along_it_at_the_excess_over_m) {
  const Eigen::Vector2d f = Eigen::Vector2d(3.0, 4.0) / 5.0 * (2 * kFriction);
  const double dt = 0.1, a = kFriction / kMass;  // (|f| - F) / m
  const PlanarSlide end = slide_under_coulomb_friction({}, f, kFriction, kMass, dt);
  BOOST_TEST((end.position_m - 0.5 * a * dt * dt * Eigen::Vector2d(0.6, 0.8)).norm() < 1e-15);
  BOOST_TEST((end.velocity_m_s - a * dt * Eigen::Vector2d(0.6, 0.8)).norm() < 1e-15);
}

BOOST_AUTO_TEST_CASE(a_coasting_body_stops_after_v_squared_over_2_mu_g_and_stays) {
  const double v0 = 0.1, mu_g = kFriction / kMass;
  const PlanarSlide start{Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, -v0)};
  const PlanarSlide half =
      slide_under_coulomb_friction(start, Eigen::Vector2d::Zero(), kFriction, kMass, 0.5 * v0 / mu_g);
  BOOST_TEST(half.position_m.y() == -0.75 * v0 * v0 / (2 * mu_g), boost::test_tools::tolerance(1e-14));
  const PlanarSlide end = slide_under_coulomb_friction(start, Eigen::Vector2d::Zero(), kFriction, kMass, 1.0);
  BOOST_TEST(end.position_m.y() == -v0 * v0 / (2 * mu_g), boost::test_tools::tolerance(1e-14));
  BOOST_TEST(end.position_m.x() == 0.0);
  BOOST_TEST(end.velocity_m_s.norm() == 0.0);
}

BOOST_AUTO_TEST_CASE(a_force_against_the_motion_stops_the_body_then_pushes_it_back_if_it_exceeds_friction) {
  const double v0 = 0.05, f = 3 * kFriction;
  const PlanarSlide start{Eigen::Vector2d::Zero(), Eigen::Vector2d(v0, 0)};
  const double a_stop = (f + kFriction) / kMass, t_stop = v0 / a_stop, a_back = (f - kFriction) / kMass;
  const double dt = 0.1, rest = dt - t_stop;
  const PlanarSlide end = slide_under_coulomb_friction(start, Eigen::Vector2d(-f, 0), kFriction, kMass, dt);
  BOOST_TEST(end.position_m.x() == v0 * v0 / (2 * a_stop) - 0.5 * a_back * rest * rest,
             boost::test_tools::tolerance(1e-13));
  BOOST_TEST(end.velocity_m_s.x() == -a_back * rest, boost::test_tools::tolerance(1e-13));
}

BOOST_AUTO_TEST_CASE(the_closed_form_follows_a_fine_integration_of_the_law_while_the_body_slides) {
  // Forces below, at and above the friction, at every angle to the velocity, for a body fast enough not to stop
  // within the step (RK4 meets the law's kink only at rest).
  std::mt19937 random(5);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), ratio(0.2, 0.95);
  for (int trial = 0; trial < 60; ++trial) {
    const double k = trial % 3 == 0 ? 1.0 : ratio(random) * (trial % 3 == 1 ? 1.0 : 1.2);  // F / |f|
    const Eigen::Vector2d f = kFriction / k * Eigen::Vector2d(std::cos(angle(random)), std::sin(angle(random)));
    const double a = angle(random);
    const PlanarSlide start{Eigen::Vector2d(0.01, 0.02), 0.3 * Eigen::Vector2d(std::cos(a), std::sin(a))};
    const double dt = 0.1;
    const PlanarSlide exact = slide_under_coulomb_friction(start, f, kFriction, kMass, dt);
    const PlanarSlide fine = runge_kutta(start, f, kFriction, kMass, dt, 20000);
    BOOST_TEST_REQUIRE((exact.position_m - fine.position_m).norm() < 1e-11, "trial " << trial);
    BOOST_TEST_REQUIRE((exact.velocity_m_s - fine.velocity_m_s).norm() < 1e-10, "trial " << trial);
  }
}

BOOST_AUTO_TEST_CASE(sliding_dt1_then_dt2_is_sliding_dt1_plus_dt2) {
  // Through stops, at |f| = F exactly and next to it, nearly against the motion and nearly along it.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), speed(0.0, 0.2), duration(0.0, 0.3);
  const double ratios[] = {0.3, 0.9, 1.0 - 1e-9, 1.0, 1.0 + 1e-9, 1.1, 2.5, 40.0};
  for (int trial = 0; trial < 400; ++trial) {
    const double k = ratios[trial % 8];
    double fa = angle(random);
    double va = angle(random);
    if (trial % 5 == 0) va = fa + M_PI - 1e-7;  // nearly against the force
    if (trial % 7 == 0) va = fa + 1e-9;         // nearly along it
    const Eigen::Vector2d f = kFriction / k * Eigen::Vector2d(std::cos(fa), std::sin(fa));
    const PlanarSlide start{Eigen::Vector2d(-0.3, 0.4), speed(random) * Eigen::Vector2d(std::cos(va), std::sin(va))};
    const double dt1 = duration(random), dt2 = duration(random);
    const PlanarSlide once = slide_under_coulomb_friction(start, f, kFriction, kMass, dt1 + dt2);
    const PlanarSlide twice = slide_under_coulomb_friction(
        slide_under_coulomb_friction(start, f, kFriction, kMass, dt1), f, kFriction, kMass, dt2);
    const double scale = 1e-12 * (1 + once.velocity_m_s.norm() + start.velocity_m_s.norm());
    BOOST_TEST_REQUIRE((once.position_m - twice.position_m).norm() < scale, "trial " << trial << ", k " << k);
    BOOST_TEST_REQUIRE((once.velocity_m_s - twice.velocity_m_s).norm() < 10 * scale, "trial " << trial << ", k " << k);
  }
}

BOOST_AUTO_TEST_CASE(the_slide_is_continuous_in_the_force_through_the_friction) {
  // Each side of |f| = F, where the closed form's exponents k - 1 and 2k - 2 change sign.
  const PlanarSlide start{Eigen::Vector2d::Zero(), Eigen::Vector2d(0.02, 0.05)};
  const Eigen::Vector2d direction(1.0, 0.0);
  const PlanarSlide at = slide_under_coulomb_friction(start, kFriction * direction, kFriction, kMass, 0.2);
  for (const double relative : {-1e-6, 1e-6, -1e-12, 1e-12}) {
    const PlanarSlide near =
        slide_under_coulomb_friction(start, (1 + relative) * kFriction * direction, kFriction, kMass, 0.2);
    // A force changed by delta moves the body by at most delta t^2 / (2 m): twice that, and rounding.
    const double bound = std::abs(relative) * kFriction / kMass * 0.2 * 0.2 + 1e-15;
    BOOST_TEST((near.position_m - at.position_m).norm() < bound, "relative " << relative);
  }
}

BOOST_AUTO_TEST_CASE(far_from_the_datasets_scales_the_slide_stays_finite_and_within_its_bounds) {
  // Forces from a micronewton to a meganewton, speeds from a nanometre to a kilometre per second, steps from a
  // nanosecond to minutes: the state stays finite, the speed within |v0| + (|f| + F) dt / m, and a body whose force
  // is below the friction never ends faster than it began.
  std::mt19937 random(17);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), exponent(0.0, 1.0);
  const auto log_uniform = [&](double lo, double hi) { return lo * std::pow(hi / lo, exponent(random)); };
  for (int trial = 0; trial < 20000; ++trial) {
    const double f = log_uniform(1e-6, 1e6), friction = log_uniform(1e-6, 1e6), mass = log_uniform(1e-3, 1e3);
    const double s0 = trial % 10 == 0 ? 0.0 : log_uniform(1e-9, 1e3), dt = log_uniform(1e-9, 300.0);
    const double fa = angle(random), va = trial % 13 == 0 ? fa + M_PI : angle(random);
    const PlanarSlide start{Eigen::Vector2d(1.0, -2.0), s0 * Eigen::Vector2d(std::cos(va), std::sin(va))};
    const PlanarSlide end =
        slide_under_coulomb_friction(start, f * Eigen::Vector2d(std::cos(fa), std::sin(fa)), friction, mass, dt);
    BOOST_TEST_REQUIRE((end.position_m.allFinite() && end.velocity_m_s.allFinite()), "trial " << trial);
    const double speed = end.velocity_m_s.norm();
    BOOST_TEST_REQUIRE(speed <= (s0 + (f + friction) * dt / mass) * (1 + 1e-9), "trial " << trial);
    if (f < friction) BOOST_TEST_REQUIRE(speed <= s0 * (1 + 1e-9), "trial " << trial);
  }
}

BOOST_AUTO_TEST_CASE(bad_inputs_are_clear_errors) {
  const PlanarSlide start{Eigen::Vector2d::Zero(), Eigen::Vector2d(0.1, 0)};
  const Eigen::Vector2d f(1, 0);
  BOOST_CHECK_THROW(slide_under_coulomb_friction(start, f, kFriction, kMass, -0.1), InputError);
  BOOST_CHECK_THROW(slide_under_coulomb_friction(start, f, -1.0, kMass, 0.1), InputError);
  BOOST_CHECK_THROW(slide_under_coulomb_friction(start, f, kFriction, 0.0, 0.1), InputError);
  BOOST_CHECK_THROW(slide_under_coulomb_friction(start, Eigen::Vector2d(std::nan(""), 0), kFriction, kMass, 0.1),
                    InputError);
  BOOST_CHECK_THROW(
      slide_under_coulomb_friction({Eigen::Vector2d::Zero(), Eigen::Vector2d(INFINITY, 0)}, f, kFriction, kMass, 0.1),
      InputError);
}

BOOST_AUTO_TEST_SUITE_END()
