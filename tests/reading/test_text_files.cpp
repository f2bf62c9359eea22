// reading/text_files.hpp: the rows of a CSV file a user writes, and an outline file's vertices, with every error
// naming the file and the line.
#include <boost/test/unit_test.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/reading/text_files.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::contains;
using pushpred::testing::input_error;
using pushpred::testing::TempFolder;
using pushpred::testing::write_text;

BOOST_AUTO_TEST_SUITE(text_files)

BOOST_AUTO_TEST_CASE(csv_rows_skip_blank_lines_and_comments_and_keep_their_line_numbers) {
  std::vector<std::pair<std::string, std::string>> rows;
  for_each_csv_row("# a comment\r\na,b\r\n\r\n\nc,d\n# last", "t.csv",
                   [&](const std::string& line, const std::string& where) { rows.emplace_back(line, where); });
  const std::vector<std::pair<std::string, std::string>> expected = {{"a,b", "t.csv:2"}, {"c,d", "t.csv:5"}};
  BOOST_TEST((rows == expected));
}

BOOST_AUTO_TEST_CASE(an_outline_file_gives_its_vertices_after_its_header_and_comments) {
  const TempFolder temp;
  write_text(temp / "tri.csv", "# a right triangle\r\nx_m,y_m\r\n0,0\r\n0.1,-2.5e-2\r\n\r\n0,0.05\r\n");
  const std::vector<Eigen::Vector2d> v = read_outline_csv_vertices(temp / "tri.csv");
  BOOST_REQUIRE(v.size() == 3u);
  BOOST_TEST(v[1].x() == 0.1);
  BOOST_TEST(v[1].y() == -0.025);
  BOOST_TEST(v[2].y() == 0.05);
  write_text(temp / "plain.csv", "0,0\n1,0\n0,1\n");  // no header
  BOOST_TEST(read_outline_csv_vertices(temp / "plain.csv").size() == 3u);
}

BOOST_AUTO_TEST_CASE(a_bad_outline_file_is_an_input_error_naming_the_file_line_and_problem) {
  const TempFolder temp;
  const auto error_of = [&](const std::string& text) {
    write_text(temp / "o.csv", text);
    return input_error([&] { read_outline_csv_vertices(temp / "o.csv"); });
  };
  const std::string file = (temp / "o.csv").string();
  BOOST_TEST(contains(error_of("x_m,y_m\n0,0\n0.1,nan\n"), file + ":3: 'nan' is not finite"));
  BOOST_TEST(contains(error_of("x_m,y_m\n0 0\n"), file + ":2: expected two numbers x_m,y_m, got '0 0'"));
  BOOST_TEST(contains(error_of("0,0,0\n"), file + ":1: expected two numbers x_m,y_m"));
  BOOST_TEST(contains(error_of("0,0\n0.1m,0\n"), file + ":2: '0.1m' is not a number"));
  BOOST_TEST(contains(error_of("0,0\nx_m,y_m\n"), file + ":2: 'x_m' is not a number"));  // a header only first
  BOOST_TEST(
      contains(input_error([&] { read_outline_csv_vertices(temp / "none.csv"); }), "cannot open an outline file"));
  BOOST_TEST(
      contains(input_error([&] { read_outline_csv_vertices(temp.path()); }), "is a folder, not an outline file"));
}

BOOST_AUTO_TEST_SUITE_END()
