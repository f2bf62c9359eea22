#define BOOST_TEST_MODULE jobs
// jobs/partial_codecs.hpp: a result written into a partial output reads back to the same bits, so that a merge of
// shards writes what one run writes (tests/apps/cli_shard.sh checks the whole files), and a malformed one is an
// input error naming what is wrong.
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "pushpred/core/error.hpp"
#include "pushpred/jobs/partial_codecs.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "pushpred/reports/prediction_summary.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::awkward_push_study;
using pushpred::testing::contains;
using pushpred::testing::input_error;
using pushpred::testing::same_bits;

BOOST_AUTO_TEST_CASE(a_study_reads_back_to_the_same_bits) {
  const PushStudy s = awkward_push_study();
  const PushStudy back = push_study_from_exact_json(nlohmann::json::parse(push_study_exact_json(s).dump()));
  BOOST_TEST(back.source == s.source);
  BOOST_TEST(back.methods == s.methods);
  BOOST_REQUIRE(back.intervals.size() == 2u);
  BOOST_TEST(same_bits(back.intervals[0].t1_s, 0.1 + 0.2));
  BOOST_REQUIRE(back.phases.size() == 1u);
  const PhaseResult& r = back.phases[0];
  BOOST_TEST(same_bits(r.relation.beta(1), -0.0));
  BOOST_TEST(same_bits(r.relation.beta(2), 1e-300));
  BOOST_TEST(std::isnan(r.relation.eps(0)));
  BOOST_TEST((r.relation.eps(1) == std::numeric_limits<double>::infinity()));
  BOOST_TEST((r.relation.eps(2) == -std::numeric_limits<double>::infinity()));
  BOOST_TEST(same_bits(r.relation.covariance[1](0, 0), 1.0 / 7.0));
  BOOST_TEST(same_bits(r.relation.covariance[1](1, 1), 5e300));
  BOOST_TEST(same_bits(r.relation.effective_samples, 24.999999999999996));
  BOOST_TEST(same_bits(r.errors.at("dob").pos_mm_mean, 0.7000000000000001));
  BOOST_TEST(same_bits(r.errors.at("dob").final_theta_deg, 8.123456789012345));
  BOOST_TEST(std::isnan(r.errors.at("hold").pos_mm_mean));
  BOOST_TEST(r.method_notes.at("hold") == "stays");
  BOOST_REQUIRE(r.method_parameters.at("dob").size() == 2u);
  BOOST_TEST(r.method_parameters.at("dob")[1].source == "default: none");
  BOOST_TEST(std::isnan(r.method_parameters.at("dob")[1].value));
  BOOST_TEST(same_bits(r.initial_velocity(0), std::nextafter(1.0, 2.0)));
  BOOST_TEST(r.predicted.size() == 2u);
  // What the outputs are made of is the same text.
  BOOST_TEST(study_json(back).dump() == study_json(s).dump());
  BOOST_TEST(grouped_errors_markdown({back}) == grouped_errors_markdown({s}));
}

BOOST_AUTO_TEST_CASE(a_malformed_study_is_an_input_error) {
  nlohmann::json doc = push_study_exact_json(awkward_push_study());
  doc["phases"][0]["errors"]["dob"] = {1, 2};
  BOOST_CHECK_THROW(push_study_from_exact_json(doc), InputError);
  doc = push_study_exact_json(awkward_push_study());
  doc.erase("span");
  BOOST_CHECK_THROW(push_study_from_exact_json(doc), InputError);
  doc = push_study_exact_json(awkward_push_study());
  doc["phases"][0]["initial_velocity"][0] = "fast";
  BOOST_CHECK_THROW(push_study_from_exact_json(doc), InputError);
}

BOOST_AUTO_TEST_CASE(a_validation_trial_reads_back_to_the_same_bits) {
  ValidationTrial t;
  t.index = 7;
  t.seed = 18446744073709551615ull;  // the largest seed
  t.true_kind = "force_offset";
  t.amount = -0.1 - 0.2;
  t.floor = 1e-300;
  t.fitted_amount = std::numeric_limits<double>::quiet_NaN();
  t.true_score = -std::numeric_limits<double>::infinity();
  t.named = {"force_offset", "time_offset"};
  t.true_named = true;
  t.after = {3, 0.7000000000000001, 1.0 / 3.0, 2.0 / 3.0, 5, 6, 7};
  t.failure = "";
  const ValidationTrial back =
      validation_trial_from_exact_json(nlohmann::json::parse(validation_trial_exact_json(t).dump()));
  BOOST_TEST(back.index == 7);
  BOOST_TEST(back.seed == t.seed);
  BOOST_TEST(same_bits(back.amount, -0.1 - 0.2));
  BOOST_TEST(same_bits(back.floor, 1e-300));
  BOOST_TEST(std::isnan(back.fitted_amount));
  BOOST_TEST((back.true_score == -std::numeric_limits<double>::infinity()));
  BOOST_TEST(back.named == t.named);
  BOOST_TEST(back.after.phases == 3);
  BOOST_TEST(same_bits(back.after.x_mm_mean, 1.0 / 3.0));
  BOOST_TEST(same_bits(back.after.pos_mm_mean, 0.7000000000000001));
  nlohmann::json doc = validation_trial_exact_json(t);
  doc["errors"].erase(0);
  BOOST_CHECK_EXCEPTION(validation_trial_from_exact_json(doc), InputError, [](const InputError& e) {
    return std::string(e.what()).find("a trial holds 5 error summaries, not 6") != std::string::npos;
  });
}

BOOST_AUTO_TEST_CASE(a_diagnosed_object_reads_back_to_what_its_overview_reads) {
  DiagnosedObject d;
  d.outcome.name = "hex_on_abs";
  d.outcome.pushes = 14;
  d.printed = "found: support_friction\n";
  d.complaints = "LEFT OUT a.h5: no contact\n";
  d.left_out = 1;
  DiagnosisResult r;
  r.shape = "hex";
  r.surface = "abs";
  EffectReport found, structural, rejected;
  found.kind = "force_offset";
  found.selected = true;
  structural.kind = "support_pressure";
  structural.structural = true;
  structural.selected = true;
  rejected.kind = "time_offset";  // not selected: the overview does not read it, and the codec leaves it out
  r.effects = {found, rejected, structural};
  r.adequacy.tested = true;
  r.adequacy.explained = false;
  r.error_before = {3, 0.1 + 0.2, 1.0 / 3.0, -0.0, 2.0, 4.9e-324, 7.0};
  r.error_after = {3, std::numeric_limits<double>::quiet_NaN(), 0, 0, 0, 0, 0};
  r.hold = {3, 1, 2, 3, 4, 5, 6};
  d.outcome.result = r;

  const DiagnosedObject back =
      diagnosed_object_from_exact_json(nlohmann::json::parse(diagnosed_object_exact_json(d).dump()));
  BOOST_TEST(back.outcome.name == "hex_on_abs");
  BOOST_TEST(back.outcome.pushes == 14u);
  BOOST_TEST(back.printed == d.printed);
  BOOST_TEST(back.complaints == d.complaints);
  BOOST_TEST(back.left_out == 1u);
  BOOST_REQUIRE(back.outcome.result.has_value());
  const DiagnosisResult& b = *back.outcome.result;
  BOOST_REQUIRE(b.effects.size() == 2u);
  BOOST_TEST(b.effects[0].kind == "force_offset");
  BOOST_TEST(!b.effects[0].structural);
  BOOST_TEST(b.effects[1].structural);
  BOOST_TEST(same_bits(b.error_before.pos_mm_mean, 0.1 + 0.2));
  BOOST_TEST(same_bits(b.error_before.y_mm_mean, -0.0));
  BOOST_TEST(same_bits(b.error_before.final_pos_mm, 4.9e-324));
  BOOST_TEST(std::isnan(b.error_after.pos_mm_mean));
  BOOST_TEST(b.hold.final_theta_deg == 6.0);
  // What the overview is made of is the same text.
  BOOST_TEST(diagnosis_overview_markdown({back.outcome}) == diagnosis_overview_markdown({d.outcome}));
  BOOST_TEST(diagnosis_overview_json({back.outcome}).dump() == diagnosis_overview_json({d.outcome}).dump());

  DiagnosedObject failed;
  failed.outcome.name = "ellip3_on_abs";
  failed.outcome.error = "too few pushes";
  const DiagnosedObject failed_back = diagnosed_object_from_exact_json(diagnosed_object_exact_json(failed));
  BOOST_TEST(!failed_back.outcome.result.has_value());
  BOOST_TEST(failed_back.outcome.error == "too few pushes");

  nlohmann::json doc = diagnosed_object_exact_json(d);
  doc["overview"]["errors"].erase(5);
  BOOST_TEST(contains(input_error([&] { diagnosed_object_from_exact_json(doc); }),
                      "an object holds 5 error summaries, not 6"));
  doc = diagnosed_object_exact_json(d);
  doc.erase("printed");
  BOOST_TEST(contains(input_error([&] { diagnosed_object_from_exact_json(doc); }), "not an object's diagnosis"));
}
