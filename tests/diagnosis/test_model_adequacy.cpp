// The model-adequacy test (diagnosis/model_adequacy.hpp): a residual the catalogue cannot explain is called
// "unexplained residual" with its size, clean pushes are "explained", the statistics find what was put into the data
// and not symmetric noise; and the joint test: a friction patch does not give a delay or a low-speed friction.
#define BOOST_TEST_MODULE diagnosis_adequacy
#include <boost/test/unit_test.hpp>
#include <cmath>
#include <random>

#include "diagnosis_checks.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/diagnosis/effect_floor.hpp"
#include "pushpred/diagnosis/model_adequacy.hpp"
#include "pushpred/diagnosis/validation.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "simulated_pushes.hpp"
#include "simulated_truth.hpp"

using namespace pushpred;
using namespace pushpred::testing;

namespace {

/// Clean simulated pushes prepared for the regression, with the Coulomb law's columns and mu fitted on them.
struct PreparedPushes {
  std::vector<DiagnosisPush> data;
  EffectColumns coulomb;
  FloorContext context;
};

/// Pushes 0, 1, 4, 5, ... of `scenarios` start pressed with 2 N on their contact stiffness, the others 1 mm away (so
/// that the fit pushes, every other one by name, hold both); each push has its own force-sensor zero, normal with
/// the pessimistic bound's spread per axis (six times the real sensor's).
bool pressed(std::size_t k) { return k % 4 < 2; }
void press_half_with_zeros(std::vector<PushScenario>& scenarios, std::mt19937_64& rng) {
  std::normal_distribution<double> zero(0.0, kPessimisticSensorZeroSpread_N);
  for (std::size_t k = 0; k < scenarios.size(); ++k) {
    scenarios[k].approach_gap_m = pressed(k) ? -2.0 / scenarios[k].contact_stiffness_N_m : 0.001;
    scenarios[k].sensors.push_offset_N = Eigen::Vector2d(zero(rng), zero(rng));
  }
}

PreparedPushes prepare(const std::vector<PushScenario>& scenarios) {
  PreparedPushes out;
  for (const auto& p : simulate_all(scenarios)) out.data.push_back(prepare_diagnosis_push(p, 0.0, p.duration_s()));
  const auto law = make_coulomb_friction_effect();
  out.coulomb.assign(1, std::vector<Eigen::MatrixX3d>(out.data.size()));
  for (std::size_t p = 0; p < out.data.size(); ++p) out.coulomb[0][p] = law->regressors(out.data[p], 0.0)[0];
  const RegressionFit f = ResidualRegression(out.data, Relation::Friction).fit({&out.coulomb});
  const ShapeInfo& shape = out.data.front().push.shape;
  out.context.mass_kg = shape.mass_kg;
  out.context.friction_coefficient = f.theta(0);
  out.context.radius_of_gyration_m = std::sqrt(shape.inertia_kgm2 / shape.mass_kg);
  return out;
}

std::vector<SynchronisedPush> recorded_pushes(const std::vector<DiagnosisPush>& pushes) {
  std::vector<SynchronisedPush> out;
  for (const auto& d : pushes) out.push_back(d.push);
  return out;
}

PreparedPushes prepare_clean(unsigned seed, int count) {
  std::mt19937_64 rng(seed);
  return prepare(draw_scenarios(rng, count, {}));
}

}  // namespace

BOOST_AUTO_TEST_SUITE(model_adequacy)

BOOST_AUTO_TEST_CASE(a_constant_world_force_left_in_the_residual_is_unexplained_and_hinted_as_such) {
  PreparedPushes clean = prepare_clean(230001, 4);
  ModelAdequacy without;
  test_residual_structure(clean.data, {&clean.coulomb}, clean.context, {}, without);
  BOOST_TEST_MESSAGE("clean: R^2 " << without.force_share << ", p " << without.force_p_value << ", " << without.force_N
                                   << " N (floor " << without.force_floor_N << " N)");
  BOOST_TEST(without.force_tested);
  BOOST_TEST(!without.force_unexplained, without.force_N << " N against the floor " << without.force_floor_N << " N");

  // A constant world-frame force of a quarter of the friction force (five times the floor) acts while the object
  // slides, as a support tilted by asin(mu / 4) would push it: the observer sees it through its Q filter.
  const double size_N = 0.25 * clean.context.friction_force_N();
  for (auto& d : clean.data) {
    Eigen::MatrixX3d raw = Eigen::MatrixX3d::Zero(d.rows(), 3);
    raw.col(0).setConstant(size_N * 0.6);
    raw.col(1).setConstant(size_N * 0.8);
    d.estimate.d_hat += d.as_observed(raw);
  }
  ModelAdequacy with;
  const auto hints = test_residual_structure(clean.data, {&clean.coulomb}, clean.context, {}, with);
  BOOST_TEST_MESSAGE("tilted: R^2 " << with.force_share << ", p " << with.force_p_value << ", " << with.force_N
                                    << " N");
  BOOST_TEST(with.force_unexplained);
  BOOST_TEST(with.force_p_value <= with.alpha);
  BOOST_REQUIRE(!hints.empty());
  BOOST_TEST(hints.front().signature == "world_force");
  // The structured part's size is the force put in (less what the Coulomb law's re-fit takes up along the motion).
  BOOST_TEST(with.force_N > 0.5 * size_N);
  BOOST_TEST(with.force_N < 1.1 * size_N);
}

BOOST_AUTO_TEST_CASE(a_sensor_bias_left_in_the_data_reads_at_rest_and_is_unexplained) {
  // Four clean pushes 1 mm clear of the object, each with the real sensor's own zero (0.1 N per axis): their rests
  // read those zeros and nothing the floor counts. A bias of three times the force floor on every push, which no
  // candidate took out, is the force the rests share: unexplained, at its size.
  std::mt19937_64 rng(230003);
  auto scenarios = draw_scenarios(rng, 4, {});
  std::normal_distribution<double> zero(0.0, kSensorZeroSpread_N);
  for (auto& s : scenarios) {
    s.approach_gap_m = 0.001;
    s.sensors.push_offset_N = Eigen::Vector2d(zero(rng), zero(rng));
  }
  PreparedPushes clean = prepare(scenarios);
  ModelAdequacy without;
  test_rest_force(recorded_pushes(clean.data), Eigen::Vector2d::Zero(), clean.context, 10.0, {}, without);
  BOOST_TEST_REQUIRE(without.rest_tested);
  BOOST_TEST(without.rest_pushes == 4);
  BOOST_TEST(!without.rest_unexplained, without.rest_force_N << " N, floor " << without.force_floor_N << " N");

  const double size_N = 3 * clean.context.relevance_fraction * clean.context.friction_force_N();
  for (auto& s : scenarios) s.effects.set("force_offset", size_N / std::sqrt(2.0));  // per axis
  PreparedPushes biased = prepare(scenarios);
  ModelAdequacy with;
  test_rest_force(recorded_pushes(biased.data), Eigen::Vector2d::Zero(), biased.context, 10.0, {}, with);
  BOOST_TEST(with.rest_unexplained, with.rest_force_N << " N, floor " << with.force_floor_N << " N");
  BOOST_TEST(with.rest_force_N == size_N, boost::test_tools::tolerance(0.25));
}

BOOST_AUTO_TEST_CASE(a_compliant_pusher_shows_in_the_contact_and_a_rigid_one_does_not) {
  // Six pushes by the rod on its contact stiffness: the recorded rod sits a little deeper in the outline the harder it
  // pushes, a lag far below the floor (kappa of how far the object travels). The same pushes by a pusher of three
  // times the compliance c whose lag under the friction force is that floor: in series with the contact, the pusher
  // adds c f to the penetration, the median slope grows by c, and the lag is unexplained.
  std::mt19937_64 rng(357300);
  auto scenarios = draw_scenarios(rng, 6, {});
  PreparedPushes rigid = prepare(scenarios);
  rigid.context = measure_floor_context(rigid.data, rigid.context.friction_coefficient, 0.0,
                                        rigid.context.relevance_fraction);  // with how far the objects travel
  const double contact_compliance = 1.0 / scenarios.front().contact_stiffness_N_m;
  const double floor_compliance =
      rigid.context.relevance_fraction * rigid.context.travel_m / rigid.context.friction_force_N();
  BOOST_TEST_MESSAGE("contact compliance " << 1e3 * contact_compliance << " mm/N, floor " << 1e3 * floor_compliance
                                           << " mm/N");

  ModelAdequacy without;
  test_contact_compliance(recorded_pushes(rigid.data), rigid.context, {}, without);
  BOOST_TEST_REQUIRE(without.contact_tested);
  BOOST_TEST(without.contact_pushes == 6);
  BOOST_TEST(!without.contact_unexplained, without.contact_lag_mm << " mm, floor " << without.contact_floor_mm);
  BOOST_TEST(without.contact_compliance_m_N > 0.5 * contact_compliance);  // the contact's own give

  for (auto& s : scenarios) s.effects.set("compliant_pusher", 3 * floor_compliance);
  ModelAdequacy with;
  test_contact_compliance(simulate_all(scenarios), rigid.context, {}, with);
  BOOST_TEST_REQUIRE(with.contact_tested);
  BOOST_TEST_MESSAGE("median slopes " << 1e3 * without.contact_compliance_m_N << " and "
                                      << 1e3 * with.contact_compliance_m_N << " mm/N");
  BOOST_TEST(with.contact_unexplained, with.contact_lag_mm << " mm, floor " << with.contact_floor_mm);
  BOOST_TEST(with.contact_compliance_m_N - without.contact_compliance_m_N == 3 * floor_compliance,
             boost::test_tools::tolerance(0.15));
}

BOOST_AUTO_TEST_CASE(the_motion_test_finds_a_systematic_bias_and_not_symmetric_noise) {
  std::mt19937_64 rng(230002);
  std::normal_distribution<double> noise(0.0, 0.5e-3);  // 0.5 mm per phase
  std::vector<PhaseBias> symmetric, biased;
  for (int k = 0; k < 16; ++k) {
    PhaseBias b;
    b.position_m = Eigen::Vector2d(noise(rng), noise(rng));
    b.yaw_rad = noise(rng);  // 0.03 deg
    const double angle = 0.4 * k;
    b.travel_direction = Eigen::Vector2d(std::cos(angle), std::sin(angle));
    symmetric.push_back(b);
    b.position_m -= 2e-3 * b.travel_direction;  // the model runs 2 mm behind, along every phase's travel
    biased.push_back(b);
  }
  ModelAdequacy a, b;
  test_motion_bias(symmetric, 10.0, 5.0, 0.05, 0.0, {}, a);  // floor: 0.5 mm, 0.25 deg
  test_motion_bias(biased, 10.0, 5.0, 0.05, 0.0, {}, b);
  BOOST_TEST(a.motion_tested);
  BOOST_TEST(!a.motion_unexplained, "p " << a.motion_p_value << ", bias " << a.position_bias_mm << " mm");
  BOOST_TEST(b.motion_unexplained, "p " << b.motion_p_value << ", bias " << b.position_bias_mm << " mm");
  BOOST_TEST(b.position_bias_mm == 2.0, boost::test_tools::tolerance(0.2));
  BOOST_TEST(b.position_floor_mm == 0.5, boost::test_tools::tolerance(1e-9));
  // Fewer than four phases are not tested.
  ModelAdequacy few;
  test_motion_bias({biased.begin(), biased.begin() + 3}, 10.0, 5.0, 0.05, 0.0, {}, few);
  BOOST_TEST(!few.motion_tested);
  BOOST_TEST(!few.motion_unexplained);
}

BOOST_AUTO_TEST_CASE(clean_pushes_are_explained) {
  std::mt19937_64 rng(230010);
  const auto pushes = simulate_all(draw_scenarios(rng, 6, {}));
  const DiagnosisResult r = diagnose(pushes, EffectLibrary::standard(), fast_options());
  log_result(r);
  BOOST_TEST(r.adequacy.tested);
  BOOST_TEST(r.adequacy.explained, r.adequacy.verdict());
  BOOST_TEST(effects_found(r).empty(), findings_text(r));
  BOOST_TEST(findings_text(r).rfind("nothing found, residual explained", 0) == 0u, findings_text(r));
  BOOST_TEST(hints_json(r).empty());
}

BOOST_AUTO_TEST_CASE(the_corrected_models_rod_gives_way_as_the_fit_pushes_contact_does) {
  // Clean pushes on a soft contact (4 kN/m, 0.25 mm/N): with measured_contact_compliance the base model's pushing
  // model takes the fit pushes' median contact slope as its compliance, which the contact part measures on all pushes,
  // and the report says so; without it the rod stays rigid.
  std::mt19937_64 rng(230015);
  auto scenarios = draw_scenarios(rng, 6, {});
  for (auto& s : scenarios) s.contact_stiffness_N_m = 4000;
  DiagnosisOptions options = fast_options();
  options.measured_contact_compliance = true;
  const DiagnosisResult r = diagnose(simulate_all(scenarios), EffectLibrary::standard(), options);
  log_result(r);
  BOOST_TEST_REQUIRE(r.correction.pushing_model);
  BOOST_TEST_REQUIRE(r.adequacy.contact_tested);
  BOOST_TEST_MESSAGE("compliance: corrected model " << 1e3 * r.correction.contact_compliance_m_N
                                                    << " mm/N, contact part " << 1e3 * r.adequacy.contact_compliance_m_N
                                                    << " mm/N, simulated 0.25 mm/N");
  BOOST_TEST(r.correction.contact_compliance_m_N == 1.0 / 4000, boost::test_tools::tolerance(0.4));
  BOOST_TEST(r.correction.contact_compliance_m_N == r.adequacy.contact_compliance_m_N,
             boost::test_tools::tolerance(0.25));
  bool described = false;
  for (const auto& line : r.correction.describe()) described |= line.find("rod sinks") != std::string::npos;
  BOOST_TEST(described);
  const DiagnosisResult rigid = diagnose(simulate_all(scenarios), EffectLibrary::standard(), fast_options());
  BOOST_TEST(rigid.correction.contact_compliance_m_N == 0.0);
}

BOOST_AUTO_TEST_CASE(a_kind_missing_from_the_catalogue_gives_unexplained_residual) {
  // Drag well above its floor (the floor is about 5 1/s on these speeds), diagnosed by a catalogue without it.
  std::mt19937_64 rng(230020);
  DrawRanges ranges;
  ranges.speed_min_m_s = 0.02;
  ranges.speed_max_m_s = 0.15;
  const auto pushes = simulate_all(draw_scenarios(rng, 8, {{"viscous_friction", 30.0}}, ranges));
  EffectLibrary library = EffectLibrary::standard();
  library.remove("viscous_friction");
  const DiagnosisResult r = diagnose(pushes, library, fast_options());
  log_result(r);
  BOOST_TEST(r.adequacy.tested);
  BOOST_TEST(!r.adequacy.explained, r.adequacy.verdict());
  BOOST_TEST(effects_found(r).empty(), findings_text(r));
  const std::string headline = findings_text(r);
  BOOST_TEST(headline.rfind("unexplained residual", 0) == 0u, headline);
  BOOST_TEST(headline.find("nothing found") == std::string::npos, headline);
  const auto summary = diagnosis_summary_text(r);
  BOOST_TEST(summary.find("hint (not a finding): speed") != std::string::npos, summary);
}

BOOST_AUTO_TEST_CASE(a_friction_patch_does_not_give_a_delay) {
  // A patch of half as much again to three times the friction: whatever position_friction is called (found or
  // significant but negligible), neither a force-stream delay nor a low-speed friction is found, and its amount,
  // put into the patch's excess (simulated_truth.hpp), is within a quarter of the excess simulated.
  std::mt19937_64 rng(230030);
  const double amount = draw(rng, 0.5, 2.0);
  DrawRanges ranges;
  ranges.length_min_m = 0.04;
  ranges.length_max_m = 0.06;
  std::vector<SynchronisedPush> pushes;
  const auto sims = simulate_with_states(draw_scenarios(rng, 10, {{"position_friction", amount}}, ranges), pushes);
  const DiagnosisResult r = diagnose(pushes, EffectLibrary::standard(), fast_options());
  log_result(r);
  BOOST_TEST(!report(r, "time_offset").selected, findings_text(r));
  BOOST_TEST(!report(r, "stribeck_friction").selected, findings_text(r));
  const EffectReport& e = report(r, "position_friction");
  BOOST_TEST(e.passed_test);
  check_within_share(e.theta(0) / patch_gradient_per_unit_excess(sims, e.setting), amount, 0.25, "patch excess");
}

BOOST_AUTO_TEST_CASE(an_unknown_sensor_zero_on_pressed_pushes_leaves_a_clean_model_explained) {
  // Eight clean pushes, four starting pressed, each with its own sensor zero (0.6 N per axis). The zero a pressing
  // rod hides is projected out; the others are measured at rest, and that measure is the simulated zero.
  std::mt19937_64 rng(320500);
  auto scenarios = draw_scenarios(rng, 8, {});
  press_half_with_zeros(scenarios, rng);
  const PreparedPushes pushes = prepare(scenarios);
  // A clear push whose zero happens to point into the contact reads as pressed (samples_without_contact).
  int measured = 0;
  for (std::size_t p = 0; p < scenarios.size(); ++p) {
    const auto zero = measured_sensor_zero_N(pushes.data[p]);
    const bool reads_clear = !pressed(p) && !rest_force_points_into_contact(pushes.data[p].push);
    measured += reads_clear;
    BOOST_TEST(zero.has_value() == reads_clear, "push " << p);
    // The rest's mean tells the simulated zero to half the zeros' push-to-push spread (the sensor's slow noise, 0.1 N
    // in fy, over a rest of a few tenths of a second).
    if (zero)
      BOOST_TEST((*zero - scenarios[p].sensors.push_offset_N).norm() < 0.5 * kPessimisticSensorZeroSpread_N,
                 "push " << p << ": measured " << zero->transpose() << " N, simulated "
                         << scenarios[p].sensors.push_offset_N.transpose() << " N");
  }
  ModelAdequacy invariant, as_recorded;
  test_residual_structure(pushes.data, {&pushes.coulomb}, pushes.context, {}, invariant);
  AdequacyOptions recorded;
  recorded.sensor_zeros = false;
  test_residual_structure(pushes.data, {&pushes.coulomb}, pushes.context, recorded, as_recorded);
  BOOST_TEST_MESSAGE("zeros taken out: p "
                     << invariant.force_p_value << ", " << invariant.force_N << " N, " << invariant.torque_Nm
                     << " N m, shared " << invariant.shared_force_N << " N (p " << invariant.shared_force_p_value
                     << "); as recorded: p " << as_recorded.force_p_value << ", " << as_recorded.force_N << " N, "
                     << as_recorded.torque_Nm << " N m (floors " << invariant.force_floor_N << " N, "
                     << invariant.torque_floor_Nm << " N m)");
  BOOST_TEST_REQUIRE(measured >= 2);  // or the measured zeros' part is not tested
  BOOST_TEST(invariant.pushes_zero_projected == 8 - measured);
  BOOST_TEST(invariant.zero_measured_pushes == measured);
  BOOST_TEST(!invariant.force_unexplained, invariant.force_N << " N, " << invariant.torque_Nm << " N m");
  // The same pushes with the zeros taken as recorded: the zeros alone leave structure of the size of the floor.
  BOOST_TEST(as_recorded.force_N > 2 * invariant.force_N);
  BOOST_TEST(as_recorded.torque_Nm > 2 * invariant.torque_Nm);
}

BOOST_AUTO_TEST_CASE(a_sensor_zeroed_on_every_push_is_taken_as_recorded) {
  // Clean pushes 1 mm away and no zeros: the measured zeros spread by the sensor's noise, far below the force floor,
  // and the test is the one that takes the zeros as recorded.
  const PreparedPushes clean = prepare_clean(320530, 6);
  ModelAdequacy a, as_recorded;
  test_residual_structure(clean.data, {&clean.coulomb}, clean.context, {}, a);
  AdequacyOptions recorded;
  recorded.sensor_zeros = false;
  test_residual_structure(clean.data, {&clean.coulomb}, clean.context, recorded, as_recorded);
  BOOST_TEST_MESSAGE("zeros' spread " << a.zero_spread_N << " N, floor " << a.force_floor_N << " N");
  BOOST_TEST(a.zero_spread_N < 0.5 * a.force_floor_N);
  BOOST_TEST(a.pushes_zero_projected == 0);
  BOOST_TEST(a.zero_measured_pushes == 0);
  BOOST_TEST(a.force_statistic == as_recorded.force_statistic);
  BOOST_TEST(a.force_N == as_recorded.force_N);
  BOOST_TEST(!a.force_unexplained);
}

// The support's friction half as large again along the body's x axis as along y (never in the catalogue), on pushes
// half of which start pressed, each with its own zero: taking the zeros out of the adequacy test does not take the
// missing friction with them. Expected to fail, the last claim (no kind named; docs/diagnosis.md, "Limits"): one
// clear push's zero points into its contact and reads as pressed, and with its zero projected a 9 mm mass-centre
// offset stands in for part of the direction-dependent friction's torque (held out it predicts worse).
BOOST_AUTO_TEST_CASE(a_hidden_anisotropic_friction_is_still_unexplained_with_sensor_zeros_and_preloads,
                     *boost::unit_test::expected_failures(1)) {
  std::mt19937_64 rng(320510);
  DrawRanges ranges;
  ranges.speed_min_m_s = 0.02;
  ranges.speed_max_m_s = 0.15;
  auto scenarios = draw_scenarios(rng, 8, {{"anisotropic_friction", 1.5}}, ranges);
  press_half_with_zeros(scenarios, rng);
  const EffectLibrary library = EffectLibrary::standard();
  BOOST_REQUIRE(!library.find("anisotropic_friction"));
  const DiagnosisResult r = diagnose(simulate_all(scenarios), library, fast_options());
  log_result(r);
  BOOST_TEST(r.adequacy.tested);
  BOOST_TEST(r.adequacy.pushes_zero_projected > 0);
  BOOST_TEST(!r.adequacy.explained, r.adequacy.verdict());
  BOOST_TEST(effects_found(r).empty(), findings_text(r));
}

BOOST_AUTO_TEST_CASE(a_bias_the_measured_pushes_share_is_unexplained_beyond_their_zeros) {
  // A sensor bias of 2 N, against zeros of 0.6 N per axis, on six pushes of which four rest clear: the measured
  // pushes' mean zero carries it, and their spread does not.
  std::mt19937_64 rng(320520);
  auto scenarios = draw_scenarios(rng, 6, {{"force_offset", 2.0}});
  std::normal_distribution<double> zero(0.0, kPessimisticSensorZeroSpread_N);
  for (std::size_t k = 0; k < scenarios.size(); ++k) {
    scenarios[k].approach_gap_m = k < 2 ? -2.0 / scenarios[k].contact_stiffness_N_m : 0.001;
    scenarios[k].sensors.push_offset_N = Eigen::Vector2d(zero(rng), zero(rng));
  }
  const PreparedPushes pushes = prepare(scenarios);
  int clear = 0;  // the bias's rest force may point into a clear push's contact: that push then reads as pressed
  for (std::size_t k = 2; k < scenarios.size(); ++k) clear += !rest_force_points_into_contact(pushes.data[k].push);
  BOOST_TEST_REQUIRE(clear >= 2);
  ModelAdequacy a;
  test_residual_structure(pushes.data, {&pushes.coulomb}, pushes.context, {}, a);
  BOOST_TEST_MESSAGE("shared " << a.shared_force_N << " +- " << a.shared_force_N_std << " N, p "
                               << a.shared_force_p_value << " (floor " << a.force_floor_N << " N)");
  BOOST_TEST(a.zero_measured_pushes == clear);
  BOOST_TEST(a.shared_force_unexplained);
  // The bias is 2 N on each axis: |(2, 2)| = 2.83 N, less what the Coulomb law's re-fit takes up along the motion.
  BOOST_TEST(a.shared_force_N > 0.5 * 2.83);
  BOOST_TEST(a.shared_force_N < 1.3 * 2.83);
}

BOOST_AUTO_TEST_SUITE_END()
