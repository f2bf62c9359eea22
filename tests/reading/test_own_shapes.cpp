#include <boost/test/unit_test.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/physical_bounds.hpp"
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

BOOST_AUTO_TEST_CASE(an_outline_is_measured_by_its_extent_narrowest_width_and_area) {
  const Eigen::Vector2d a(0, 0), b(0.1, 0), c(0.1, 0.1), d(0, 0.1);
  const OutlineSize square = polygon_size({a, b, c, d});
  BOOST_TEST(square.extent_m == 0.1 * std::sqrt(2.0), boost::test_tools::tolerance(1e-12));
  BOOST_TEST(square.width_m == 0.1, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(square.area_m2 == 0.01, boost::test_tools::tolerance(1e-12));
  // An L: its convex hull's narrowest width (across the cut corner, 0.12 / sqrt(2) m), not a leg's; a long thin
  // sliver: its thickness.
  const OutlineSize l = polygon_size({{0, 0}, {0.1, 0}, {0.1, 0.02}, {0.02, 0.02}, {0.02, 0.1}, {0, 0.1}});
  BOOST_TEST(l.width_m == 0.12 / std::sqrt(2.0), boost::test_tools::tolerance(1e-12));
  BOOST_TEST(l.area_m2 == 0.0036, boost::test_tools::tolerance(1e-12));
  const OutlineSize sliver = polygon_size({{0, 0}, {1, 0}, {1, 0.0005}, {0, 0.0005}});
  BOOST_TEST(sliver.width_m == 0.0005, boost::test_tools::tolerance(1e-9));
  const OutlineSize ellipse = ellipse_size(0.05, 0.03);
  BOOST_TEST(ellipse.extent_m == 0.1);
  BOOST_TEST(ellipse.width_m == 0.06);
}

BOOST_AUTO_TEST_CASE(an_object_no_tabletop_push_could_move_is_refused_with_the_reason) {
  const auto error_of = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const OutlineSize disc = ellipse_size(0.05, 0.05);
  BOOST_TEST(error_of([&] { check_outline_size(disc, "--circle"); }) == "no error");
  BOOST_TEST(error_of([&] { check_mass_and_inertia(disc, 1, 1e-3, "--mass", "--inertia"); }) == "no error");
  BOOST_TEST(error_of([] { check_outline_size(ellipse_size(1e9, 1e9), "--circle"); }) ==
             "--circle: the outline is 2e+09 m across, more than the 2 m a pushed tabletop object may be");
  BOOST_TEST(error_of([] { check_outline_size(ellipse_size(0.05, 1e-4), "--ellipse"); }) ==
             "--ellipse: the outline is 0.2 mm wide at its narrowest, less than the 1 mm a pushed tabletop object "
             "must be");
  BOOST_TEST(error_of([] { check_outline_size(ellipse_size(1e300, 1e300), "x"); }) ==
             "x: the outline's size is not finite");
  BOOST_TEST(error_of([&] {
               check_mass_and_inertia(disc, 1e9, 1e-3, "--mass", "--inertia");
             }).rfind("--mass: 1e+09 kg", 0) == 0u);
  BOOST_TEST(error_of([&] {
               check_mass_and_inertia(disc, 1e-9, 1e-12, "--mass", "--inertia");
             }).rfind("--mass: 1e-09 kg", 0) == 0u);
  BOOST_TEST(error_of([&] {
               check_mass_and_inertia(disc, 1, 1e6, "--mass", "--inertia");
             }).find("the mass would lie outside the outline") != std::string::npos);
  BOOST_TEST(error_of([&] {
               check_mass_and_inertia(disc, 1, 1e-12, "--mass", "--inertia");
             }).rfind("--inertia: 1e-12", 0) == 0u);
  BOOST_TEST(error_of([&] {
               check_mass_and_inertia(disc, std::nan(""), 1e-3, "--mass", "--inertia");
             }).rfind("--mass: must be a positive finite number", 0) == 0u);
  // Every object of the dataset lies well inside every bound.
  for (const ShapeInfo& s : ShapeTable::published().shapes()) {
    if (!s.has_outline()) continue;
    const OutlineSize size =
        s.geometry == Geometry::Ellipse ? ellipse_size(s.dim1_m, s.dim2_m) : polygon_size(outline_polygon(s));
    BOOST_TEST(error_of([&] { check_outline_size(size, s.name); }) == "no error");
    BOOST_TEST(error_of([&] { check_mass_and_inertia(size, s.mass_kg, s.inertia_kgm2, s.name, s.name); }) ==
               "no error");
    const double share = std::sqrt(s.inertia_kgm2 / s.mass_kg) / size.extent_m;
    BOOST_TEST_MESSAGE(s.name << ": " << size.extent_m << " m across, " << s.mass_kg / size.area_m2
                              << " kg/m^2, radius of gyration " << share << " of the extent");
  }
  // A shape file's object gets the same checks, named by the file and the shape.
  ShapeInfo huge;
  huge.name = "huge";
  huge.mass_kg = 1;
  huge.inertia_kgm2 = 1e-3;
  huge.geometry = Geometry::Rectangle;
  huge.dim1_m = 100;
  huge.dim2_m = 100;
  BOOST_TEST(error_of([&] {
               validate_shape(huge, "s.json");
             }).find("s.json: shape 'huge': outline: the outline is 141 m across") != std::string::npos);
  BOOST_TEST(is_shape_name("puck2"));
  for (const char* bad : {"", "my box", "a_b", "a/b", "it's", "caf\xC3\xA9"}) BOOST_TEST(!is_shape_name(bad));
}

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
