#include <boost/test/unit_test.hpp>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/shape_table.hpp"

using namespace pushpred;

BOOST_AUTO_TEST_SUITE(shape_table)

BOOST_AUTO_TEST_CASE(the_published_table_holds_the_papers_rect2) {
  const ShapeInfo& rect2 = ShapeTable::published().find("rect2");
  BOOST_TEST(rect2.mass_kg == 1.045);        // the paper's nominal mass
  BOOST_TEST(rect2.inertia_kgm2 == 0.001808);  // the paper rounds it to 0.0018
  BOOST_TEST(rect2.dim1_m == 0.08991);
  BOOST_TEST(ShapeTable::published().shapes().size() == 11u);
  for (const char* name : {"rect1", "ellip1", "ellip3", "hex", "butter", "tri1"})
    BOOST_TEST(ShapeTable::published().contains(name));
}

BOOST_AUTO_TEST_CASE(outlines_have_the_published_size) {
  const auto& t = ShapeTable::published();
  BOOST_TEST(signed_distance_to_outline(t.find("rect1"), {0.045, 0.0}) == 0.0, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(signed_distance_to_outline(t.find("rect1"), {0.0, 0.0}) == -0.045, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(signed_distance_to_outline(t.find("ellip3"), {0.0, 0.0785 + 0.01}) == 0.01,
             boost::test_tools::tolerance(1e-4));
  BOOST_TEST(signed_distance_to_outline(t.find("hex"), {0.0605, 0.0}) == 0.0, boost::test_tools::tolerance(1e-12));
  BOOST_CHECK_THROW(outline_polygon(t.find("butter")), InputError);
}

BOOST_AUTO_TEST_CASE(a_bad_table_names_the_line) {
  try {
    ShapeTable::from_csv_text("shape,mass_kg,inertia_kgm2,centroid_x_m,centroid_y_m,geometry,dim1_m,dim2_m\n"
                              "box,heavy,0.1,0,0,rect,0.1,0.1\n",
                              "mine.csv");
    BOOST_ERROR("no error");
  } catch (const InputError& e) {
    BOOST_TEST(std::string(e.what()) == "mine.csv:2: 'heavy' is not a number");
  }
  BOOST_CHECK_THROW(ShapeTable::from_csv_file("/nonexistent/shapes.csv"), InputError);
  BOOST_CHECK_THROW(ShapeTable::published().find("teapot"), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
