#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/shape_table.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::contains;
using pushpred::testing::input_error;
using pushpred::testing::TempFolder;

namespace {

std::string one_shape(const std::string& fields) { return R"({"shapes": [{"name": "x", )" + fields + "}]}"; }

const std::string kCircle = R"("outline": {"kind": "circle", "radius_m": 0.05})";
const std::string kHeader = "shape,mass_kg,inertia_kgm2,centroid_x_m,centroid_y_m,geometry,dim1_m,dim2_m\n";

}  // namespace

BOOST_AUTO_TEST_SUITE(own_shapes)

BOOST_AUTO_TEST_CASE(a_json_rectangle_is_the_dataset_rectangle) {
  const ShapeTable t = ShapeTable::from_json_text(
      one_shape(
          R"("mass_kg": 1.045, "inertia_kgm2": 0.001808, "outline": {"kind": "rectangle", "sides_m": [0.08991, 0.11258]})"),
      "own.json");
  const ShapeInfo& mine = t.find("x");
  const ShapeInfo& rect2 = ShapeTable::published().find("rect2");
  BOOST_TEST(mine.own);
  BOOST_TEST(!rect2.own);
  BOOST_TEST((mine.geometry == rect2.geometry));
  BOOST_TEST(mine.dim1_m == rect2.dim1_m);
  BOOST_TEST(mine.dim2_m == rect2.dim2_m);
  BOOST_TEST(outline_polygon(mine) == outline_polygon(rect2));
}

BOOST_AUTO_TEST_CASE(a_non_convex_polygon_has_the_area_centroid_and_the_right_signed_distance) {
  // An L: a 40 x 20 mm bar with a 20 x 20 mm square on its left end; by hand its area centroid is (50/3, 50/3) mm.
  const ShapeTable t = ShapeTable::from_json_text(
      one_shape(R"("mass_kg": 0.3, "inertia_kgm2": 1e-4, "outline": {"kind": "polygon", "vertices_m": )"
                R"([[0, 0], [0.04, 0], [0.04, 0.02], [0.02, 0.02], [0.02, 0.04], [0, 0.04]]})"),
      "own.json");
  const ShapeInfo& l = t.find("x");
  BOOST_TEST(l.centroid_m.x() == 0.05 / 3, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(l.centroid_m.y() == 0.05 / 3, boost::test_tools::tolerance(1e-12));
  // In the notch: (30, 30) mm is outside, 10 mm above the bar's top side; (50, 30) mm is nearest the corner (40, 20).
  BOOST_TEST(signed_distance_to_outline(l, {0.03, 0.03}) == 0.01, boost::test_tools::tolerance(1e-9));
  BOOST_TEST(signed_distance_to_outline(l, {0.05, 0.03}) == std::hypot(0.01, 0.01), boost::test_tools::tolerance(1e-9));
  BOOST_TEST(signed_distance_to_outline(l, {0.01, 0.01}) == -0.01, boost::test_tools::tolerance(1e-9));
}

BOOST_AUTO_TEST_CASE(own_shapes_add_to_and_replace_the_known_ones) {
  const ShapeTable own = ShapeTable::from_json_text(
      R"({"shapes": [{"name": "hex", "mass_kg": 2, "inertia_kgm2": 0.002, "outline": {"kind": "circle", "radius_m": 0.06}},)"
      R"({"name": "tinydisc", "mass_kg": 0.1, "inertia_kgm2": 1e-5, "outline": {"kind": "circle", "radius_m": 0.01}}]})",
      "own.json");
  const ShapeTable merged = ShapeTable::published().with(own);
  BOOST_TEST(merged.shapes().size() == ShapeTable::published().shapes().size() + 1);
  BOOST_TEST(merged.find("hex").mass_kg == 2.0);
  BOOST_TEST(merged.find("tinydisc").own);
  BOOST_TEST(ShapeTable::published().find("hex").mass_kg == 0.9827);  // the published table is untouched
}

BOOST_AUTO_TEST_CASE(a_csv_polygon_reads_its_vertices_from_the_outline_file) {
  const TempFolder temp;
  const std::filesystem::path& folder = temp.path();
  std::ofstream(folder / "tri.csv") << "# a right triangle\nx_m,y_m\n0,0\n0.1,0\n0,0.05\n";
  std::ofstream(folder / "shapes.csv") << kHeader.substr(0, kHeader.size() - 1) << ",outline_file\n"
                                       << "tri9,0.5,0.0004,,,polygon,,,tri.csv\n";
  const ShapeInfo s = ShapeTable::from_file(folder / "shapes.csv").find("tri9");  // a copy: the table is a temporary
  BOOST_TEST((s.geometry == Geometry::Polygon));
  BOOST_TEST(s.vertices_m.size() == 3u);
  BOOST_TEST(s.centroid_m.x() == 0.1 / 3, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(s.dim1_m == 0.1);
  BOOST_TEST(s.dim2_m == 0.05);
  std::ofstream(folder / "tri.csv") << "x_m,y_m\n0,0\n0.1,nan\n0,0.05\n";
  const std::string e = input_error([&] { ShapeTable::from_file(folder / "shapes.csv"); });
  BOOST_TEST(contains(e, (folder / "shapes.csv").string() + ":2"), e);
  BOOST_TEST(contains(e, (folder / "tri.csv").string() + ":3: 'nan' is not finite"), e);
}

BOOST_AUTO_TEST_CASE(every_hostile_shape_file_is_an_input_error_naming_the_problem) {
  const struct {
    std::string text, expected;
  } cases[] = {
      {"", "not valid JSON"},
      {"[]", "no shapes in the file"},
      {"42", "expected {\"shapes\""},
      {R"({"shapes": 3})", "'shapes' must be a list"},
      {R"({"shapes": [], "colour": 1})", "unknown field 'colour'"},
      {R"({"format": "other", "shapes": []})", "'format' must be"},
      {one_shape(R"("mass_kg": "heavy", "inertia_kgm2": 0.001, )" + kCircle), "'mass_kg' must be a number"},
      {one_shape(R"("mass_kg": 1e999, "inertia_kgm2": 0.001, )" + kCircle), "number overflow"},
      {one_shape(R"("mass_kg": 0, "inertia_kgm2": 0.001, )" + kCircle), "mass_kg must be positive"},
      {one_shape(R"("mass_kg": 1, "inertia_kgm2": -0.001, )" + kCircle), "inertia_kgm2 must be positive"},
      {one_shape(R"("mass_kg": 1, "inertia_kgm2": 0.001)"), "'outline' must be an object"},
      {one_shape(R"("mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "circle", "radius_m": -1})"),
       "must be positive"},
      {one_shape(R"("mass_kg": 1, "inertia_kgm2": 0.001, "centroid_m": [1], )" + kCircle),
       "'centroid_m' must be a pair"},
      {one_shape(
           R"("mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [1, 0]]})"),
       "at least 3 vertices, got 2"},
      {one_shape(
           R"("mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [1, 0], [1, 0], [0, 1]]})"),
       "are the same point"},
      {one_shape(
           R"("mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [1, 1], [1, 0], [0, 1]]})"),
       "not a simple polygon"},
      {one_shape(
           R"("mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [2, 0], [1, 0], [1, 1]]})"),
       "not a simple polygon"},
      {one_shape(
           R"("mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [1, 0], [2, 0]]})"),
       "not a simple polygon"},
      {one_shape(
           R"("mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], [0, 1], [1, 0]]})"),
       "clockwise"},
      {one_shape(
           R"("mass_kg": 1, "inertia_kgm2": 0.001, "outline": {"kind": "polygon", "vertices_m": [[0, 0], ["a", 0], [0, 1]]})"),
       "every vertex must be a pair"},
  };
  for (const auto& c : cases) {
    const std::string e = input_error([&] { ShapeTable::from_json_text(c.text, "own.json"); });
    BOOST_TEST(e.rfind("own.json", 0) == 0, c.text << " -> '" << e << "'");
    BOOST_TEST(contains(e, c.expected), c.text << " -> '" << e << "'");
  }
  const struct {
    std::string text, expected;
  } csv[] = {
      {"", "no shapes"},
      {"name,mass\n", "expected the header line"},
      {kHeader + "x,1\n", "expected at least shape,mass_kg,inertia_kgm2"},
      {kHeader + "x,nan,0.001,0,0,circle,0.05,\n", "'nan' is not a number"},
      {kHeader + "x,1,0.001,0,0,circle,0.05,,extra,more\n", "expected at most 9 fields"},
      {kHeader + "x,1,0.001,0,0,blob,0.05,\n", "unknown geometry 'blob'"},
      {kHeader + "x,1,0.001,0,0,rect,0.05,\n", "must be positive"},
      {kHeader + "x,1,0.001,0,0,polygon,,\n", "names its vertex file"},
      {kHeader + "x,1,0.001,0,0,circle,0.05,\nx,1,0.001,0,0,circle,0.05,\n", "given twice"},
      {kHeader + "my box,1,0.001,0,0,circle,0.05,\n", "letters and digits"},
  };
  for (const auto& c : csv) {
    const std::string e = input_error([&] { ShapeTable::from_csv_text(c.text, "own.csv"); });
    BOOST_TEST(e.rfind("own.csv", 0) == 0, c.text << " -> '" << e << "'");
    BOOST_TEST(contains(e, c.expected), c.text << " -> '" << e << "'");
  }
  BOOST_TEST(contains(input_error([] { ShapeTable::from_file("/nonexistent/own.json"); }),
                      "/nonexistent/own.json: cannot open a shape file"));
}

BOOST_AUTO_TEST_SUITE_END()
