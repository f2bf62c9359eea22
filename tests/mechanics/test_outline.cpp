#define BOOST_TEST_MODULE mechanics
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "pushpred/core/error.hpp"
#include "pushpred/preprocessing/synchronised_push.hpp"
#include "pushpred/mechanics/outline.hpp"
#include "test_support.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(outline)

BOOST_AUTO_TEST_CASE(polygon_distances_agree_with_the_shape_table) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-0.12, 0.12);
  for (const char* name : {"rect2", "hex", "tri2"}) {
    const ShapeInfo& s = ShapeTable::published().find(name);
    const Outline o(s);
    for (int k = 0; k < 400; ++k) {
      const Eigen::Vector2d p(coord(rng), coord(rng));
      const Outline::Closest c = o.closest(p);
      BOOST_TEST(c.signed_distance_m == signed_distance_to_outline(s, p), boost::test_tools::tolerance(1e-12));
      BOOST_TEST(c.normal.norm() == 1.0, boost::test_tools::tolerance(1e-12));
      // The nearest point is on the outline and the point lies along its normal from there.
      BOOST_TEST(std::abs(signed_distance_to_outline(s, c.point_m)) < 1e-12);
      BOOST_TEST((c.point_m + c.signed_distance_m * c.normal - p).norm() < 1e-12);
    }
  }
}

BOOST_AUTO_TEST_CASE(ellipse_distances_are_exact_not_a_sampled_polygon) {
  const ShapeInfo& s = ShapeTable::published().find("ellip3");  // a = 52.5 mm along x, b = 78.5 mm along y
  const Outline o(s);
  for (int k = 0; k < 360; k += 7) {
    const double phi = k * M_PI / 180;
    const Eigen::Vector2d on(s.dim1_m * std::cos(phi), s.dim2_m * std::sin(phi));
    const Eigen::Vector2d n = Eigen::Vector2d(s.dim2_m * std::cos(phi), s.dim1_m * std::sin(phi)).normalized();
    for (double d : {-0.004, -0.0003, 0.0, 0.0047, 0.02}) {
      const Outline::Closest c = o.closest(on + d * n);
      BOOST_TEST(c.signed_distance_m == d, boost::test_tools::tolerance(1e-9));
      BOOST_TEST((c.point_m - on).norm() < 1e-9);
      BOOST_TEST((c.normal - n).norm() < 1e-7);
    }
  }
}

BOOST_AUTO_TEST_CASE(contact_sides_follow_the_dataset_convention_of_the_real_files) {
  // In every real file of a listed outline the tip starts at (within a few millimetres of: placement and
  // tracking) the point the file name's side and position give, outside the outline along its normal. The next
  // position on a side (s +- 0.1) or another side would be 6 mm or more away.
  std::vector<double> errors;
  for (const auto& path : list_recordings(resolve_data_folder(), "abs")) {
    const std::string name = path.filename().string();
    if (name.find("butter") != std::string::npos) continue;
    const SynchronisedPush p = load_push(path);
    const Outline o(p.shape);
    const Outline::Closest side =
        o.point_on_side(static_cast<int>(std::round(p.push.contact_side)), p.push.contact_position);
    const Eigen::Vector2d expected = side.point_m + kPusherRadius_m * side.normal;
    const double c = std::cos(p.pose(0, 2)), s = std::sin(p.pose(0, 2));
    const Eigen::Vector2d d = (p.tip_m.row(0) - p.pose.row(0).head<2>()).transpose();
    const Eigen::Vector2d tip_body(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
    errors.push_back((tip_body - expected).norm());
    BOOST_TEST(errors.back() < 4e-3, name);
  }
  BOOST_TEST(errors.size() == 50u);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  BOOST_TEST(errors[errors.size() / 2] < 1.5e-3);
}

BOOST_AUTO_TEST_CASE(the_footprint_has_the_outline_area_and_centroid) {
  auto area_of = [](const ShapeInfo& s) {
    if (s.geometry == Geometry::Rectangle) return s.dim1_m * s.dim2_m;
    if (s.geometry == Geometry::Ellipse) return M_PI * s.dim1_m * s.dim2_m;
    if (s.geometry == Geometry::Hexagon) return 1.5 * std::sqrt(3.0) * s.dim1_m * s.dim1_m;
    return 0.5 * s.dim1_m * s.dim2_m;
  };
  for (const char* name : {"rect2", "ellip1", "ellip3", "hex", "tri3"}) {
    const ShapeInfo& s = ShapeTable::published().find(name);
    const Footprint f = make_footprint(Outline(s));
    // Exact for polygons (cells clipped by the sides), sampled for ellipses.
    BOOST_TEST(f.total_area_m2 == area_of(s),
               boost::test_tools::tolerance(s.geometry == Geometry::Ellipse ? 1e-3 : 1e-9));
    BOOST_TEST((f.centroid_m - s.centroid_m).norm() < 1e-9, name);
    BOOST_TEST(f.area_m2.size() >= 200u);
  }
}

BOOST_AUTO_TEST_CASE(a_side_or_position_that_does_not_exist_is_an_input_error) {
  const Outline rect(ShapeTable::published().find("rect2"));
  BOOST_CHECK_THROW(rect.point_on_side(4, 0.5), InputError);
  BOOST_CHECK_THROW(rect.point_on_side(-1, 0.5), InputError);
  BOOST_CHECK_THROW(rect.point_on_side(0, 1.2), InputError);
  BOOST_CHECK_THROW(Outline(ShapeTable::published().find("ellip1")).point_on_side(1, 0.5), InputError);
  BOOST_CHECK_THROW(Outline(ShapeTable::published().find("butter")), InputError);
}

BOOST_AUTO_TEST_CASE(an_own_polygon_with_a_reflex_corner_has_the_l_shapes_area_and_contact_geometry) {
  // An L: a 40 x 20 mm bar with a 20 x 20 mm square on its left end. By hand: area 1200 mm^2, area centroid
  // (50/3, 50/3) mm; the reflex corner at (20, 20) mm.
  ShapeInfo l;
  l.name = "ell";
  l.mass_kg = 0.3;
  l.inertia_kgm2 = 1e-4;
  l.geometry = Geometry::Polygon;
  l.vertices_m = {{0, 0}, {0.04, 0}, {0.04, 0.02}, {0.02, 0.02}, {0.02, 0.04}, {0, 0.04}};
  const Outline outline(l);
  BOOST_TEST(!outline.is_convex_polygon());
  BOOST_TEST(outline.side_count() == 6);
  BOOST_TEST(outline.contains({0.01, 0.03}));
  BOOST_TEST(!outline.contains({0.03, 0.03}));  // in the notch
  const Outline::Closest notch = outline.closest({0.03, 0.025});
  BOOST_TEST(notch.signed_distance_m == 0.005, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(notch.normal.y() == 1.0, boost::test_tools::tolerance(1e-12));  // the bar's top side faces up
  const Outline::Closest inside = outline.closest({0.015, 0.015});
  // Nearest the reflex corner, 5 mm away along each axis (the sides it joins end there).
  BOOST_TEST(inside.signed_distance_m == -std::hypot(0.005, 0.005), boost::test_tools::tolerance(1e-12));
  BOOST_TEST(inside.normal.x() == std::sqrt(0.5), boost::test_tools::tolerance(1e-12));
  const Footprint f = make_footprint(outline, 40, 8);
  BOOST_TEST(f.total_area_m2 == 1.2e-3, boost::test_tools::tolerance(1e-3));
  BOOST_TEST(f.centroid_m.x() == 0.05 / 3, boost::test_tools::tolerance(1e-3));
  BOOST_TEST(f.centroid_m.y() == 0.05 / 3, boost::test_tools::tolerance(1e-3));
}

BOOST_AUTO_TEST_SUITE_END()
