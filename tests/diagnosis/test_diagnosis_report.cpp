// diagnosis.json carries every documented key, for every candidate; report.md is written beside it, and
// nothing is left half-written.
#include <boost/test/unit_test.hpp>
#include <algorithm>
#include <fstream>
#include <sstream>

#include "pushpred/diagnosis/push_groups.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::TempFolder;
using pushpred::testing::real_file;

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

BOOST_AUTO_TEST_CASE(structure_fixes_alone_are_reported_as_nothing_found) {
  DiagnosisResult r = made_up_result();
  BOOST_TEST(effects_found(r) == std::vector<std::string>{"time_offset"});
  BOOST_TEST(findings_text(r).rfind("found: time_offset", 0) == 0u, findings_text(r));
  r.effects[0].selected = false;     // the physical effect is gone;
  r.effects[1].structural = true;    // the paper's structure is fixed (initial velocity)
  r.effects[1].selected = true;
  BOOST_TEST(effects_found(r).empty());
  BOOST_TEST(findings_text(r).rfind("nothing found", 0) == 0u, findings_text(r));
  BOOST_TEST(findings_text(r).find("base model: initial_velocity") != std::string::npos);
  const nlohmann::json j = diagnosis_json(r, DiagnosisOptions{});
  BOOST_TEST(j["nothing_found"].get<bool>());
  BOOST_TEST(j["found"].empty());
}

BOOST_AUTO_TEST_CASE(a_significant_but_negligible_effect_is_reported_as_such_and_not_found) {
  DiagnosisResult r = made_up_result();
  r.effects[0].selected = false;
  r.effects[0].passed_test = true;
  r.effects[0].negligible = true;
  r.effects[0].amount = 0.003;
  r.effects[0].amount_unit = "s";
  r.effects[0].floor = {0.008, "two force samples"};
  BOOST_TEST(effects_found(r).empty());
  BOOST_TEST(findings_text(r).rfind("nothing found", 0) == 0u, findings_text(r));
  BOOST_TEST(findings_text(r).find("significant but negligible: time_offset") != std::string::npos, findings_text(r));
  const nlohmann::json j = diagnosis_json(r, DiagnosisOptions{});
  BOOST_TEST(j["effects"][0]["negligible"].get<bool>());
  BOOST_TEST(j["effects"][0]["amount"]["floor"].get<double>() == 0.008);
}

BOOST_AUTO_TEST_CASE(an_effect_the_motion_contradicts_is_reported_as_such_and_not_found) {
  DiagnosisResult r = made_up_result();
  r.effects[0].selected = false;
  r.effects[0].passed_test = true;
  r.effects[0].contradicted_by_motion = true;
  r.effects[0].amount = 0.02;
  r.effects[0].amount_std = 0.002;
  r.effects[0].amount_unit = "s";
  BOOST_TEST(effects_found(r).empty());
  BOOST_TEST(findings_text(r).rfind("nothing found", 0) == 0u, findings_text(r));
  BOOST_TEST(findings_text(r).find("contradicted by the fit pushes' motion: time_offset") != std::string::npos,
             findings_text(r));
  const nlohmann::json j = diagnosis_json(r, DiagnosisOptions{});
  BOOST_TEST(j["effects"][0]["contradicted_by_motion"].get<bool>());
  BOOST_TEST(!j["effects"][0]["negligible"].get<bool>());
  BOOST_TEST(j["effects"][0]["amount"]["std"].get<double>() == 0.002);
}

BOOST_AUTO_TEST_CASE(an_effect_standing_in_for_an_unexplained_residual_is_reported_as_such_and_not_found) {
  DiagnosisResult r = made_up_result();
  r.effects[0].selected = false;
  r.effects[0].passed_test = true;
  r.effects[0].stands_in_for_unexplained = true;
  BOOST_TEST(effects_found(r).empty());
  BOOST_TEST(findings_text(r).find("standing in for the unexplained residual (not found beside it): time_offset") !=
                 std::string::npos,
             findings_text(r));
  const nlohmann::json j = diagnosis_json(r, DiagnosisOptions{});
  BOOST_TEST(j["effects"][0]["stands_in_for_unexplained"].get<bool>());
  BOOST_TEST(!j["effects"][0]["contradicted_by_motion"].get<bool>());
}

BOOST_AUTO_TEST_CASE(a_found_effect_that_does_not_help_prediction_is_reported_with_its_held_out_change) {
  DiagnosisResult r = made_up_result();
  r.effects[0].amount = 0.02;
  r.effects[0].amount_unit = "s";
  r.effects[0].has_ablation = true;
  r.error_after.pos_mm_mean = 2.0;
  r.effects[0].held_out_without.pos_mm_mean = 1.9;  // the model is better without it
  const std::string text = findings_text(r);
  BOOST_TEST(text.rfind("found: time_offset 0.02 s", 0) == 0u, text);
  BOOST_TEST(text.find("held-out change +0.10 mm") != std::string::npos, text);
  BOOST_TEST(text.find("does not help prediction") != std::string::npos, text);
  r.effects[0].has_fit_ablation = true;
  r.effects[0].fit_without.pos_mm_mean = 0.7;
  const nlohmann::json j = diagnosis_json(r, DiagnosisOptions{});
  BOOST_TEST(j["effects"][0]["held_out_without"]["pos_mm_mean"].get<double>() == 1.9);
  BOOST_TEST(j["effects"][0]["fit_without"]["pos_mm_mean"].get<double>() == 0.7);
}

BOOST_AUTO_TEST_CASE(the_overview_lists_every_object_and_the_ones_not_diagnosed) {
  std::vector<DiagnosisGroupOutcome> groups;
  groups.push_back({"hex_on_abs", 4, made_up_result(), ""});
  groups.push_back({"rect1_on_abs", 2, std::nullopt, "no usable push"});
  const std::string md = diagnosis_overview_markdown(groups);
  // before, base (not set here: zero), after
  BOOST_TEST(
      md.find("[hex_on_abs](hex_on_abs/report.md) | 4 | 3 | time_offset | not tested | 5.00 / 0.00 | 0.00 / 0.00 | "
              "1.00 / 0.50") != std::string::npos,
      md);
  BOOST_TEST(md.find("rect1_on_abs (2 pushes): no usable push") != std::string::npos, md);
  const nlohmann::json j = diagnosis_overview_json(groups);
  BOOST_TEST(j["objects"][0]["after_beats_both_references"].get<bool>());
  BOOST_TEST(j["objects"][1]["error"].get<std::string>() == "no usable push");
}

BOOST_AUTO_TEST_CASE(nothing_found_is_said_only_with_an_explained_residual) {
  DiagnosisResult r = made_up_result();
  r.effects[0].selected = false;
  r.adequacy.tested = true;
  r.adequacy.explained = true;
  BOOST_TEST(findings_text(r).rfind("nothing found, residual explained", 0) == 0u, findings_text(r));
  BOOST_TEST(hints_json(r).empty());
  // An unexplained residual with nothing found: the headline gives its size and never says "nothing found".
  r.adequacy.explained = false;
  r.adequacy.force_unexplained = true;
  r.adequacy.force_N = 0.8;
  r.adequacy.torque_Nm = 0.01;
  r.hints = {{"world_force", "a constant force in the world frame", 0.4, 0.8}};
  const std::string text = findings_text(r);
  BOOST_TEST(text.rfind("unexplained residual: 0.8 N and 0.01 N m", 0) == 0u, text);
  BOOST_TEST(text.find("nothing found") == std::string::npos, text);
  BOOST_TEST(
      diagnosis_summary_text(r).find("hint (not a finding): world_force: 40.0 % of the residual") != std::string::npos,
      diagnosis_summary_text(r));
  const nlohmann::json j = diagnosis_json(r, DiagnosisOptions{});
  BOOST_TEST(!j["adequacy"]["explained"].get<bool>());
  BOOST_TEST(j["hints"][0]["signature"].get<std::string>() == "world_force");
  BOOST_TEST(diagnosis_markdown(r, DiagnosisOptions{}, {}, "").find("## Model adequacy") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(the_report_traces_the_phases_where_the_corrected_model_loses) {
  DiagnosisResult r = made_up_result();
  // Two phases of constant errors: in the first the corrected model is best; in the second its yaw error is
  // twice const_velocity's.
  const auto phase = [](int k, double corrected_yaw_rad) {
    PhaseTrace p;
    p.source = "b.h5";
    p.phase = k;
    p.t0_s = 0.5 * k;
    p.t_s = Eigen::VectorXd::LinSpaced(5, 0.0, 0.1);
    const auto rows = [](double x_m, double yaw_rad) {
      Eigen::MatrixX3d e(5, 3);
      e.col(0).setConstant(x_m);
      e.col(1).setZero();
      e.col(2).setConstant(yaw_rad);
      return e;
    };
    p.error["dob"] = rows(0.01, 0.1);
    p.error[kCorrectedMethod] = rows(0.001, corrected_yaw_rad);
    p.error["hold"] = rows(0.004, 0.05);
    p.error["const_velocity"] = rows(0.002, 0.01);
    return p;
  };
  r.test_phases = {phase(1, 0.005), phase(2, 0.02)};
  const std::string md = diagnosis_markdown(r, DiagnosisOptions{}, {}, "");
  BOOST_TEST(md.find("Of the 2 held-out phases, the corrected model beats `hold` in both position and yaw in 2 and "
                     "`const_velocity` in 1. It loses to the better reference in 1 phase(s)") != std::string::npos,
             md);
  BOOST_TEST(md.find("| `b.h5` | 2 | 1.00 | 1.00 / 1.15 | 2.00 / 0.57 | yaw |") != std::string::npos, md);
  // The same phases over time, one row per sample.
  const std::string csv = test_phase_errors_csv(r);
  BOOST_TEST(csv.substr(0, csv.find('\n')) ==
             "push,phase,t_s,dob_x_mm,dob_y_mm,dob_theta_deg,corrected_x_mm,corrected_y_mm,corrected_theta_deg,"
             "hold_x_mm,hold_y_mm,hold_theta_deg,const_velocity_x_mm,const_velocity_y_mm,const_velocity_theta_deg");
  BOOST_TEST(std::count(csv.begin(), csv.end(), '\n') == 1 + 2 * 5);
  BOOST_TEST(csv.find("\nb.h5,2,1,10,0,5.72958,1,0,1.14592,4,0,2.86479,2,0,0.572958\n") != std::string::npos, csv);
}

BOOST_AUTO_TEST_CASE(a_mixed_batch_is_grouped_by_object_and_surface) {
  std::vector<SynchronisedPush> pushes;
  pushes.push_back(load_push(real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000")));
  pushes.push_back(load_push(real_file("shape=ellip1_a=0_v=50_i=0.000_s=0.175_t=-0.349")));
  pushes.push_back(load_push(real_file("shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.349")));
  const std::vector<PushGroup> groups = group_by_object(pushes);
  BOOST_TEST_REQUIRE(groups.size() == 2u);
  BOOST_TEST(groups[0].name() == "ellip1_on_abs");
  BOOST_TEST(groups[1].name() == "hex_on_abs");
  BOOST_TEST_REQUIRE(groups[1].pushes.size() == 2u);
  BOOST_TEST(groups[1].pushes[0].source == pushes[0].source);  // the given order is kept
  BOOST_TEST(groups[1].pushes[1].source == pushes[2].source);
}

BOOST_AUTO_TEST_SUITE_END()
