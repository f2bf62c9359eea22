// reports/prediction_summary.hpp: what predict writes one push at a time (summary.json, the predictions files, the
// tables) is the text the whole documents make.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "pushpred/reports/prediction_summary.hpp"
#include "pushpred/runtime/output_files.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::awkward_push_study;
using pushpred::testing::same_bits;

BOOST_AUTO_TEST_CASE(the_streamed_summary_is_the_whole_documents_text_byte_for_byte) {
  // predict writes summary.json one push at a time (write_prediction_summary) rather than dumping the document
  // built whole; the file must not change. Awkward content: NaN and infinities, invalid UTF-8 and quotes, line
  // breaks in a note, options that name "files" themselves, no push and no failure.
  Batch<PushStudy> batch;
  batch.results.push_back(awkward_push_study());
  PushStudy odd = awkward_push_study();
  odd.source = std::string("shape=rect1 \xff\xfe \"quoted\"\n.h5");
  odd.phases[0].note = "two\nlines and a \"quote\" and a tab\t";
  odd.phases.push_back(odd.phases[0]);
  odd.phases[1].phase = 2;
  batch.results.push_back(odd);
  batch.failures.push_back({"missing \xc3\x28.h5", "file does not exist"});
  const nlohmann::json options = {{"files", "a \"files\": [] key"}, {"intervals", 4}, {"methods", {"dob", "hold"}}};
  const auto streamed = [](const Batch<PushStudy>& b, const nlohmann::json& o) {
    std::ostringstream out;
    write_prediction_summary(out, b, o);
    return out.str();
  };
  BOOST_TEST(streamed(batch, options) == json_file_text(prediction_summary_json(batch, options)));
  Batch<PushStudy> one;
  one.results.push_back(awkward_push_study());
  BOOST_TEST(streamed(one, options) == json_file_text(prediction_summary_json(one, options)));
  const Batch<PushStudy> none;
  BOOST_TEST(streamed(none, nlohmann::json::object()) ==
             json_file_text(prediction_summary_json(none, nlohmann::json::object())));
}

BOOST_AUTO_TEST_CASE(a_prediction_csv_writes_every_number_as_an_ostream_at_precision_9_would) {
  // predictions_csv formats with std::to_chars for speed; the files must stay what they were when a stream at
  // precision 9 wrote them, special values included.
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::vector<double> values = {0.0,        -0.0, 1.0 / 3.0, -2.5e-7, 123456789.123, 1e-300, 5e300, 1e9,
                                      99999.9999, 0.1,  nan,       -nan,    inf,           -inf,   1e-5,  0.0001};
  PushStudy s;
  s.methods = {"dob", "hold"};
  PhaseResult r;
  r.phase = 3;
  const Eigen::Index n = static_cast<Eigen::Index>(values.size());
  r.t_s = Eigen::VectorXd::LinSpaced(n, 0.0, 0.3);
  r.measured.resize(n, 3);
  for (const auto& m : s.methods) r.predicted[m].resize(n, 3);
  for (Eigen::Index j = 0; j < n; ++j)
    for (int c = 0; c < 3; ++c) {
      r.measured(j, c) = values[static_cast<std::size_t>((j + c) % n)];
      r.predicted["dob"](j, c) = values[static_cast<std::size_t>((j + 5 * c + 1) % n)];
      r.predicted["hold"](j, c) = values[static_cast<std::size_t>((j + 7 * c + 2) % n)];
    }
  s.phases.push_back(r);

  std::ostringstream expected;  // what predictions_csv wrote before, with a stream
  expected.precision(9);
  expected << "phase,t_s,measured_x_mm,measured_y_mm,measured_theta_deg,dob_x_mm,dob_y_mm,dob_theta_deg,"
              "hold_x_mm,hold_y_mm,hold_theta_deg\n";
  constexpr double deg = 180.0 / M_PI;
  for (Eigen::Index j = 0; j < n; ++j) {
    expected << 3 << "," << r.t_s(j) << "," << 1e3 * r.measured(j, 0) << "," << 1e3 * r.measured(j, 1) << ","
             << deg * r.measured(j, 2);
    for (const auto& m : s.methods) {
      const auto& p = r.predicted.at(m);
      expected << "," << 1e3 * p(j, 0) << "," << 1e3 * p(j, 1) << "," << deg * p(j, 2);
    }
    expected << "\n";
  }
  BOOST_TEST(predictions_csv(s) == expected.str());
}

BOOST_AUTO_TEST_CASE(tables_summed_one_push_at_a_time_keep_what_sorting_every_phase_at_the_end_keeps) {
  // predict adds each push to PredictionTables as it finishes and keeps only the worst losing phases seen so far;
  // the table must list what sorting all of them at the end lists, ties in input order.
  std::vector<PushStudy> studies;
  for (int k = 0; k < 300; ++k) {
    PushStudy s;
    s.source = "dir/shape=" + std::string(k % 3 ? "rect1" : "ellip2") + "_a=0_v=" + std::to_string(10 + 10 * (k % 4)) +
               "_i=" + std::to_string(k) + ".h5";
    s.methods = {"quasi_static", "hold", "const_velocity"};
    for (int p = 1; p <= 2; ++p) {
      PhaseResult r;
      r.phase = p;
      // Seven distinct excesses, so many exact ties; every tenth phase does not lose.
      const double qs = (k + p) % 10 == 0 ? 0.4 : 1.0 + 0.5 * ((k * 3 + p) % 7);
      r.errors["quasi_static"] = {qs, 0.1 * k, 0, 0, 0, 0.2, 0, 0, 0};
      r.errors["hold"] = {0.5, 0, 0, 0, 0, 0.3, 0, 0, 0};
      r.errors["const_velocity"] = {0.6 + 1e-3 * k, 0, 0, 0, 0, 0.25, 0, 0, 0};
      s.phases.push_back(r);
    }
    studies.push_back(s);
  }
  const std::vector<std::string> refs{"hold", "const_velocity"};
  const std::string trimmed = losing_phases_markdown(studies, "quasi_static", refs, 15);
  const std::string whole = losing_phases_markdown(studies, "quasi_static", refs, 100000);  // never trimmed
  const auto lines = [](const std::string& text, std::size_t count) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; out.size() < count && std::getline(in, line);) out.push_back(line);
    return out;
  };
  const std::vector<std::string> head = lines(whole, 4 + 15);  // the counts, a blank line, the table's head, 15 rows
  BOOST_TEST(lines(trimmed, 1000) == head, boost::test_tools::per_element());
  BOOST_TEST(head.back().find("| `shape=") == 0u);
  // The worst excess is 4.0 - 0.5 mm (the best yaw 0.25 deg is not beaten); the first phase with it in input order,
  // (3 k + p) % 7 == 6: push 4, phase 1, leads.
  BOOST_TEST(head[4].find("| 4.00 / 0.20 | 0.50 / 0.25 |") != std::string::npos);
  BOOST_TEST(head[4].find("_i=4.h5` | 1 |") != std::string::npos);

  PredictionTables tables("quasi_static", refs);
  for (const auto& s : studies) tables.add(s);
  BOOST_TEST(tables.pushes() == 300u);
  const auto streamed = tables.aggregate(), whole_sum = aggregate_errors(studies);
  BOOST_REQUIRE(streamed.size() == whole_sum.size());
  for (const auto& [name, e] : whole_sum) {
    BOOST_TEST(same_bits(streamed.at(name).pos_mm_mean, e.pos_mm_mean));
    BOOST_TEST(same_bits(streamed.at(name).x_mm_mean, e.x_mm_mean));
    BOOST_TEST(same_bits(streamed.at(name).theta_deg_mean, e.theta_deg_mean));
  }
  BOOST_TEST(tables.losing_phases_markdown() == trimmed);
}
