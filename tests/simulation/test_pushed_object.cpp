// The physics of the simulated object: Newton's laws with distributed Coulomb friction and a compliant rod.
#define BOOST_TEST_MODULE simulation
#include <Eigen/Geometry>
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "pushpred/core/error.hpp"
#include "pushpred/simulation/pushed_object_system.hpp"
#include "pushpred/systems/cvode_integrator.hpp"

using namespace pushpred;

namespace {
const double kG = SupportFriction().gravity_m_s2;  // 9.81 m/s^2
}  // namespace

namespace {

const ShapeInfo& shape(const char* name) { return ShapeTable::published().find(name); }

/// A rod that never comes near the object.
PusherPath far_away_rod() {
  PusherMotion m;
  m.speed_m_s = 0.01;
  return PusherPath(Eigen::Vector2d(10, 10), Eigen::Vector2d(1, 0), 1e3, m);
}

Eigen::MatrixXd integrate(const PushedObjectSystem& system, const Eigen::VectorXd& x0, const Eigen::VectorXd& times) {
  IntegratorOptions o;
  o.relative_tolerance = 1e-8;
  o.absolute_tolerance = 1e-11;
  CvodeIntegrator integrator(system, o);
  return integrator.solve(0.0, x0, times);
}

}  // namespace

BOOST_AUTO_TEST_SUITE(pushed_object)

BOOST_AUTO_TEST_CASE(without_friction_or_contact_the_object_keeps_its_velocity) {
  SupportFriction frictionless;
  frictionless.coefficient = 0;
  const PushedObjectSystem system(shape("rect2"), ObjectProperties::nominal(shape("rect2")), frictionless, RodContact{},
                                  far_away_rod());
  Eigen::VectorXd x0(6);
  x0 << 0.3, -0.1, 0.4, 0.12, -0.05, 0.8;
  const Eigen::MatrixXd x = integrate(system, x0, Eigen::Vector2d(0.5, 2.0));
  for (int k = 0; k < 2; ++k) {
    const double t = k == 0 ? 0.5 : 2.0;
    BOOST_TEST(x(k, 0) == 0.3 + 0.12 * t, boost::test_tools::tolerance(1e-8));
    BOOST_TEST(x(k, 1) == -0.1 - 0.05 * t, boost::test_tools::tolerance(1e-8));
    BOOST_TEST(x(k, 2) == 0.4 + 0.8 * t, boost::test_tools::tolerance(1e-8));
    BOOST_TEST((x.row(k).tail<3>() - x0.tail<3>().transpose()).norm() < 1e-9);
  }
}

BOOST_AUTO_TEST_CASE(with_friction_only_a_sliding_object_stops_after_v_squared_over_two_mu_g) {
  SupportFriction f;
  f.coefficient = 0.3;
  const PushedObjectSystem system(shape("rect2"), ObjectProperties::nominal(shape("rect2")), f, RodContact{},
                                  far_away_rod());
  const double v0 = 0.2;
  const Eigen::Vector2d u(0.6, 0.8);
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(6);
  x0.segment<2>(3) = v0 * u;
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(301, 0.0, 0.15);
  const Eigen::MatrixXd x = integrate(system, x0, times);

  const double mu_g = 0.3 * kG;
  const double distance = x.row(300).head<2>().norm();
  BOOST_TEST(distance == v0 * v0 / (2 * mu_g), boost::test_tools::tolerance(1e-3));
  BOOST_TEST(std::abs(x.row(300).head<2>().normalized().dot(u) - 1) < 1e-9);  // straight on
  // While it slides the deceleration is mu g, so it stops at v0 / (mu g).
  for (Eigen::Index k = 0; k < 301; ++k) {
    const double t = times(k), speed = x.row(k).segment<2>(3).norm();
    if (t < 0.9 * v0 / mu_g) BOOST_TEST(speed == v0 - mu_g * t, boost::test_tools::tolerance(2e-3));
    if (t > 1.02 * v0 / mu_g) BOOST_TEST(speed < 1e-4);
    BOOST_TEST(std::abs(x(k, 5)) < 1e-6);  // symmetric pressure: no torque from a pure slide
  }
}

BOOST_AUTO_TEST_CASE(a_spinning_disc_feels_two_thirds_mu_m_g_r_of_friction_torque) {
  // Uniform pressure over a disc of radius R resists spinning with (2/3) mu m g R.
  const ShapeInfo& disc = shape("ellip1");  // a circle, R = 52.5 mm
  SupportFriction f;
  f.coefficient = 0.3;
  const ObjectProperties body = ObjectProperties::nominal(disc);
  const PushedObjectSystem system(disc, body, f, RodContact{}, far_away_rod());
  Eigen::VectorXd x0 = Eigen::VectorXd::Zero(6);
  x0(5) = 5.0;
  const Eigen::MatrixXd x = integrate(system, x0, Eigen::Vector2d(0.02, 0.04));
  const double torque = 2.0 / 3.0 * 0.3 * body.mass_kg * kG * disc.dim1_m;
  for (int k = 0; k < 2; ++k) {
    const double t = k == 0 ? 0.02 : 0.04;
    BOOST_TEST(5.0 - x(k, 5) == torque / body.inertia_kgm2 * t, boost::test_tools::tolerance(0.01));
    BOOST_TEST(x.row(k).segment<2>(3).norm() < 1e-7);
  }
}

BOOST_AUTO_TEST_CASE(a_steady_central_push_needs_mu_m_g_and_carries_the_object_along) {
  const ShapeInfo& s = shape("rect2");
  SupportFriction f;
  f.coefficient = 0.3;
  // The rod touches the middle of the +y side and pushes along -y at 50 mm/s.
  PusherMotion m;
  m.speed_m_s = 0.05;
  m.length_m = 0.05;
  const Eigen::Vector2d start(0.0, s.dim2_m / 2 + kPusherRadius_m);
  const PushedObjectSystem system(s, ObjectProperties::nominal(s), f, RodContact{},
                                  PusherPath(start, Eigen::Vector2d(0, -1), 0.1, m));
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(61, 0.6, 0.9);  // well inside the cruise
  const Eigen::MatrixXd x = integrate(system, system.state_at_rest(Eigen::Vector3d::Zero()), times);
  for (Eigen::Index k = 0; k < times.size(); ++k) {
    const RodWrench w = system.rod_wrench(times(k), x.row(k).transpose());
    BOOST_TEST_REQUIRE(w.touching);
    BOOST_TEST(-w.force_on_object_N.y() == 0.3 * s.mass_kg * kG, boost::test_tools::tolerance(0.01));
    BOOST_TEST(std::abs(w.force_on_object_N.x()) < 1e-6);
    BOOST_TEST(x(k, 4) == -0.05, boost::test_tools::tolerance(0.01));
    BOOST_TEST(std::abs(x(k, 2)) < 1e-6);
    // Pushing with mu m g on a spring of 1e4 N/m: the rod is in by about 0.3 mm.
    BOOST_TEST(w.penetration_m == 0.3 * s.mass_kg * kG / 1e4, boost::test_tools::tolerance(0.02));
  }
}

BOOST_AUTO_TEST_CASE(the_rod_follows_its_prescribed_speed_profiles) {
  PusherMotion m;
  m.speed_m_s = 0.075;
  m.length_m = 0.05;
  m.ramp_s = 0.07;
  const PusherPath constant(Eigen::Vector2d::Zero(), Eigen::Vector2d(3, 4), 0.2, m);
  BOOST_TEST(constant.direction().norm() == 1.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(constant.distance_m(0.1) == 0.0);
  BOOST_TEST(constant.distance_m(constant.end_time_s() + 1) == 0.05, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(constant.end_time_s() == 0.2 + 0.05 / 0.075 + 0.07, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(constant.speed_m_s(0.2 + 0.07 + 0.1) == 0.075, boost::test_tools::tolerance(1e-12));
  // Speed is the rate of distance everywhere, and continuous.
  for (double t = 0.19; t < constant.end_time_s() + 0.01; t += 0.0037) {
    const double h = 1e-6;
    const double rate = (constant.distance_m(t + h) - constant.distance_m(t - h)) / (2 * h);
    BOOST_TEST(rate == constant.speed_m_s(t), boost::test_tools::tolerance(1e-5));
    BOOST_TEST(std::abs(constant.speed_m_s(t + h) - constant.speed_m_s(t)) < 1e-5);
  }
  // The raised cosine goes from 5 % to 95 % of the speed in 0.713 of the ramp, as measured on the real tips.
  BOOST_TEST(constant.speed_m_s(0.2 + 0.1436 * 0.07) == 0.05 * 0.075, boost::test_tools::tolerance(1e-3));
  BOOST_TEST(constant.speed_m_s(0.2 + 0.8564 * 0.07) == 0.95 * 0.075, boost::test_tools::tolerance(1e-3));

  m.profile = PusherMotion::Profile::ConstantAcceleration;
  m.acceleration_m_s2 = 2.5;
  const PusherPath accelerating(Eigen::Vector2d::Zero(), Eigen::Vector2d(1, 0), 0.2, m);
  BOOST_TEST(accelerating.speed_m_s(0.3) == 0.25, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(accelerating.distance_m(0.3) == 0.5 * 2.5 * 0.01, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(accelerating.distance_m(accelerating.end_time_s()) == 0.05, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(accelerating.speed_m_s(accelerating.end_time_s()) == 0.0);
  BOOST_TEST(accelerating.peak_speed_m_s() == std::sqrt(2 * 2.5 * (0.05 - accelerating.peak_speed_m_s() * 0.07 / 2)),
             boost::test_tools::tolerance(1e-12));

  m.speed_m_s = -1;
  m.profile = PusherMotion::Profile::ConstantSpeed;
  BOOST_CHECK_THROW(PusherPath(Eigen::Vector2d::Zero(), Eigen::Vector2d(1, 0), 0, m), InputError);
}

BOOST_AUTO_TEST_CASE(the_pressure_puts_its_centre_under_the_mass_centre) {
  const ShapeInfo& s = shape("rect2");
  for (double dx : {0.0, 0.01, -0.014}) {
    ObjectProperties body = ObjectProperties::nominal(s);
    body.mass_centre_m.x() += dx;
    const PushedObjectSystem system(s, body, SupportFriction{}, RodContact{}, far_away_rod());
    const Footprint f = make_footprint(Outline(s));
    double total = 0;
    Eigen::Vector2d moment = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < f.area_m2.size(); ++i) {
      BOOST_TEST(system.element_loads_N()[i] >= 0.0);
      total += system.element_loads_N()[i];
      moment += system.element_loads_N()[i] * f.centre_m[i];
    }
    BOOST_TEST(total == s.mass_kg * kG, boost::test_tools::tolerance(1e-12));
    BOOST_TEST((moment / total - body.mass_centre_m).norm() < 1e-12);
  }
  ObjectProperties off = ObjectProperties::nominal(s);
  off.mass_centre_m.x() = 0.016;  // outside the middle third of the 90 mm width: a planar pressure cannot carry it
  BOOST_CHECK_THROW(PushedObjectSystem(s, off, SupportFriction{}, RodContact{}, far_away_rod()), InputError);
}

BOOST_AUTO_TEST_CASE(a_block_on_a_tilted_support_slides_down_at_g_sin_alpha_minus_mu_g_cos_alpha) {
  // The textbook incline: steeper than the friction angle, from rest, a = g (sin alpha - mu cos alpha) downhill.
  SupportFriction f;
  f.coefficient = 0.1;
  f.tilt_rad = 10 * M_PI / 180;
  f.downhill = Eigen::Vector2d(std::cos(0.5), std::sin(0.5));
  const PushedObjectSystem system(shape("rect2"), ObjectProperties::nominal(shape("rect2")), f, RodContact{},
                                  far_away_rod());
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(4, 0.1, 0.4);
  const Eigen::MatrixXd x = integrate(system, system.state_at_rest(Eigen::Vector3d(0, 0, 0.3)), times);
  const double a = kG * (std::sin(f.tilt_rad) - 0.1 * std::cos(f.tilt_rad));
  for (Eigen::Index k = 0; k < times.size(); ++k) {
    const Eigen::Vector2d moved =
        x.row(k).head<2>().transpose() - system.state_at_rest(Eigen::Vector3d(0, 0, 0.3)).head<2>();
    BOOST_TEST(moved.dot(f.downhill) == 0.5 * a * times(k) * times(k), boost::test_tools::tolerance(1e-3));
    BOOST_TEST(std::abs(moved.dot(Eigen::Vector2d(-f.downhill.y(), f.downhill.x()))) < 1e-9);
    BOOST_TEST(x.row(k).segment<2>(3).dot(f.downhill) == a * times(k), boost::test_tools::tolerance(1e-3));
    BOOST_TEST(std::abs(x(k, 5)) < 1e-6);
  }
  // The support carries the weight's normal component only.
  double load = 0;
  for (double l : system.element_loads_N()) load += l;
  BOOST_TEST(load == ObjectProperties::nominal(shape("rect2")).mass_kg * kG * std::cos(f.tilt_rad),
             boost::test_tools::tolerance(1e-12));
}

BOOST_AUTO_TEST_CASE(on_a_tilt_below_the_friction_angle_the_block_stays) {
  SupportFriction f;
  f.coefficient = 0.3;  // tan 10 deg = 0.176 < 0.3: static friction holds it
  f.tilt_rad = 10 * M_PI / 180;
  const PushedObjectSystem system(shape("hex"), ObjectProperties::nominal(shape("hex")), f, RodContact{},
                                  far_away_rod());
  const Eigen::VectorXd x0 = system.state_at_rest(Eigen::Vector3d(0.2, 0.1, 1.0));
  const Eigen::MatrixXd x = integrate(system, x0, Eigen::Vector2d(0.5, 1.0));
  // It creeps at eps sin / (mu cos) = 6 micrometres per second, the regularisation's slip.
  BOOST_TEST((x.row(1).head<2>().transpose() - x0.head<2>()).norm() < 1e-5);
}

BOOST_AUTO_TEST_CASE(anisotropic_friction_decelerates_along_each_body_axis_at_its_own_mu_g) {
  // mu_x / mu_y = 1.4 with mean 0.3: mu_x = 0.35, mu_y = 0.25. A slide along a body axis stops after v^2 / (2 mu g)
  // with that axis's mu, and goes straight on.
  SupportFriction f;
  f.coefficient = 0.3;
  f.anisotropy = 1.4;
  const ShapeInfo& s = shape("rect2");
  const PushedObjectSystem system(s, ObjectProperties::nominal(s), f, RodContact{}, far_away_rod());
  const double yaw = 0.7, v0 = 0.2;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(yaw).toRotationMatrix();
  for (int axis = 0; axis < 2; ++axis) {
    const double mu = axis == 0 ? 0.3 * 2 * 1.4 / 2.4 : 0.3 * 2 / 2.4;
    Eigen::VectorXd x0 = system.state_at_rest(Eigen::Vector3d(0, 0, yaw));
    const Eigen::Vector2d u = R.col(axis);
    x0.segment<2>(3) = v0 * u;
    const Eigen::MatrixXd x = integrate(system, x0, Eigen::Vector2d(0.5 * v0 / (mu * kG), 0.3));
    BOOST_TEST(x.row(0).segment<2>(3).norm() == 0.5 * v0, boost::test_tools::tolerance(2e-3));
    const Eigen::Vector2d moved = x.row(1).head<2>().transpose() - x0.head<2>();
    BOOST_TEST(moved.norm() == v0 * v0 / (2 * mu * kG), boost::test_tools::tolerance(2e-3));
    BOOST_TEST(std::abs(moved.normalized().dot(u) - 1) < 1e-9);
  }
  // Sliding obliquely, the friction force lies on the ellipse (f_x / A_x)^2 + (f_y / A_y)^2 = (mu m g)^2 and is
  // not opposite to the velocity: it points along -A^2 v (maximum dissipation).
  Eigen::VectorXd x = system.state_at_rest(Eigen::Vector3d(0, 0, yaw));
  const Eigen::Vector2d v_body = Eigen::Vector2d(1, 1).normalized() * 0.05;
  x.segment<2>(3) = R * v_body;
  const Eigen::Vector2d force_body = R.transpose() * system.support_wrench(x).force_N;
  const Eigen::Array2d A(2 * 1.4 / 2.4, 2 / 2.4);
  const double F = 0.3 * s.mass_kg * kG;
  BOOST_TEST((force_body.array() / A).matrix().norm() == F, boost::test_tools::tolerance(1e-6));
  const Eigen::Vector2d expected = -(A * A * v_body.array()).matrix().normalized();
  BOOST_TEST((force_body.normalized() - expected).norm() < 1e-6);
}

BOOST_AUTO_TEST_CASE(a_compliant_pusher_lags_its_commanded_path_by_force_times_compliance) {
  // A 500 N/m pusher on a 1.3 kg object rings at about sqrt(k / m) = 3 Hz, and Coulomb friction does not damp it: over
  // whole periods of the cruise the push carries mu m g and the tip lags its commanded point by f c.
  const ShapeInfo& s = shape("rect2");
  SupportFriction f;
  f.coefficient = 0.3;
  RodContact c;
  c.pusher_compliance_m_N = 2e-3;
  PusherMotion m;
  m.speed_m_s = 0.05;
  m.length_m = 0.1;
  const Eigen::Vector2d start(0.0, s.dim2_m / 2 + kPusherRadius_m);
  const PusherPath path(start, Eigen::Vector2d(0, -1), 0.1, m);
  const PushedObjectSystem system(s, ObjectProperties::nominal(s), f, c, path);
  BOOST_TEST(system.state_size() == 10);
  // The pusher's spring in series with the contact's: the ringing's period.
  const double period = 2 * M_PI * std::sqrt((2e-3 + 1 / c.stiffness_N_m) * s.mass_kg);
  const int n = 400;
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(n, 0.5, 0.5 + 4 * period * (n - 1) / n);
  const Eigen::MatrixXd x = integrate(system, system.state_at_rest(Eigen::Vector3d::Zero()), times);
  const double push = 0.3 * s.mass_kg * kG;
  double contact = 0, lag = 0, spring = 0, across = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::VectorXd xk = x.row(k).transpose();
    const RodWrench w = system.rod_wrench(times(k), xk);
    BOOST_TEST_REQUIRE(w.touching);
    contact += -w.force_on_object_N.y() / n;
    const Eigen::Vector2d behind = path.position_m(times(k)) - system.tip_position_m(times(k), xk);
    lag += -behind.y() / n;
    across = std::max(across, std::abs(behind.x()));
    spring += -system.pusher_spring_force_N(times(k), xk).y() / n;
  }
  BOOST_TEST(contact == push, boost::test_tools::tolerance(0.01));
  BOOST_TEST(spring == push, boost::test_tools::tolerance(0.01));
  BOOST_TEST(lag == push * 2e-3, boost::test_tools::tolerance(0.01));
  BOOST_TEST(across < 1e-7);
}

BOOST_AUTO_TEST_SUITE_END()
