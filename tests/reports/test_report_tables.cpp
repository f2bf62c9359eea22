#define BOOST_TEST_MODULE reports
// Report writers fed small hand-made results: every cell of the table is checked against numbers written out by
// hand, so a change of column, rounding or ratio shows here and not only in a user's report.
#include <boost/test/unit_test.hpp>
#include <algorithm>
#include <sstream>

#include "pushpred/reports/estimator_comparison.hpp"
#include "pushpred/reports/markdown_table.hpp"
#include "pushpred/reports/plotting.hpp"

using namespace pushpred;

namespace {

/// The line of `text` that starts with `prefix` (empty when there is none).
std::string line_starting(const std::string& text, const std::string& prefix) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(prefix, 0) == 0) return line;
  return "";
}

/// The cell separators of a Markdown table row: its bars not escaped by a backslash.
long separators(const std::string& line) {
  long n = 0;
  for (std::size_t k = 0; k < line.size(); ++k) n += line[k] == '|' && (k == 0 || line[k - 1] != '\\');
  return n;
}

EstimatorComparison two_estimators() {
  EstimatorComparison c;
  c.reference = "rls";
  c.options.schedule.intervals = 4;
  c.options.plan_rate_hz = 10;
  c.methods = {"dob", "dob_velinit"};
  EstimatorComparisonRow rls;
  rls.estimator = "rls";
  rls.pushes = 3;
  rls.beta_mean = {0.5, -0.25, 0.125};
  rls.eps_mean = {1.5, -2.0, 0.00125};
  rls.errors["dob"].x_mm_mean = 1.234, rls.errors["dob"].y_mm_mean = 2.5, rls.errors["dob"].theta_deg_mean = 0.75;
  rls.errors["dob_velinit"].x_mm_mean = 0.5, rls.errors["dob_velinit"].y_mm_mean = 0.25;
  rls.errors["dob_velinit"].theta_deg_mean = 0.125;
  rls.fit_seconds = 2.0;
  EstimatorComparisonRow huber = rls;
  huber.estimator = "huber";
  huber.beta_max_abs_diff = {1e-3, 2.5e-2, 0};  // the worst of the three is reported
  huber.eps_max_abs_diff = {0, 0, 3e-4};
  huber.fit_seconds = 5.0;  // 2.5 times the reference's
  c.rows = {rls, huber};
  c.failures.push_back({"bad.h5", "array 'tip_pose' is missing"});
  return c;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(estimator_comparison_report)

BOOST_AUTO_TEST_CASE(each_row_holds_the_hand_made_numbers_and_the_time_ratio_to_the_reference) {
  const std::string md = comparison_markdown(two_estimators());
  BOOST_TEST_MESSAGE(md);
  BOOST_TEST(md.rfind("# Relation estimators compared\n\n3 pushes, 4 intervals over the whole span, observer `dob`, "
                      "planned force at 10 Hz.",
                      0) == 0u);
  BOOST_TEST(
      line_starting(md, "| rls |") ==
      "| rls | 0.5000 | -0.2500 | 0.1250 | 1.5000 | -2.0000 | 0.00125 | 0.00e+00 | 0.00e+00 | 1.23 / 2.50 | 0.75 "
      "| 0.50 / 0.25 | 0.12 | 1.00 |");
  BOOST_TEST(line_starting(md, "| huber |") ==
             "| huber | 0.5000 | -0.2500 | 0.1250 | 1.5000 | -2.0000 | 0.00125 | 2.50e-02 | 3.00e-04 | 1.23 / 2.50 | "
             "0.75 | 0.50 / 0.25 | 0.12 | 2.50 |");
  BOOST_TEST(md.find("per prediction method (`dob`, `dob_velinit`)") != std::string::npos);
  BOOST_TEST(line_starting(md, "| estimator |")
                 .find("| dob yaw err [deg] | dob_velinit pos err x/y [mm] | "
                       "dob_velinit yaw err [deg] | fit time ratio |") != std::string::npos);
  BOOST_TEST(md.find("## Pushes left out\n\n- `bad.h5`: array 'tip_pose' is missing\n") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(the_header_has_one_column_per_cell) {
  const std::string md = comparison_markdown(two_estimators());
  const auto cells = [](const std::string& line) { return separators(line); };
  const std::string header = line_starting(md, "| estimator |");
  BOOST_REQUIRE(!header.empty());
  // "max |dbeta|" and "max |deps|" are escaped ("max \\|dbeta\\|"): the header renders as many cells as the rows.
  BOOST_TEST(header.find("| max \\|dbeta\\| | max \\|deps\\| |") != std::string::npos);
  BOOST_TEST(cells(header) == 15);
  BOOST_TEST(cells(line_starting(md, "|---")) == 15);
  BOOST_TEST(cells(line_starting(md, "| huber |")) == 15);
}

BOOST_AUTO_TEST_CASE(each_method_chosen_adds_its_two_error_columns) {
  EstimatorComparison c = two_estimators();
  c.methods.push_back("hold");
  for (auto& row : c.rows) row.errors["hold"].x_mm_mean = 4.0, row.errors["hold"].y_mm_mean = 3.0;
  const std::string md = comparison_markdown(c);
  const auto cells = [](const std::string& line) { return std::count(line.begin(), line.end(), '|'); };
  BOOST_TEST(cells(line_starting(md, "|---")) == 17);
  BOOST_TEST(line_starting(md, "| estimator |").find("| hold pos err x/y [mm] | hold yaw err [deg] | fit time") !=
             std::string::npos);
  BOOST_TEST(line_starting(md, "| rls |").find("| 0.50 / 0.25 | 0.12 | 4.00 / 3.00 | 0.00 | 1.00 |") !=
             std::string::npos);
  // A row without errors for a method (no pushes) shows dashes, not a number.
  c.rows[1].errors.clear();
  BOOST_TEST(line_starting(comparison_markdown(c), "| huber |").find("| - | - | - | - | - | - | 2.50 |") !=
             std::string::npos);
}

BOOST_AUTO_TEST_CASE(without_rows_no_ratio_is_invented) {
  EstimatorComparison c = two_estimators();
  c.rows.clear();
  c.failures.clear();
  const std::string md = comparison_markdown(c);
  BOOST_TEST(md.rfind("# Relation estimators compared\n\n0 pushes,", 0) == 0u);
  BOOST_TEST(md.find("Pushes left out") == std::string::npos);
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_SUITE(gnuplot_text)

BOOST_AUTO_TEST_CASE(quoted_names_survive_quotes_and_the_png_terminal_names_its_file) {
  BOOST_TEST(gnuplot_quoted("forces.png") == "'forces.png'");
  BOOST_TEST(gnuplot_quoted("it's.png") == "'it''s.png'");  // gnuplot doubles a quote inside single quotes
  const std::string t = png_terminal("a'b.png", 800, 600);
  BOOST_TEST(t.find("set terminal pngcairo size 800,600") != std::string::npos);
  BOOST_TEST(t.find("set terminal png size 800,600") != std::string::npos);  // without cairo
  BOOST_TEST(t.find("set output 'a''b.png'\n") != std::string::npos);
}

BOOST_AUTO_TEST_SUITE_END()

BOOST_AUTO_TEST_SUITE(markdown_tables)

BOOST_AUTO_TEST_CASE(a_cell_cannot_split_its_row) {
  BOOST_TEST(markdown_cell("max |dbeta|") == "max \\|dbeta\\|");
  BOOST_TEST(markdown_cell("two\nlines") == "two lines");
  BOOST_TEST(markdown_row({"a|b", "c"}) == "| a\\|b | c |\n");
  BOOST_TEST(markdown_header({"x [mm]", "y"}, {"---:"}) == "| x [mm] | y |\n|---:|---|\n");
  BOOST_TEST(separators(markdown_row({"|", "||", "a"})) == 4);
}

BOOST_AUTO_TEST_CASE(a_number_that_rounds_to_zero_has_no_sign) {
  BOOST_TEST(table_number("%.1f", -0.04) == "0.0");
  BOOST_TEST(table_number("%.2f", -0.0) == "0.00");
  BOOST_TEST(table_number("%.2e", -0.0) == "0.00e+00");
  BOOST_TEST(table_number("%.1f", -0.06) == "-0.1");
  BOOST_TEST(table_number("%.3g", -1e-300) == "-1e-300");
  BOOST_TEST(table_number("%.0f", -0.4) == "0");
}

BOOST_AUTO_TEST_SUITE_END()
