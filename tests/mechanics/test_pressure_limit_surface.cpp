// The limit surface of a distributed support pressure against closed forms (a disk of uniform pressure: the largest
// torque over the largest force is 2R/3, and a pure rotation about the centre needs the torque mu m g 2R/3) and the
// quartic fitted to it against the exact summation over the footprint (Goyal, Ruina & Papadopoulos 1991; Zhou et al.
// 2017): on the dataset's outlines the quartic's twist direction follows the exact surface to a few degrees. A
// rim-weighted disk's torque ratio against its closed form 2R/3 (1 + w / 5).
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/pressure_limit_surface.hpp"
#include "pushpred/reading/shape_table.hpp"

using namespace pushpred;

namespace {

ShapeInfo disk(double radius_m) {
  ShapeInfo s;
  s.name = "disk";
  s.geometry = Geometry::Ellipse;
  s.dim1_m = radius_m;
  s.dim2_m = radius_m;
  s.mass_kg = 1;
  s.inertia_kgm2 = 1e-3;
  return s;
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
}

/// The twist direction in the metric the fit uses, (v, rho omega), of a (v, omega) direction.
Eigen::Vector3d scaled_twist(const Eigen::Vector3d& twist, double rho) { return {twist(0), twist(1), rho * twist(2)}; }

}  // namespace

BOOST_AUTO_TEST_SUITE(pressure_limit_surface)

BOOST_AUTO_TEST_CASE(a_disk_of_uniform_pressure_has_torque_ratio_two_thirds_of_its_radius) {
  const double R = 0.05;
  const SupportPressure p = planar_support_pressure(make_footprint(Outline(disk(R)), 40), Eigen::Vector2d::Zero());
  BOOST_TEST(p.torque_ratio_m == 2 * R / 3, boost::test_tools::tolerance(2e-3));
  // A pure rotation about the centre: no force, the torque mu m g 2R/3 (per unit mu m g: 2R/3).
  const double mu = 0.3, m = 0.8, g = 9.81;
  const Eigen::Vector3d w = mu * m * g * limit_surface_wrench(p, Eigen::Vector2d::Zero(), 2.0);
  BOOST_TEST(std::abs(w(0)) < 1e-9);
  BOOST_TEST(std::abs(w(1)) < 1e-9);
  BOOST_TEST(w(2) == mu * m * g * 2 * R / 3, boost::test_tools::tolerance(2e-3));
  // A pure translation: the whole force against the velocity, no torque.
  const Eigen::Vector3d t = limit_surface_wrench(p, Eigen::Vector2d(0.0, 0.1), 0.0);
  BOOST_TEST(t(1) == 1.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(std::abs(t(2)) < 1e-12);
  // The quartic fitted to it gives both back, to its own error (the disk's surface is not a quartic: 0.6 % at the
  // pure rotation).
  const PolynomialLimitSurface ls = PolynomialLimitSurface::fit(p);
  const Eigen::Vector3d spin = ls.wrench_for_twist(Eigen::Vector2d::Zero(), -1.0);
  BOOST_TEST(spin(2) == -2 * R / 3, boost::test_tools::tolerance(1e-2));
  BOOST_TEST(spin.head<2>().norm() < 1e-4);
  const Eigen::Vector3d slide = ls.wrench_for_twist(Eigen::Vector2d(1.0, 0.0), 0.0);
  BOOST_TEST(slide(0) == 1.0, boost::test_tools::tolerance(5e-3));
  BOOST_TEST(std::abs(slide(2)) < 1e-6);
}

BOOST_AUTO_TEST_CASE(a_tilted_pressure_is_centred_where_it_is_asked_to_be) {
  const ShapeInfo& rect1 = ShapeTable::published().find("rect1");
  const Eigen::Vector2d centre(0.006, -0.003);
  const SupportPressure p = planar_support_pressure(make_footprint(Outline(rect1)), centre);
  Eigen::Vector2d first_moment = Eigen::Vector2d::Zero();
  double total = 0;
  for (std::size_t i = 0; i < p.share.size(); ++i) {
    first_moment += p.share[i] * p.offset_m[i];
    total += p.share[i];
  }
  BOOST_TEST(total == 1.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(first_moment.norm() < 1e-12);
  // A translating object feels no torque about its centre of pressure.
  BOOST_TEST(std::abs(limit_surface_wrench(p, Eigen::Vector2d(0.3, -0.2), 0.0)(2)) < 1e-12);
  BOOST_CHECK_THROW(planar_support_pressure(make_footprint(Outline(rect1)), Eigen::Vector2d(0.2, 0)), InputError);
}

BOOST_AUTO_TEST_CASE(a_rim_weighted_disk_has_its_closed_form_torque_ratio_and_stays_non_negative) {
  // p ~ 1 + w (2 r^2 / R^2 - 1) on a disk (<r^2> = R^2 / 2): int p r dA / int p dA = 2R/3 (1 + w / 5), and the
  // pressure stays non-negative for w in [-1, 1] (zero at the rim for w = -1, at the centre for w = 1).
  const double R = 0.05;
  const Footprint footprint = make_footprint(Outline(disk(R)), 40);
  const RimWeightRange range = rim_weight_range(footprint);
  BOOST_TEST_MESSAGE("disk rim weight range [" << range.lower << ", " << range.upper << "] (cell centres)");
  BOOST_TEST(range.lower == -1.0, boost::test_tools::tolerance(0.05));
  BOOST_TEST(range.upper == 1.0, boost::test_tools::tolerance(0.05));
  for (const double w : {-0.8, -0.4, 0.4, 0.9}) {
    const SupportPressure p = planar_support_pressure(footprint, Eigen::Vector2d::Zero(), w);
    BOOST_TEST(p.rim_weight == w);
    BOOST_TEST(p.torque_ratio_m == 2 * R / 3 * (1 + w / 5), boost::test_tools::tolerance(3e-3));
    for (const double share : p.share) BOOST_TEST(share >= 0);
    // The quartic's pure rotation gives it back to its own error (as the uniform disk's above).
    const Eigen::Vector3d spin = PolynomialLimitSurface::fit(p).wrench_for_twist(Eigen::Vector2d::Zero(), 1.0);
    BOOST_TEST(spin(2) == 2 * R / 3 * (1 + w / 5), boost::test_tools::tolerance(1.5e-2));
  }
  BOOST_CHECK_THROW(planar_support_pressure(footprint, Eigen::Vector2d::Zero(), range.lower - 0.05), InputError);
  BOOST_CHECK_THROW(planar_support_pressure(footprint, Eigen::Vector2d::Zero(), range.upper + 0.05), InputError);
  BOOST_CHECK_THROW(planar_support_pressure(footprint, Eigen::Vector2d::Zero(), std::nan("")), InputError);
}

BOOST_AUTO_TEST_CASE(a_rim_weighted_tilted_pressure_is_centred_where_it_is_asked_to_be) {
  // The rim shape about the right triangle's centroid is not symmetric: the tilt must still put the centre of
  // pressure where it is asked to be. A rectangle's range is set by its corners: -1 / (3 - 1) = -0.5 at the corner
  // itself, a little beyond at the corner cells' centres.
  for (const char* name : {"rect1", "tri1"}) {
    const Footprint footprint = make_footprint(Outline(ShapeTable::published().find(name)));
    const Eigen::Vector2d centre = footprint.centroid_m + Eigen::Vector2d(0.002, -0.001);
    const SupportPressure p = planar_support_pressure(footprint, centre, 0.5);
    Eigen::Vector2d first_moment = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < p.share.size(); ++i) first_moment += p.share[i] * p.offset_m[i];
    BOOST_TEST(first_moment.norm() < 1e-12, name);
    BOOST_TEST(std::abs(limit_surface_wrench(p, Eigen::Vector2d(0.3, -0.2), 0.0)(2)) < 1e-12, name);
  }
  const RimWeightRange rect = rim_weight_range(make_footprint(Outline(ShapeTable::published().find("rect1"))));
  BOOST_TEST(rect.lower < -0.5);
  BOOST_TEST(rect.lower > -0.6);
}

BOOST_AUTO_TEST_CASE(the_quartic_follows_the_exact_limit_surface_of_the_dataset_outlines) {
  std::mt19937 rng(345000);
  std::normal_distribution<double> normal;
  for (const char* name : {"rect1", "rect3", "ellip1", "ellip3", "hex", "tri1"}) {
    const ShapeInfo& shape = ShapeTable::published().find(name);
    const Footprint footprint = make_footprint(Outline(shape));
    for (const Eigen::Vector2d& offset : {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.004, 0.002)}) {
      const SupportPressure p = planar_support_pressure(footprint, footprint.centroid_m + offset);
      const PolynomialLimitSurface ls = PolynomialLimitSurface::fit(p);
      double worst_angle = 0, mean_angle = 0, worst_value = 0;
      const int n = 400;
      for (int i = 0; i < n; ++i) {
        const Eigen::Vector3d twist(normal(rng), normal(rng), normal(rng) / p.torque_ratio_m);
        const Eigen::Vector3d w = limit_surface_wrench(p, twist.head<2>(), twist(2));
        const double angle =
            angle_between(scaled_twist(ls.twist_direction(w), p.torque_ratio_m), scaled_twist(twist, p.torque_ratio_m));
        worst_angle = std::max(worst_angle, angle);
        mean_angle += angle / n;
        worst_value = std::max(worst_value, std::abs(ls.value(w) - 1));
        // And back: the wrench the quartic gives for the twist is near the exact one.
        const Eigen::Vector3d back = ls.wrench_for_twist(twist.head<2>(), twist(2));
        BOOST_TEST(std::abs(ls.value(back) - 1) < 1e-9);
      }
      BOOST_TEST_MESSAGE(name << " centre offset " << offset.transpose() * 1e3 << " mm: twist direction off by "
                              << mean_angle * 180 / M_PI << " deg mean, " << worst_angle * 180 / M_PI
                              << " deg worst; |H - 1| <= " << worst_value);
      // A quartic cannot follow the exact surface everywhere: measured on these outlines the twist direction is off
      // by 0.9-1.9 degrees on average and 1.8-9.4 at worst (the right triangle, whose surface is least
      // symmetric), |H - 1| up to 0.08 (Zhou et al. report errors of this size for their quartics).
      BOOST_TEST(mean_angle * 180 / M_PI < 2.0, name);
      BOOST_TEST(worst_angle * 180 / M_PI < 10.0, name);
      BOOST_TEST(worst_value < 0.1, name);
    }
  }
}

BOOST_AUTO_TEST_SUITE_END()
