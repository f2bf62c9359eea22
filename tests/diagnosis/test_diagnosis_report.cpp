// diagnosis.json carries every key the issue names, for every candidate; report.md is written beside it, and
// nothing is left half-written.
#include <boost/test/unit_test.hpp>
#include <fstream>
#include <sstream>

#include "pushpred/reports/diagnosis_report.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::TempFolder;

namespace {

DiagnosisResult made_up_result() {
  DiagnosisResult r;
  r.shape = "hex";
  r.surface = "abs";
  r.held_out = "alternate pushes";
  r.fit_sources = {"a.h5"};
  r.test_sources = {"b.h5"};
  EffectReport e;
  e.kind = "time_offset";
  e.description = "lag";
  e.selected = e.passed_test = true;
  e.score = 42;
  e.parameter_info = {{"delay", "s"}};
  e.theta = Eigen::VectorXd::Constant(1, 0.02);
  e.theta_std = Eigen::VectorXd::Constant(1, 0.001);
  r.effects.push_back(e);
  EffectReport v;
  v.kind = "initial_velocity";
  v.test = EffectTest::Prediction;
  v.score = -0.1;
  r.effects.push_back(v);
  r.error_before.phases = r.error_after.phases = r.hold.phases = r.const_velocity.phases = 3;
  r.error_before.pos_mm_mean = 5;
  r.error_after.pos_mm_mean = 1;
  r.hold.pos_mm_mean = 2;
  r.const_velocity.pos_mm_mean = 1.5;
  r.error_after.theta_deg_mean = 0.5;
  r.hold.theta_deg_mean = r.const_velocity.theta_deg_mean = 1;
  return r;
}

}  // namespace

BOOST_AUTO_TEST_SUITE(diagnosis_report)

BOOST_AUTO_TEST_CASE(diagnosis_json_has_every_key_the_issue_names) {
  const nlohmann::json j = diagnosis_json(made_up_result(), DiagnosisOptions{});
  BOOST_TEST_REQUIRE(j["effects"].size() == 2u);
  for (const auto& e : j["effects"]) {
    for (const char* key : {"kind", "selected", "score", "parameters"}) BOOST_TEST(e.contains(key), key);
  }
  BOOST_TEST(j["effects"][0]["parameters"]["delay"]["value"].get<double>() == 0.02);
  BOOST_TEST(j["effects"][0]["parameters"]["delay"]["std"].get<double>() == 0.001);
  for (const char* block : {"error_before", "error_after"})
    for (const char* key : {"pos_mm_mean", "theta_deg_mean"}) BOOST_TEST(j[block].contains(key), block << "." << key);
  for (const char* ref : {"hold", "const_velocity"})
    for (const char* key : {"pos_mm_mean", "theta_deg_mean"})
      BOOST_TEST(j["error_references"][ref].contains(key), ref << "." << key);
  BOOST_TEST(j["error_after"]["pos_mm_mean"].get<double>() == 1.0);
}

BOOST_AUTO_TEST_CASE(the_report_is_written_together_and_says_who_wins) {
  TempFolder tmp;
  const DiagnosisResult r = made_up_result();
  {
    StagedOutput out(tmp / "run");
    write_diagnosis_report(r, DiagnosisOptions{}, out, false);
    BOOST_TEST(!std::filesystem::exists(tmp / "run" / "report.md"));  // nothing before the commit
    out.commit();
  }
  BOOST_TEST(std::filesystem::exists(tmp / "run" / "diagnosis.json"));
  std::ifstream in(tmp / "run" / "report.md");
  std::stringstream md;
  md << in.rdbuf();
  BOOST_TEST(md.str().find("beats both naive references") != std::string::npos);
  BOOST_TEST(md.str().find("time_offset") != std::string::npos);
}

BOOST_AUTO_TEST_SUITE_END()
