// The nominal inertia: the shape table's values unless overridden, and an error naming the shape without one.
#include <boost/test/unit_test.hpp>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/mechanics/nominal_inertia.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(nominal_inertia_choice)

BOOST_AUTO_TEST_CASE(the_nominal_inertia_is_the_tables_unless_overridden) {
  ShapeInfo s;
  s.name = "block";
  s.mass_kg = 0.8;
  s.inertia_kgm2 = 1.2e-3;
  BOOST_TEST((nominal_inertia(s) - Eigen::Vector3d(0.8, 0.8, 1.2e-3)).norm() == 0.0);
  BOOST_TEST((nominal_inertia(s, 1.5) - Eigen::Vector3d(1.5, 1.5, 1.2e-3)).norm() == 0.0);
  BOOST_TEST((nominal_inertia(s, 0, 2e-3) - Eigen::Vector3d(0.8, 0.8, 2e-3)).norm() == 0.0);
  s.inertia_kgm2 = 0;  // an unlisted shape without an override
  try {
    nominal_inertia(s);
    BOOST_FAIL("a shape without a moment of inertia was accepted");
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()) == "moment of inertia of shape 'block' [kg m^2] must be positive and finite, got 0");
  }
}

BOOST_AUTO_TEST_SUITE_END()
