#include <algorithm>
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <limits>

#include "pushpred/core/error.hpp"
#include "pushpred/observers/q_filter_observer.hpp"
#include "pushpred/reports/prediction_summary.hpp"
#include "test_support.hpp"

using namespace pushpred;
using pushpred::testing::real_file;

BOOST_AUTO_TEST_SUITE(prediction_study)

BOOST_AUTO_TEST_CASE(four_intervals_give_three_prediction_phases_with_every_method) {
  const SynchronisedPush push = load_push(real_file("shape=hex_a=0_v=50"));
  const PushStudy study = run_prediction_study(push);
  BOOST_REQUIRE_EQUAL(study.phases.size(), 3u);
  BOOST_TEST(study.span == "whole");
  for (const auto& phase : study.phases) {
    for (const auto& m : prediction_method_names()) {
      BOOST_TEST_REQUIRE(phase.predicted.count(m) == 1u);
      BOOST_TEST_REQUIRE(phase.predicted.at(m).rows() == phase.t_s.size());
    }
    // `hold` keeps the initial pose: its error at the first sample is one grid step of motion at most.
    BOOST_TEST(phase.t_s(0) > phase.interval.t0_s);
    BOOST_TEST(phase.t_s(phase.t_s.size() - 1) <= phase.interval.t1_s + 1e-12);
  }
  // The relation is identified on more data in every later phase.
  BOOST_TEST(study.phases[0].relation.intervals == 1);
  BOOST_TEST(study.phases[2].relation.intervals == 3);
}

BOOST_AUTO_TEST_CASE(every_key_of_summary_json_is_present_and_finite) {
  Batch<PushStudy> batch;
  batch.results.push_back(run_prediction_study(load_push(real_file("shape=ellip1_a=0_v=100"))));
  batch.failures.push_back({"x.h5", "file does not exist"});
  const nlohmann::json j = prediction_summary_json(batch, StudyOptions{});
  const std::vector<std::string> keys{"x_mm_mean",      "x_mm_std",      "y_mm_mean",    "y_mm_std",
                                      "theta_deg_mean", "theta_deg_std", "final_pos_mm", "final_theta_deg"};
  auto check = [&](const nlohmann::json& e) {
    for (const auto& k : keys) {
      BOOST_TEST_REQUIRE(e.contains(k));
      BOOST_TEST_REQUIRE(std::isfinite(e[k].get<double>()));
      BOOST_TEST_REQUIRE(e[k].get<double>() >= 0.0);
    }
  };
  BOOST_REQUIRE_EQUAL(j["files"].size(), 1u);
  BOOST_REQUIRE_EQUAL(j["files"][0]["phases"].size(), 3u);
  for (const auto& phase : j["files"][0]["phases"])
    for (const auto& m : prediction_method_names()) check(phase["methods"][m]);
  for (const auto& m : prediction_method_names()) check(j["aggregate"][m]);
  BOOST_TEST(j["failures"][0]["reason"] == "file does not exist");
  BOOST_TEST(j["options"]["span"] == "whole");
}

BOOST_AUTO_TEST_CASE(a_study_without_its_samples_gives_the_same_summary_and_tables) {
  Batch<PushStudy> full;
  full.results.push_back(run_prediction_study(load_push(real_file("shape=ellip1_a=0_v=100"))));
  Batch<PushStudy> light = full;
  drop_samples(light.results[0]);
  const PushStudy& s = light.results[0];
  BOOST_TEST(s.identification.empty());
  for (const auto& phase : s.phases) {
    BOOST_TEST(phase.t_s.size() == 0);
    BOOST_TEST(phase.measured.rows() == 0);
    for (const auto& [method, poses] : phase.predicted) BOOST_TEST(poses.rows() == 0);
  }
  BOOST_TEST(prediction_summary_json(light, StudyOptions{}).dump() == prediction_summary_json(full, StudyOptions{}).dump());
  BOOST_TEST(grouped_errors_markdown(light.results) == grouped_errors_markdown(full.results));
  BOOST_TEST(losing_phases_markdown(light.results, "quasi_static", {"hold", "const_velocity"}) ==
             losing_phases_markdown(full.results, "quasi_static", {"hold", "const_velocity"}));
}

BOOST_AUTO_TEST_CASE(a_push_with_a_frozen_force_sensor_is_refused) {
  BOOST_CHECK_THROW(run_prediction_study(load_push(real_file("shape=rect1_a=0_v=75"))), InputError);
}

BOOST_AUTO_TEST_CASE(on_an_unknown_surface_only_the_method_needing_its_friction_coefficient_is_skipped) {
  const SynchronisedPush push = load_push(resolve_data_folder() / "plywood" /
                                          "motion_surface=plywood_shape=hex_a=0_v=150_i=1.000_s=0.000_t=-0.349.json");
  BOOST_CHECK_THROW(surface_friction_coefficient("plywood"), MissingCoefficient);
  const PushStudy without = run_prediction_study(push);
  BOOST_TEST(std::count(without.methods.begin(), without.methods.end(), "simple") == 0);
  BOOST_TEST(std::count(without.methods.begin(), without.methods.end(), "dob") == 1);
  BOOST_TEST(without.phases.size() == 3u);
  StudyOptions o;
  o.friction_coefficient = 0.3;
  const PushStudy with = run_prediction_study(push, o);
  BOOST_TEST(with.phases.size() == 3u);
  for (size_t k = 0; k < with.phases.size(); ++k) {
    const PhaseResult& a = without.phases[k];
    BOOST_TEST(!a.predicted.count("simple"));
    BOOST_TEST(a.method_notes.at("simple").rfind("skipped: no friction coefficient known for surface 'plywood'", 0) ==
               0);
    BOOST_TEST(with.phases[k].predicted.count("simple") == 1u);
    // The methods that need no coefficient predict the same with or without it.
    BOOST_TEST(a.errors.at("dob").pos_mm_mean == with.phases[k].errors.at("dob").pos_mm_mean);
  }
}

BOOST_AUTO_TEST_CASE(a_friction_coefficient_that_is_not_finite_is_refused_not_read_as_from_the_surface) {
  // On ABS the surface has a coefficient: a nan, which fails every "< 0" test, must not fall back to it silently.
  const SynchronisedPush push = load_push(real_file("shape=hex_a=0_v=50"));
  for (double mu : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    StudyOptions o;
    o.friction_coefficient = mu;
    BOOST_CHECK_THROW(run_prediction_study(push, o), InputError);
  }
}

BOOST_AUTO_TEST_CASE(a_continuous_observer_run_feeds_every_sample_once_and_reads_no_sample_after_its_interval) {
  // One observer run over the schedule, sliced per identification interval: the slices tile the identified span,
  // each grid sample once, and each slice equals the rows of a run over the whole recording (the observer is
  // causal, so the run that identifies an interval reads nothing after it).
  const Eigen::Index n = 400;
  SynchronisedPush push = pushpred::testing::synthetic_push_shell("rect2", 250.0, n);
  push.push.surface = "abs";
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = push.t_s(k);
    push.pose.row(k) << 0.02 * t * t, -0.01 * t, 0.05 * std::sin(3 * t);
    push.force_N.row(k) << 1.0 + 0.5 * std::sin(5 * t), 0.3 * std::cos(4 * t);
    push.torque_about_centre_Nm(k) = 0.01 * std::sin(2 * t);
  }
  StudyOptions o;
  o.methods = {"dob", "hold"};
  o.observer_run = StudyOptions::ObserverRun::Continuous;
  const PushStudy study = run_prediction_study(push, o);
  BOOST_REQUIRE_EQUAL(study.identification.size(), 3u);
  const DisturbanceEstimate whole = make_exact_q_filter_observer()->estimate(push, 0.0, push.duration_s());
  Eigen::Index row = 0;
  for (const auto& slice : study.identification) {
    for (Eigen::Index k = 0; k < slice.t_s.size(); ++k, ++row) {
      BOOST_TEST(slice.t_s(k) == push.t_s(row));
      BOOST_TEST((slice.d_hat.row(k) - whole.d_hat.row(row)).norm() < 1e-9);
    }
  }
  BOOST_TEST(push.t_s(row - 1) <= study.intervals[2].t1_s + 1e-9);
  BOOST_TEST(push.t_s(row) > study.intervals[2].t1_s);

  // Per interval (the default), each interval's own run starts at its first grid sample and ends at its last.
  o.observer_run = StudyOptions::ObserverRun::PerInterval;
  const PushStudy per_interval = run_prediction_study(push, o);
  for (std::size_t k = 0; k < 3; ++k) {
    const TimeInterval& i = per_interval.intervals[k];
    const auto& id = per_interval.identification[k];
    BOOST_TEST(id.t_s(0) == push.t_s(push.index_at(i.t0_s)));
    BOOST_TEST(id.t_s(id.t_s.size() - 1) <= i.t1_s + 1e-9);
  }
  // The grid samples of the identified span are fed at least once, none skipped.
  BOOST_TEST(per_interval.identification[1].t_s(0) <=
             per_interval.identification[0].t_s(per_interval.identification[0].t_s.size() - 1) + 1.5 / push.rate_hz);
}

BOOST_AUTO_TEST_CASE(observer_run_names_parse_and_unknown_ones_are_refused) {
  BOOST_TEST(observer_run_name(parse_observer_run("continuous")) == std::string("continuous"));
  BOOST_TEST(observer_run_name(parse_observer_run("per-interval")) == std::string("per-interval"));
  BOOST_CHECK_THROW(parse_observer_run("whole"), InputError);
}

BOOST_AUTO_TEST_SUITE_END()
