// A rod that presses before the tip moves is no sensor bias: the force-offset test reads only the rest of pushes
// whose rod rests clear of the object (samples_without_contact), and the friction fit holds with preloads and with
// per-push sensor offsets. A true bias is still found when some pushes start with a gap.
#define BOOST_TEST_MODULE diagnosis_preload
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "diagnosis_checks.hpp"
#include "pushpred/core/data_folder.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "pushpred/diagnosis/validation.hpp"
#include "pushpred/jobs/inspection_job.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "simulated_pushes.hpp"

using namespace pushpred;
using namespace pushpred::testing;

namespace {

/// Half of `scenarios` start pressed with `preload_N` on the rig's 1e4 N/m, the others 1 mm away: pushes 0, 1, 4,
/// 5, ... pressed, so that the fit pushes (every other one by name) hold both kinds.
void press_half(std::vector<PushScenario>& scenarios, double preload_N) {
  for (std::size_t k = 0; k < scenarios.size(); ++k)
    scenarios[k].approach_gap_m = k % 4 < 2 ? -preload_N / scenarios[k].contact_stiffness_N_m : 0.001;
}

/// Each push's own force-sensor zero error, normal with the pessimistic bound's spread per axis.
void offset_each_push(std::vector<PushScenario>& scenarios, std::mt19937_64& rng) {
  std::normal_distribution<double> offset(0.0, kPessimisticSensorZeroSpread_N);
  for (auto& s : scenarios) s.sensors.push_offset_N = Eigen::Vector2d(offset(rng), offset(rng));
}

/// Paper case 1 started 1 mm clear of the object, and the unit direction its tip travels [world frame].
std::pair<PushScenario, Eigen::Vector2d> clear_paper_case_1() {
  PushScenario s = paper_case_scenario(1);
  s.approach_gap_m = 0.001;
  const SynchronisedPush probe = simulate_and_synchronise(s);
  const Eigen::Index end = probe.t_s.size() - 1;
  return {s, (probe.tip_m.row(end) - probe.tip_m.row(0)).transpose().normalized()};
}

}  // namespace

BOOST_AUTO_TEST_SUITE(preload)

BOOST_AUTO_TEST_CASE(the_rest_of_a_pressing_rod_is_not_force_free_and_a_gap_is_measured) {
  PushScenario s = paper_case_scenario(1);
  s.sensors.noise_scale = s.sensors.jitter_scale = 1;
  for (const double gap : {0.001, 0.0005, -0.0002}) {
    s.approach_gap_m = gap;
    const SynchronisedPush push = simulate_and_synchronise(s);
    const auto rest = samples_before_tip_moves(push);
    BOOST_TEST_REQUIRE(rest.size() > 20u);
    // The gap the trackers measure is the simulated one (with a preload: the contact's compression, -f / k).
    BOOST_TEST(measured_rod_gap_m(push, rest[rest.size() / 2]) == gap, boost::test_tools::tolerance(0.1));
    const auto free = samples_without_contact(push);
    if (gap > kContactMargin_m)
      BOOST_TEST(free.size() == rest.size());
    else
      BOOST_TEST(free.empty());
  }
}

BOOST_AUTO_TEST_CASE(a_rest_force_that_points_into_the_contact_reads_as_pressed_whatever_the_gap) {
  // Paper case 1 pushes along the contact's inward normal, 1 mm clear of the object. A sensor zero of 2 N whose
  // reading points along the push (the recorded force is the true one less the zero) is what a pressing rod would
  // show: the push reads as pressed. The same zero pointing back, or across the push, is a zero.
  auto [s, along] = clear_paper_case_1();
  const Eigen::Vector2d across(-along.y(), along.x());
  for (const auto& [zero, into] : std::vector<std::pair<Eigen::Vector2d, bool>>{
           {-2.0 * along, true}, {2.0 * along, false}, {2.0 * across, false}, {-2.0 * across, false}}) {
    s.sensors.push_offset_N = zero;
    const SynchronisedPush push = simulate_and_synchronise(s);
    BOOST_TEST(rest_force_points_into_contact(push) == into, "zero " << zero.transpose() << " N");
    BOOST_TEST(samples_without_contact(push).empty() == into, "zero " << zero.transpose() << " N");
  }
}

BOOST_AUTO_TEST_CASE(a_bias_that_points_into_one_clear_pushs_contact_is_told_by_the_other_clear_pushes) {
  // Paper case 1, 1 mm clear, turned a quarter and a half turn: one sensor bias of 0.8 N reads along the first push
  // (into its contact, as a pressing rod would) and across or against the others. Alone the first push reads as
  // pressed; the force the clear pushes share tells it is the bias. A push pressed with a preload stays pressed.
  auto [s, along] = clear_paper_case_1();
  s.sensors.push_offset_N = -0.8 * along;
  std::vector<SynchronisedPush> pushes;
  for (const double turn_rad : {0.0, M_PI / 2, M_PI, -M_PI / 2}) {
    PushScenario turned = s;
    turned.initial_yaw_rad += turn_rad;
    pushes.push_back(simulate_and_synchronise(turned));
  }
  PushScenario pressed = s;
  pressed.approach_gap_m = -0.0002;
  pushes.push_back(simulate_and_synchronise(pressed));
  BOOST_TEST_REQUIRE(rest_force_points_into_contact(pushes[0]));
  BOOST_TEST(samples_without_contact(pushes[0]).empty());
  const Eigen::Vector2d shared = shared_rest_force_N(pushes);
  BOOST_TEST((shared - 0.8 * along).norm() < 0.1, "shared rest force " << shared.transpose() << " N");
  BOOST_TEST(!rest_force_points_into_contact(pushes[0], shared));
  BOOST_TEST(samples_without_contact(pushes[0], shared).size() > 20u);
  for (std::size_t p = 1; p < 4; ++p) BOOST_TEST(samples_without_contact(pushes[p], shared).size() > 20u);
  BOOST_TEST(samples_without_contact(pushes[4], shared).empty());
}

BOOST_AUTO_TEST_CASE(a_preload_does_not_give_a_bias) {
  // Paper case 4 (the rod pressing with 2 N from the start), seeds 100-104. Reading that
  // preload as a bias gave "force_offset 2.13 N" and a corrected mu of 0.265 where the simulator uses 0.47.
  std::vector<PushScenario> scenarios;
  for (std::uint64_t seed = 100; seed <= 104; ++seed) {
    PushScenario s = paper_case_scenario(4);
    s.seed = seed;
    scenarios.push_back(s);
  }
  const DiagnosisResult r = diagnose(simulate_all(scenarios), EffectLibrary::standard(), fast_options());
  log_result(r);
  check_only(r, {});
  const EffectReport& mu = report(r, "coulomb_friction");
  check_within_share(mu.theta(0), 0.47, 0.03, "mu");
}

/// Eight pushes drawn by `seed`, half pressed with 2 N, each with its own sensor zero (0.6 N per axis).
static DiagnosisResult diagnose_pressed_with_zeros(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto scenarios = draw_scenarios(rng, 8, {});
  press_half(scenarios, 2.0);
  offset_each_push(scenarios, rng);
  return diagnose(simulate_all(scenarios), EffectLibrary::standard(), fast_options());
}

// A pressed push's zero cannot be measured: the friction fit projects it out and rests its constant part on the
// pushes whose zero is measured (residual_regression.hpp, SensorZeros::PerPush). Over twelve draws of four fit
// pushes zero-mean zeros must not bias mu, and no other term (a drag) may stand in for the support's friction.
BOOST_AUTO_TEST_CASE(the_friction_fit_holds_with_preloads_and_per_push_offsets) {
  constexpr int kDraws = 12;
  double mu_sum = 0;
  int drags = 0;
  for (int draw = 0; draw < kDraws; ++draw) {
    const DiagnosisResult r = diagnose_pressed_with_zeros(27 + draw);
    const double mu = report(r, "coulomb_friction").theta(0);
    BOOST_TEST_MESSAGE("draw " << draw << ": mu " << mu << "; " << findings_text(r));
    mu_sum += mu;
    if (report(r, "viscous_friction").selected) ++drags;
  }
  check_within_share(mu_sum / kDraws, 0.47, 0.05, "mean mu over the draws");
  BOOST_TEST(drags == 0);
}

// The friction law fitted on pushes half of which start pressed: a constant added to a pressed push's sensor zero
// leaves mu where it was (that push's zero is projected out), where the zeros taken as recorded move it.
BOOST_AUTO_TEST_CASE(the_friction_fit_is_invariant_to_a_pressed_pushs_own_sensor_zero) {
  std::mt19937_64 rng(353000);
  auto scenarios = draw_scenarios(rng, 6, {});
  press_half(scenarios, 2.0);
  offset_each_push(scenarios, rng);
  std::vector<SynchronisedPush> pushes = simulate_all(scenarios);
  const auto law = make_coulomb_friction_effect();
  const auto fit_mu = [&](const std::vector<SynchronisedPush>& recorded, SensorZeros mode) {
    std::vector<DiagnosisPush> data;
    for (const auto& p : recorded) data.push_back(prepare_diagnosis_push(p, 0.0, p.duration_s()));
    EffectColumns coulomb(1, std::vector<Eigen::MatrixX3d>(data.size()));
    for (std::size_t p = 0; p < data.size(); ++p) coulomb[0][p] = law->regressors(data[p], 0.0)[0];
    const ResidualRegression regression(data, Relation::Friction, mode);
    if (mode == SensorZeros::PerPush) {
      BOOST_TEST(regression.zeros_projected() == 4);
      BOOST_TEST(regression.zeros_measured() == 2);
    }
    return regression.fit({&coulomb}).theta(0);
  };
  const double truth = scenarios.front().surface_friction;
  const double invariant = fit_mu(pushes, SensorZeros::PerPush);
  const double recorded = fit_mu(pushes, SensorZeros::AsRecorded);
  // Push 0 starts pressed: its zero grows by 1 N along x (the recorded force is the true one less the zero).
  BOOST_TEST_REQUIRE(!measured_sensor_zero_N(prepare_diagnosis_push(pushes[0], 0.0, pushes[0].duration_s())));
  pushes[0].force_N.col(0).array() -= 1.0;
  const double invariant_shifted = fit_mu(pushes, SensorZeros::PerPush);
  const double recorded_shifted = fit_mu(pushes, SensorZeros::AsRecorded);
  BOOST_TEST_MESSAGE("mu " << truth << ": per push " << invariant << " -> " << invariant_shifted << ", as recorded "
                           << recorded << " -> " << recorded_shifted);
  // Not exactly equal: the channel weights come from the linear base's residual, which the shifted zero moves a little.
  // (How close mu comes to the truth is judged over twelve draws, above: one draw of three fit pushes says little.)
  BOOST_TEST(std::abs(invariant_shifted - invariant) < 0.25 * std::abs(recorded_shifted - recorded));
}

// A joint fit whose Coulomb mu falls to zero or below has another term standing in for the support's friction. On
// this draw (seed 405) a drag of 86 1/s beside a mu of -0.007 fits the sliding data jointly; it must not be named.
BOOST_AUTO_TEST_CASE(no_drag_stands_in_for_the_support_friction) {
  const DiagnosisResult r = diagnose_pressed_with_zeros(405);
  log_result(r);
  BOOST_TEST(!report(r, "viscous_friction").selected, findings_text(r));
  check_within_share(report(r, "coulomb_friction").theta(0), 0.47, 0.25, "mu");
}

BOOST_AUTO_TEST_CASE(a_true_bias_is_found_on_the_pushes_that_start_clear) {
  std::mt19937_64 rng(28);
  const double amount = 0.6;
  // Eight pushes, half pressed: two of the four fit pushes rest clear, as a shared bias needs.
  auto scenarios = draw_scenarios(rng, 8, {{"force_offset", amount}});
  press_half(scenarios, 2.0);
  const DiagnosisResult r = diagnose(simulate_all(scenarios), EffectLibrary::standard(), fast_options());
  log_result(r);
  const EffectReport& e = report(r, "force_offset");
  BOOST_TEST(e.selected, findings_text(r));
  check_within_share(e.theta(0), amount, 0.25, "bias x [N]");
  check_within_share(e.theta(1), amount, 0.25, "bias y [N]");
}

// Three clean pushes 1 mm clear of the object. Each draw gives every push its own sensor zero, normal with the
// pessimistic bound's spread per axis (six times the real sensor's), added to its recorded force, while the rest fit
// assumes the rig's spread: nothing is shared, so the rest fit's score should pass the search's BIC threshold about as
// seldom as a normal statistic would (far below 1 %). Where the rests' means spread beyond what the setting allows,
// their own spread sets the variance on two degrees of freedom and the score is read against F(2, 2), not chi^2_2 (as
// a normal statistic it passes in about 15 % of the draws). Expected to fail, that claim (docs/diagnosis.md,
// "Limits"): where the three zeros happen to lie close together, nothing tells that their spread is beyond the
// setting, and the normal statistic passes; 5 of 191 draws (2.6 %) pass. A true bias of 1 N with the rig's own zeros,
// whose spread the setting explains, keeps the normal statistic and is found in every draw.
BOOST_AUTO_TEST_CASE(three_clear_pushes_whose_zeros_spread_beyond_the_setting_do_not_make_a_bias,
                     *boost::unit_test::expected_failures(1)) {
  std::mt19937_64 rng(358700);
  auto scenarios = draw_scenarios(rng, 3, {});
  for (auto& s : scenarios) s.approach_gap_m = 0.001;
  const std::vector<SynchronisedPush> clean = simulate_all(scenarios);
  const auto score = [&](double spread_N, const Eigen::Vector2d& bias_N) {
    std::normal_distribution<double> zero(0.0, spread_N);
    std::vector<SynchronisedPush> pushes = clean;
    std::vector<const SynchronisedPush*> pointers;
    for (auto& p : pushes) {
      const Eigen::RowVector2d offset(zero(rng), zero(rng));
      p.force_N.rowwise() += offset - bias_N.transpose();  // the sensor reads -f_C + b
      pointers.push_back(&p);
    }
    return rest_force_fit(pointers, Eigen::Vector2d::Zero(), kSensorZeroSpread_N);
  };
  const double threshold = DiagnosisOptions{}.bic_threshold;
  const int draws = 200;
  int chance = 0, tested = 0;
  for (int k = 0; k < draws; ++k) {
    const DirectFit fit = score(kPessimisticSensorZeroSpread_N, Eigen::Vector2d::Zero());
    if (!std::isfinite(fit.score)) continue;
    ++tested;
    chance += fit.score > threshold;
  }
  BOOST_TEST_MESSAGE("chance zeros passed in " << chance << " of " << tested << " draws with two or more clear rests");
  BOOST_TEST_REQUIRE(tested >= draws / 2);
  BOOST_TEST(chance <= tested / 50);
  int found = 0;
  for (int k = 0; k < 20; ++k) found += score(kSensorZeroSpread_N, Eigen::Vector2d(0.7, -0.7)).score > threshold;
  BOOST_TEST(found == 20);
}

// The same three clean pushes with the real sensor's zeros, and the rig's zero spread known
// (DiagnosisOptions::sensor_zero_spread_N): a chance mean of three zeros is judged against the spread the zeros
// have, not against the spread three of them happen to show, and passes the BIC threshold about as seldom as a
// normal statistic would; judged against their own spread alone, the same draws pass far more often. A bias five
// times the spread in each axis is still found in every draw that has two clear rests.
BOOST_AUTO_TEST_CASE(with_the_rigs_zero_spread_known_chance_zeros_do_not_make_a_bias_and_a_true_one_still_does) {
  std::mt19937_64 rng(359700);
  auto scenarios = draw_scenarios(rng, 3, {});
  for (auto& s : scenarios) s.approach_gap_m = 0.001;
  const std::vector<SynchronisedPush> clean = simulate_all(scenarios);
  const auto draw = [&](const Eigen::Vector2d& bias_N) {
    std::normal_distribution<double> zero(0.0, kSensorZeroSpread_N);
    std::vector<SynchronisedPush> pushes = clean;
    for (auto& p : pushes) {
      const Eigen::RowVector2d offset(zero(rng), zero(rng));
      p.force_N.rowwise() += offset - bias_N.transpose();  // the sensor reads -f_C + b
    }
    return pushes;
  };
  const auto fit = [](const std::vector<SynchronisedPush>& pushes, double spread_N) {
    std::vector<const SynchronisedPush*> pointers;
    for (const auto& p : pushes) pointers.push_back(&p);
    return rest_force_fit(pointers, Eigen::Vector2d::Zero(), spread_N);
  };
  const double threshold = DiagnosisOptions{}.bic_threshold;
  const int draws = 200;
  int with_spread = 0, own_spread_only = 0, tested = 0;
  for (int k = 0; k < draws; ++k) {
    const std::vector<SynchronisedPush> pushes = draw(Eigen::Vector2d::Zero());
    const DirectFit known = fit(pushes, kSensorZeroSpread_N);
    if (!std::isfinite(known.score)) continue;
    ++tested;
    with_spread += known.score > threshold;
    own_spread_only += fit(pushes, 0.0).score > threshold;
  }
  BOOST_TEST_MESSAGE("chance zeros passed in " << with_spread << " of " << tested << " draws with the spread known, "
                                               << own_spread_only << " with the pushes' own spread alone");
  BOOST_TEST_REQUIRE(tested >= draws / 2);
  BOOST_TEST(with_spread <= tested / 50);
  BOOST_TEST(own_spread_only > with_spread);
  const Eigen::Vector2d bias(5 * kSensorZeroSpread_N, -5 * kSensorZeroSpread_N);
  int found = 0, tested_biased = 0;
  for (int k = 0; k < 20; ++k) {
    const DirectFit biased = fit(draw(bias), kSensorZeroSpread_N);
    if (!std::isfinite(biased.score)) continue;  // fewer than two rests read clear: no test
    ++tested_biased;
    found += biased.score > threshold;
  }
  BOOST_TEST_REQUIRE(tested_biased >= 15);
  BOOST_TEST(found == tested_biased);
}

// A pressed push's zero bounded by the rig's known spread (residual_regression.hpp: a random effect, not a free
// constant): on a clean validation trial (372086: rect1, three of six pushes pressed, each push with its own zero) the
// free constants take up the Coulomb friction's constant within those pushes and leave a drag and Stribeck friction
// to stand in for what they took; with the spread known neither is named. (The trial is from the seeds the zero's
// prior was tried on, 372000-373654.)
BOOST_AUTO_TEST_CASE(a_pressed_pushs_zero_within_the_rigs_spread_leaves_no_drag_to_stand_in) {
  ValidationOptions o;
  o.seed = 372000;
  ValidationTrial trial;
  const std::vector<SynchronisedPush> pushes = simulate_trial(draw_validation_trial(o, 86, "none", trial));
  const DiagnosisResult bounded = diagnose(pushes, validation_library(o), o.diagnosis);
  DiagnosisOptions free_zeros = o.diagnosis;
  free_zeros.sensor_zero_spread_N = 0;  // each pressed push's zero a free constant
  const DiagnosisResult free = diagnose(pushes, validation_library(o), free_zeros);
  BOOST_TEST_MESSAGE("bounded: " << findings_text(bounded) << "; free: " << findings_text(free));
  BOOST_TEST(trial.preloaded_pushes >= 2);
  BOOST_TEST(!report(bounded, "viscous_friction").selected, findings_text(bounded));
  BOOST_TEST(!report(bounded, "stribeck_friction").selected, findings_text(bounded));
  BOOST_TEST((report(free, "viscous_friction").selected || report(free, "stribeck_friction").selected),
             findings_text(free));
}

// The simulated rig's clear rests, as `pushpred inspect` reads them (the mean force before the tip moves on pushes that
// do not start pressed), spread as the real rig's do: the zero drawn per push (kSimulatedSensorZeroSpread_N) is what
// the real rests spread beyond the sensor noise the simulator adds itself. A zero drawn at the real rests' own 0.10 N
// counts that noise twice.
BOOST_AUTO_TEST_CASE(the_simulated_rigs_clear_rests_spread_as_the_real_rigs_do) {
  const RestZeroSpread real_rests = rest_zero_spread(inspect_files({(resolve_data_folder() / "abs").string()}).results);
  const double real = real_rests.rms_per_axis_N;
  const int real_zeros = real_rests.zeros;
  auto simulated = [&](double spread_N) {
    ValidationOptions o;
    o.seed = 1;
    o.sensor_offset_spread_N = spread_N;
    std::vector<Inspection> pushes;
    for (int trial = 0; trial < 80; ++trial) {
      ValidationTrial t;
      const std::vector<PushScenario> scenarios = draw_validation_trial(o, trial, "none", t);
      const std::vector<SynchronisedPush> simulated = simulate_trial(scenarios);
      // The pushes drawn with a gap: the real rests inspect reads as zeros are clear ones (every real rest force
      // above 0.5 N points into the contact), and a light simulated preload can point elsewhere.
      for (std::size_t p = 0; p < simulated.size(); ++p)
        if (scenarios[p].approach_gap_m > 0) pushes.push_back(inspect(simulated[p]));
    }
    return rest_zero_spread(pushes);
  };
  const RestZeroSpread drawn_rests = simulated(ValidationOptions{}.sensor_offset_spread_N);
  const double drawn = drawn_rests.rms_per_axis_N, doubled = simulated(kSensorZeroSpread_N).rms_per_axis_N;
  const int zeros = drawn_rests.zeros;
  BOOST_TEST_MESSAGE("clear rests, RMS per axis: real "
                     << real << " N over " << real_zeros << " pushes; simulated " << drawn << " N over " << zeros
                     << " (zeros drawn at " << ValidationOptions{}.sensor_offset_spread_N << " N), " << doubled
                     << " N with zeros drawn at the real rests' spread");
  BOOST_TEST_REQUIRE(real_zeros >= 10);
  BOOST_TEST_REQUIRE(zeros >= 100);
  BOOST_TEST(std::abs(drawn / real - 1) < 0.15);
  BOOST_TEST(doubled / real > 1.15);  // outside the band the calibrated draw must fall in
}

BOOST_AUTO_TEST_SUITE_END()
