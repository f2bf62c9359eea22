// The contact geometry's stand-in outlines against points placed by hand.
#include <boost/test/unit_test.hpp>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/contact_outline.hpp"
#include "pushpred/reading/shape_table.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(contact_outline)

BOOST_AUTO_TEST_CASE(a_straight_edge_measures_along_its_unit_normal) {
  // The edge y = 0 with outward normal (0, 2) (not unit: it is normalised); the point (0.3, 0.5) is 0.5 outside.
  const auto edge = straight_edge(Eigen::Vector2d::Zero(), Eigen::Vector2d(0, 2));
  const Outline::Closest c = edge->closest(Eigen::Vector2d(0.3, 0.5));
  BOOST_TEST(c.signed_distance_m == 0.5);
  BOOST_TEST((c.point_m - Eigen::Vector2d(0.3, 0)).norm() == 0.0);
  BOOST_TEST((c.normal - Eigen::Vector2d(0, 1)).norm() == 0.0);
  BOOST_TEST(edge->closest(Eigen::Vector2d(-2, -0.25)).signed_distance_m == -0.25);  // inside
}

BOOST_AUTO_TEST_CASE(a_circular_edge_measures_from_its_rim) {
  // Centre (1, 1), radius 0.5: the point (1, 3) is 1.5 outside, nearest to (1, 1.5).
  const auto circle = circular_edge(Eigen::Vector2d(1, 1), 0.5);
  const Outline::Closest c = circle->closest(Eigen::Vector2d(1, 3));
  BOOST_TEST(c.signed_distance_m == 1.5);
  BOOST_TEST((c.point_m - Eigen::Vector2d(1, 1.5)).norm() == 0.0);
  BOOST_TEST((c.normal - Eigen::Vector2d(0, 1)).norm() == 0.0);
  // At the centre every direction is nearest: the normal is +x by convention, the distance -r.
  const Outline::Closest centre = circle->closest(Eigen::Vector2d(1, 1));
  BOOST_TEST(centre.signed_distance_m == -0.5);
  BOOST_TEST((centre.normal - Eigen::Vector2d::UnitX()).norm() == 0.0);
}

BOOST_AUTO_TEST_CASE(the_shapes_outline_is_the_shape_tables_and_bad_stand_ins_are_input_errors) {
  // rect2 is 89.91 mm x 112.58 mm about its centre: the point 10 mm beyond its +y side is 10 mm outside.
  const ShapeInfo& rect2 = ShapeTable::published().find("rect2");
  const Outline::Closest c = shape_outline(rect2)->closest(Eigen::Vector2d(0, rect2.dim2_m / 2 + 0.01));
  BOOST_TEST(c.signed_distance_m == 0.01, boost::test_tools::tolerance(1e-12));
  BOOST_CHECK_THROW(shape_outline(ShapeTable::published().find("butter")), InputError);
  BOOST_CHECK_THROW(straight_edge(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()), InputError);
  BOOST_CHECK_THROW(circular_edge(Eigen::Vector2d::Zero(), 0.0), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
