// The support's Coulomb friction against closed forms worked out here: a point sliding, a square and a disk of
// uniform pressure translating and turning. The footprint is a grid of area elements, so the turning object's
// torque carries the grid's quadrature error (the tolerance says how much); everything else is exact up to
// rounding and the regularisation eps^2 / |v|^2.
#include <boost/test/unit_test.hpp>
#include <cmath>

#include "pushpred/mechanics/support_friction.hpp"
#include "pushpred/reading/shape_table.hpp"

using namespace pushpred;

namespace {

/// The footprint's elements with their share of `total_force_N` under uniform pressure, summed by the law.
Eigen::Vector3d uniform_footprint_wrench(const Footprint& footprint, const Eigen::Vector2d& velocity, double omega,
                                         double total_force_N, double regularisation = 1e-9) {
  return footprint_friction_wrench(
      footprint.area_m2.size(), [&](std::size_t i) { return footprint.centre_m[i]; }, velocity, omega,
      regularisation, [&](std::size_t i, const Eigen::Vector2d&, double) {
        return total_force_N * footprint.area_m2[i] / footprint.total_area_m2;
      });
}

const double kSqrt2 = std::sqrt(2.0);

}  // namespace

BOOST_AUTO_TEST_SUITE(support_friction)

BOOST_AUTO_TEST_CASE(a_sliding_point_feels_the_force_against_its_velocity_softened_by_eps) {
  // |v| = 5, eps = 12: sqrt(25 + 144) = 13, so f = -2 (3, 4) / 13.
  const Eigen::Vector2d f = regularised_coulomb_force(Eigen::Vector2d(3, 4), 2.0, 12.0);
  BOOST_TEST(f.x() == -6.0 / 13.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(f.y() == -8.0 / 13.0, boost::test_tools::tolerance(1e-15));
  // eps << |v|: the full Coulomb force -F v / |v|.
  const Eigen::Vector2d sliding = regularised_coulomb_force(Eigen::Vector2d(0.3, -0.4), 2.0, 1e-9);
  BOOST_TEST(sliding.x() == -1.2, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(sliding.y() == 1.6, boost::test_tools::tolerance(1e-12));
  // At rest nothing.
  BOOST_TEST(regularised_coulomb_force(Eigen::Vector2d::Zero(), 2.0, 1e-5).norm() == 0.0);
}

BOOST_AUTO_TEST_CASE(a_point_of_a_turning_body_moves_with_omega_cross_r) {
  // v = (1, 2), omega = 3, r = (0.5, -1): omega x r = (3, 1.5), so (4, 3.5).
  const Eigen::Vector2d v = rigid_point_velocity(Eigen::Vector2d(1, 2), 3.0, Eigen::Vector2d(0.5, -1));
  BOOST_TEST(v.x() == 4.0);
  BOOST_TEST(v.y() == 3.5);
  BOOST_TEST(planar_moment(Eigen::Vector2d(2, 0), Eigen::Vector2d(0, 3)) == 6.0);    // counter-clockwise
  BOOST_TEST(planar_moment(Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 0)) == -1.0);   // clockwise
}

BOOST_AUTO_TEST_CASE(a_translating_square_feels_mu_m_g_against_its_velocity_and_no_torque) {
  const ShapeInfo& square = ShapeTable::published().find("rect1");  // 90 mm x 90 mm
  const Footprint footprint = make_footprint(Outline(square));
  const double F = 0.35 * square.mass_kg * 9.81;
  const Eigen::Vector3d w = uniform_footprint_wrench(footprint, Eigen::Vector2d(0.06, -0.08), 0.0, F);
  BOOST_TEST(w(0) == -0.6 * F, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(w(1) == 0.8 * F, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(std::abs(w(2)) < 1e-12 * F * 0.09);  // the centroid is the centre of pressure
}

BOOST_AUTO_TEST_CASE(a_square_turning_about_its_centre_feels_mu_m_g_times_its_mean_radius) {
  // The mean distance from the centre over a square of side a: a (sqrt 2 + ln(1 + sqrt 2)) / 6 = 0.3826 a.
  const ShapeInfo& square = ShapeTable::published().find("rect1");
  const double a = square.dim1_m;
  const double mean_radius = a * (kSqrt2 + std::log(1 + kSqrt2)) / 6;
  const Footprint footprint = make_footprint(Outline(square));
  const double F = 2.0;
  const Eigen::Vector3d w = uniform_footprint_wrench(footprint, Eigen::Vector2d::Zero(), 0.5, F);
  BOOST_TEST(std::abs(w(0)) < 1e-12 * F);
  BOOST_TEST(std::abs(w(1)) < 1e-12 * F);
  // 20 x 20 cells, each counted at its centre: the midpoint rule on the convex |r| comes out about 0.1 % low.
  BOOST_TEST(w(2) == -F * mean_radius, boost::test_tools::tolerance(2e-3));
  BOOST_TEST(uniform_pressure_torque_ratio(footprint, Eigen::Vector2d::Zero()) == mean_radius,
             boost::test_tools::tolerance(2e-3));
}

BOOST_AUTO_TEST_CASE(a_disk_turning_about_its_centre_feels_two_thirds_of_mu_m_g_times_its_radius) {
  const ShapeInfo& disk = ShapeTable::published().find("ellip1");  // semi-axes 52.5 mm and 52.5 mm
  const double R = disk.dim1_m;
  const Footprint footprint = make_footprint(Outline(disk));
  const double F = 3.0;
  const Eigen::Vector3d w = uniform_footprint_wrench(footprint, Eigen::Vector2d::Zero(), -2.0, F);
  // Cells cut by the rim are sampled (8 x 8 points each): with the cells' quadrature about 0.1 % low here too.
  BOOST_TEST(w(2) == F * 2 * R / 3, boost::test_tools::tolerance(5e-3));
  BOOST_TEST(std::abs(w(0)) < 1e-3 * F);
  BOOST_TEST(std::abs(w(1)) < 1e-3 * F);
}

BOOST_AUTO_TEST_CASE(elements_without_force_are_left_out_and_each_carries_its_own) {
  // Two elements at (+-1, 0) from the reference, the body turning at omega = 1: they slide at (0, 1) and (0, -1).
  // Only the first carries force (1 N): f = (0, -1) at (1, 0), moment -1.
  const Eigen::Vector2d offsets[2] = {Eigen::Vector2d(1, 0), Eigen::Vector2d(-1, 0)};
  const Eigen::Vector3d w = footprint_friction_wrench(
      2, [&](std::size_t i) { return offsets[i]; }, Eigen::Vector2d::Zero(), 1.0, 1e-12,
      [](std::size_t i, const Eigen::Vector2d&, double speed2) {
        BOOST_TEST(speed2 == 1.0);
        return i == 0 ? 1.0 : 0.0;
      });
  BOOST_TEST(w(0) == 0.0);
  BOOST_TEST(w(1) == -1.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(w(2) == -1.0, boost::test_tools::tolerance(1e-15));
}

BOOST_AUTO_TEST_CASE(the_unregularised_integral_gives_the_full_force_and_nothing_at_rest) {
  const Footprint footprint = make_footprint(Outline(ShapeTable::published().find("rect2")));
  const Eigen::Vector3d w = integrated_friction_wrench(footprint, footprint.centroid_m, 10.0, 0.3,
                                                       Eigen::Vector2d(0, 0.2), 0.0);
  BOOST_TEST(w(0) == 0.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(w(1) == -3.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(integrated_friction_wrench(footprint, footprint.centroid_m, 10.0, 0.3, Eigen::Vector2d::Zero(), 0.0)
                 .norm() == 0.0);
}

BOOST_AUTO_TEST_CASE(the_ellipsoidal_limit_surface_in_closed_forms) {
  // v = (3, 4), c = 2, omega = 6, eps = 0: s = sqrt(25 + 144) = 13, so (f, m) = -F (3, 4, c^2 omega = 24) / 13.
  const Eigen::Vector3d w = ellipsoidal_limit_surface_wrench(Eigen::Vector2d(3, 4), 6.0, 13.0, 2.0, 0.0);
  BOOST_TEST(w(0) == -3.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(w(1) == -4.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(w(2) == -24.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(limit_surface_sliding_speed(Eigen::Vector2d(3, 4), 6.0, 2.0, 0.0) == 13.0,
             boost::test_tools::tolerance(1e-15));
  // The regularisation adds eps^2 under the root: 169 + 7056 = 85^2 with eps = 84.
  BOOST_TEST(limit_surface_sliding_speed(Eigen::Vector2d(3, 4), 6.0, 2.0, 84.0) == 85.0,
             boost::test_tools::tolerance(1e-15));
  const Eigen::Vector3d soft = ellipsoidal_limit_surface_wrench(Eigen::Vector2d(3, 4), 6.0, 85.0, 2.0, 84.0);
  BOOST_TEST(soft(2) == -24.0, boost::test_tools::tolerance(1e-15));
  // Unregularised, the wrench lies on the surface |f|^2 + (m / c)^2 = F^2, whatever the twist: 9 + 16 + 144 = 169.
  BOOST_TEST(ellipsoidal_limit_surface_force(w(0), w(1), w(2), 2.0) == 13.0, boost::test_tools::tolerance(1e-15));
  const Eigen::Vector3d spin = ellipsoidal_limit_surface_wrench(Eigen::Vector2d(0, 0), -0.5, 7.0, 0.04, 0.0);
  BOOST_TEST(std::abs(spin(0)) == 0.0);
  BOOST_TEST(spin(2) == 7.0 * 0.04, boost::test_tools::tolerance(1e-15));  // pure turning: the largest torque, c F
  // c = 0 is Coulomb friction on the whole body: the point law, and no torque.
  const Eigen::Vector3d coulomb = ellipsoidal_limit_surface_wrench(Eigen::Vector2d(3, 4), 6.0, 2.0, 0.0, 12.0);
  BOOST_TEST(coulomb(0) == -6.0 / 13.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(coulomb(1) == -8.0 / 13.0, boost::test_tools::tolerance(1e-15));
  BOOST_TEST(coulomb(2) == 0.0);
}

BOOST_AUTO_TEST_SUITE_END()
