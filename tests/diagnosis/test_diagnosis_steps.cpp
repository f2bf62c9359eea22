// The diagnosis as a pipeline of typed steps, and what evidence decides: each step runs alone on its typed input and
// returns its decisions; the base model is part of
// every corrected model; an effect found below its floor is reported as significant but negligible; a step that
// fails is reported and the diagnosis goes on; and a few blind trials of randomized physics (validation.hpp) name
// the right kind at twice its floor and nothing on clean data. (The full validation, 20+ trials per kind on seeds
// nobody tuned on, is `pushpred validate-diagnosis`, docs/diagnosis.md.)
#define BOOST_TEST_MODULE diagnosis_steps
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "diagnosis_checks.hpp"
#include "pushpred/core/error.hpp"
#include "pushpred/diagnosis/builtin_effects.hpp"
#include "pushpred/diagnosis/corrected_prediction.hpp"
#include "pushpred/diagnosis/diagnosis_data.hpp"
#include "pushpred/diagnosis/diagnosis_pipeline.hpp"
#include "pushpred/diagnosis/validation.hpp"
#include "pushpred/reports/diagnosis_report.hpp"
#include "pushpred/simulation/simulator.hpp"
#include "simulated_pushes.hpp"

using namespace pushpred;
using namespace pushpred::testing;

namespace {

/// The base model's parts, in every corrected model: the pushing model predicts, the force-domain structure is its
/// fallback, and the friction law fitted on the fit pushes' force stops its slide to rest (where the `quasi_static`
/// reference, the pushing model alone, stops it with the friction it identifies on each phase).
void check_base_model(const DiagnosisResult& r) {
  for (const char* kind : {"coulomb_friction", "initial_velocity", "quasi_static", "pusher_stop", "pushing_model"}) {
    BOOST_TEST(report(r, kind).structural, kind);
    BOOST_TEST(report(r, kind).selected, kind << " is part of the base model");
  }
  BOOST_TEST(r.correction.pushing_model);
  BOOST_TEST(r.correction.initial_velocity);
  BOOST_TEST(r.correction.quasi_static.enabled);
  BOOST_TEST(r.correction.quasi_static.pusher_stop_speed_m_s > 0);
  BOOST_TEST(std::any_of(r.correction.force_laws.begin(), r.correction.force_laws.end(),
                         [](const FittedForceLaw& law) { return law.effect->kind() == "coulomb_friction"; }));
  BOOST_TEST(r.error_base.phases == r.error_after.phases);
  BOOST_TEST(r.error_base.phases == r.quasi_static.phases);
}

/// Trial `index` of a validation run with amounts fixed at `multiple` floors, simulated and diagnosed.
struct Trial {
  ValidationTrial trial;
  DiagnosisResult result;
};
Trial run_trial(const std::string& kind, int index, double multiple, std::uint64_t seed = 7000) {
  ValidationOptions o;
  o.seed = seed;
  // The trials of the seeds below were drawn without preloads or sensor offsets.
  o.draw_preloads = o.draw_sensor_offsets = false;
  o.min_floor_multiple = o.max_floor_multiple = multiple;
  o.min_pushes = 6;
  o.max_pushes = 6;
  o.diagnosis = fast_options();
  Trial t;
  const auto scenarios = draw_validation_trial(o, index, kind, t.trial);
  t.result = diagnose(simulate_trial(scenarios), EffectLibrary::standard(), o.diagnosis);
  score_trial(t.result, t.trial);
  BOOST_TEST_MESSAGE(kind << " trial " << index << " (" << t.trial.shape << ", mu " << t.trial.surface_friction
                          << ", amount " << t.trial.amount << ", floor " << t.trial.floor << "): "
                          << findings_text(t.result) << " | the true kind: score " << t.trial.true_score
                          << ", amount " << t.trial.true_amount << " against floor " << t.trial.true_floor << "; "
                          << t.trial.true_note);
  return t;
}

/// Trial `index` of a blind validation run of `seed` with the validation's defaults (validate-diagnosis's trials),
/// simulated, diagnosed and scored.
/// `zeros`: drawn with the validation's default preloads and sensor zeros; otherwise without either (as the trials
/// of seeds below 250000 were).
Trial blind_trial(std::uint64_t seed, int index, const std::string& kind, bool zeros = false,
                  double zero_spread_N = kSimulatedSensorZeroSpread_N) {
  ValidationOptions o;
  o.seed = seed;
  o.sensor_offset_spread_N = zero_spread_N;
  o.draw_preloads = o.draw_sensor_offsets = zeros;
  Trial t;
  t.result = diagnose(simulate_trial(draw_validation_trial(o, index, kind, t.trial)), EffectLibrary::standard(),
                      o.diagnosis);
  score_trial(t.result, t.trial);
  return t;
}

/// Trial `index` of `validate-diagnosis --kinds KIND --hide KIND --seed SEED` (the validation's defaults, preloads and
/// sensor zeros drawn): `kind` simulated and diagnosed with a catalogue that lacks it.
DiagnosisResult hidden_trial(std::uint64_t seed, int index, const std::string& kind,
                             double zero_spread_N = kSimulatedSensorZeroSpread_N) {
  ValidationOptions o;
  o.seed = seed;
  o.sensor_offset_spread_N = zero_spread_N;
  o.hide = {kind};
  ValidationTrial v;
  return diagnose(simulate_trial(draw_validation_trial(o, index, kind, v)), validation_library(o), o.diagnosis);
}

/// The steps' shared context for `pushes`: split and the paper's method run.
struct Steps {
  explicit Steps(const std::vector<SynchronisedPush>& pushes, const DiagnosisOptions& options = fast_options())
      : paper(paper_method(split_pushes(pushes, EffectLibrary::standard(), options))) {}
  const DiagnosisContext& context() const { return paper.context; }
  PaperMethodOutcome paper;
};

std::size_t index_of(const DiagnosisContext& context, const std::string& kind) {
  const auto& effects = context.library.effects();
  for (std::size_t i = 0; i < effects.size(); ++i)
    if (effects[i]->kind() == kind) return i;
  throw std::runtime_error("no effect " + kind);
}

const Selection* term(const std::vector<Selection>& terms, std::size_t candidate) {
  for (const auto& t : terms)
    if (t.candidate == candidate) return &t;
  return nullptr;
}

/// A user's effect whose regressor cannot be computed: its failure must be reported, not scored.
class BrokenEffect final : public ForceLawEffect {
 public:
  std::string kind() const override { return "broken"; }
  std::string description() const override { return "a regressor that throws"; }
  std::vector<EffectParameter> parameters() const override { return {{"k", "-"}}; }
  bool needs_friction_base() const override { return true; }
  std::vector<Eigen::MatrixX3d> regressors(const DiagnosisPush&, double) const override {
    throw InputError("broken: no regressor here");
  }
  Eigen::Vector3d unit_force(int, double, const EffectState&, const ShapeInfo&) const override {
    throw InputError("broken: no force here");
  }
};

}  // namespace

BOOST_AUTO_TEST_SUITE(steps)

BOOST_AUTO_TEST_CASE(a_found_mass_centre_offset_moves_the_pushing_models_centre_of_friction) {
  std::mt19937_64 rng(5);
  const auto pushes = simulate_all(draw_scenarios(rng, 1, {}));
  const auto library = EffectLibrary::standard();
  const auto com = library.find("com_offset");
  ModelCorrection c;
  com->apply(Eigen::Vector2d(0.003, -0.002), 0.0, com, c);
  library.find("pushing_model")->apply(Eigen::VectorXd(0), 0.0, library.find("pushing_model"), c);
  const CorrectedPrediction corrected(c);
  BOOST_TEST(corrected.predicts_with_pushing_model());
  const SynchronisedPush moved = corrected.pushing_model_push(pushes.front());
  BOOST_TEST(moved.shape.centroid_m.x() == pushes.front().shape.centroid_m.x() + 0.003, boost::test_tools::tolerance(1e-12));
  BOOST_TEST(moved.shape.centroid_m.y() == pushes.front().shape.centroid_m.y() - 0.002, boost::test_tools::tolerance(1e-12));
  // The relation model reads the offset through com_offset's force law, not through the push.
  BOOST_TEST(corrected.corrected_push(pushes.front()).shape.centroid_m == pushes.front().shape.centroid_m);
  // Every force law is the friction of the pushing model's slide to rest.
  BOOST_TEST(corrected.free_slide_terms(pushes.front(), Eigen::Vector3d::Zero()).size() == c.force_laws.size());
  BOOST_TEST(CorrectedPrediction(ModelCorrection{}).free_slide_terms(pushes.front(), Eigen::Vector3d::Zero()).empty());
}

BOOST_AUTO_TEST_CASE(alternate_pushes_sorted_by_name_are_fit_and_test_pushes_and_a_frozen_sensor_is_left_out) {
  std::mt19937_64 rng(30);
  std::vector<SynchronisedPush> pushes = simulate_all(draw_scenarios(rng, 5, {}));
  for (std::size_t k = 0; k < pushes.size(); ++k) pushes[k].source = "push_" + std::to_string(4 - k);  // reversed
  pushes[2].flags.frozen_force_sensor = true;                                                          // push_2
  const DiagnosisInput input = split_pushes(pushes, EffectLibrary::standard(), fast_options());
  const auto sources = [](const std::vector<SynchronisedPush>& v) {
    std::vector<std::string> out;
    for (const auto& p : v) out.push_back(p.source);
    return out;
  };
  BOOST_TEST(sources(input.fit_pushes) == (std::vector<std::string>{"push_0", "push_3"}),
             boost::test_tools::per_element());
  BOOST_TEST(sources(input.test_pushes) == (std::vector<std::string>{"push_1", "push_4"}),
             boost::test_tools::per_element());
  BOOST_TEST_REQUIRE(input.failures.size() == 1u);
  BOOST_TEST(input.failures[0].source == "push_2");
  BOOST_TEST(input.failures[0].reason.find("frozen") != std::string::npos, input.failures[0].reason);
  BOOST_TEST(input.caution.empty(), "four usable pushes are what the validation covers");
  // The paper's method runs on all of them: the context holds the same split, and the residual per fit push.
  const PaperMethodOutcome paper = paper_method(input);
  BOOST_TEST(sources(paper.context.fit_pushes) == sources(input.fit_pushes), boost::test_tools::per_element());
  BOOST_TEST(paper.failures.empty());
  BOOST_TEST(paper.residual_before.size() == 2u);
  BOOST_TEST(paper.model.terms.empty());
  BOOST_TEST(paper.context.hold_position_mm > 1e-3);
}

BOOST_AUTO_TEST_CASE(the_friction_base_fits_mu_on_clean_pushes_and_measures_the_floors_with_it) {
  std::mt19937_64 rng(31);
  const Steps s(simulate_all(draw_scenarios(rng, 4, {})));
  const FrictionBase base = friction_base(s.context(), s.paper.model);
  const std::size_t law = index_of(s.context(), "coulomb_friction");
  const Selection* mu = term(base.model.terms, law);
  BOOST_TEST_REQUIRE(mu != nullptr, "the friction law is in the base model");
  check_within_share(mu->total(0), 0.47, 0.05, "mu");
  // The floors were measured with it: the friction force of the simulated object.
  BOOST_TEST(base.floors.friction_force_N() == mu->total(0) * 1.045 * 9.81, boost::test_tools::tolerance(1e-9));
  BOOST_TEST(base.floors.sliding_speed_m_s > 0.02);
  BOOST_TEST(base.floors.sliding_speed_m_s < 0.09);
  // The step found no physical effect, and its decisions say what it fitted.
  for (const auto& t : base.model.terms) BOOST_TEST(s.context().is_base(t.candidate));
  const auto decisions = base.trace.decisions_of(law);
  BOOST_TEST_REQUIRE(decisions.size() == 1u);
  BOOST_TEST((decisions[0].verdict == Verdict::BaseLawFitted));
  BOOST_TEST(decisions[0].passed);
}

BOOST_AUTO_TEST_CASE(the_direct_effects_step_alone_finds_a_sensor_bias_and_applies_it) {
  std::mt19937_64 rng(32);
  const Steps s(simulate_all(draw_scenarios(rng, 4, {{"force_offset", 0.6}})));
  const FrictionBase base = friction_base(s.context(), s.paper.model);
  const DirectEffects direct = direct_effects(s.context(), base.model, base.floors);
  const std::size_t bias = index_of(s.context(), "force_offset");
  const Selection* found = term(direct.model.terms, bias);
  BOOST_TEST_REQUIRE(found != nullptr, "the bias should be found");
  check_within_share(found->total(0), 0.6, 0.25, "bias x [N]");
  const auto decisions = direct.trace.decisions_of(bias);
  BOOST_TEST_REQUIRE(!decisions.empty());
  BOOST_TEST((decisions.back().verdict == Verdict::Found));
  BOOST_TEST(decisions.back().amount - decisions.back().amount_std > decisions.back().floor.amount);
  // A found data correction is applied: the step's data are the pushes with the bias removed, not its input's.
  BOOST_TEST_REQUIRE(direct.model.data.size() == base.model.data.size());
  BOOST_TEST(!direct.model.data.front().push.force_N.isApprox(base.model.data.front().push.force_N));
}

BOOST_AUTO_TEST_CASE(
    a_candidate_significant_but_below_its_floor_is_a_nuisance_not_a_finding_and_the_decision_says_why) {
  // A 1 mm mass-centre offset on rect2 (floor: 5 % of the 41 mm radius of gyration, 2.1 mm): the torque channel
  // resolves it, but it changes the motion less than the support's own variation.
  std::mt19937_64 rng(34);
  const Steps s(simulate_all(draw_scenarios(rng, 6, {{"com_offset", 0.001}})));
  const FrictionBase base = friction_base(s.context(), s.paper.model);
  const DirectEffects direct = direct_effects(s.context(), base.model, base.floors);
  const ForceLaws laws = force_laws(s.context(), direct.model, base.floors);
  const std::size_t com = index_of(s.context(), "com_offset");
  BOOST_TEST(term(laws.model.terms, com) == nullptr, "not found");
  const auto decisions = laws.trace.decisions_of(com);
  const auto negligible = std::find_if(decisions.begin(), decisions.end(),
                                       [](const SelectionDecision& d) { return d.verdict == Verdict::Negligible; });
  BOOST_TEST_REQUIRE((negligible != decisions.end()), "the search should judge it negligible");
  BOOST_TEST(negligible->score > s.context().options.bic_threshold, "significant");
  BOOST_TEST(negligible->amount < negligible->floor.amount);
  BOOST_TEST(negligible->floor.amount == 0.05 * std::sqrt(0.001808 / 1.045), boost::test_tools::tolerance(1e-9));
  // The separate rendering pass turns the decision into the report's note and the log's line.
  EffectReport r;
  r.amount_unit = "m";
  apply_decision(*negligible, 1.0, r);
  BOOST_TEST(r.passed_test);
  BOOST_TEST(r.negligible);
  BOOST_TEST(r.note.rfind("significant, negligible: ", 0) == 0u, r.note);
  BOOST_TEST(r.note.find("is below its floor") != std::string::npos, r.note);
  BOOST_TEST(decision_log_line(*negligible, "com_offset")->find("does not clear its floor by the margin") !=
             std::string::npos);
}

BOOST_AUTO_TEST_CASE(a_trials_decisions_are_discarded_and_only_its_lines_kept) {
  // A data correction that stands beside the refinements searched anew keeps the selection found with it: the trial's
  // decisions must not reach the report, its narrative stays in the log, marked as a trial.
  const EffectLibrary library = EffectLibrary::standard();
  std::size_t drag = 0;
  while (library.effects()[drag]->kind() != "viscous_friction") ++drag;
  DiagnosisTrace trial;
  trial.line("time_offset: tested again");
  SelectionDecision joins = decision_about(drag, Verdict::Found, SearchStage::GreedyFriction);
  joins.score = 12;
  trial.decide(joins);
  trial.decide(decision_about(drag, Verdict::Fitted, SearchStage::GreedyFriction));  // no line of its own
  const DiagnosisTrace kept = trial.as_trial_lines(library, "  (trial) ");
  DiagnosisResult r;
  r.effects = blank_reports(library);
  render_trace(kept, library, 1.0, r);
  BOOST_TEST(r.log == (std::vector<std::string>{"  (trial) time_offset: tested again",
                                                "  (trial) greedy (against the friction law): viscous_friction joins, "
                                                "score 12.0"}),
             boost::test_tools::per_element());
  BOOST_TEST(!r.effects[drag].passed_test);
  BOOST_TEST(kept.decisions_of(drag).empty());
}

BOOST_AUTO_TEST_CASE(the_base_structure_takes_every_base_prediction_part_and_chooses_only_its_settings) {
  std::mt19937_64 rng(36);
  DiagnosisOptions options = fast_options();
  options.fit_base_settings = true;
  const Steps s(simulate_all(draw_scenarios(rng, 4, {})), options);
  const FrictionBase base = friction_base(s.context(), s.paper.model);
  const BaseStructure structure = base_structure(s.context(), base.model);
  std::vector<std::string> kinds;
  for (const auto& p : structure.parts) kinds.push_back(s.context().effect(p.candidate).kind());
  BOOST_TEST(kinds == (std::vector<std::string>{"initial_velocity", "quasi_static", "pusher_stop", "pushing_model"}),
             boost::test_tools::per_element());
  // The stop fraction chosen is the setting whose fallback predicts the fit phases best.
  const std::size_t qs = index_of(s.context(), "quasi_static");
  const auto error_at = [&](double setting) {
    std::vector<Selection> with = base.model.terms;
    for (auto p : structure.parts) {
      if (p.candidate == qs) p.setting = setting;
      with.push_back(p);
    }
    ModelCorrection fallback = s.context().correction_of(with, true);
    fallback.pushing_model = false;
    return s.context().fit_phase_error(fallback);
  };
  const Selection* chosen = term(structure.parts, qs);
  BOOST_TEST_REQUIRE(chosen != nullptr);
  const auto settings = s.context().effect(qs).settings();
  BOOST_TEST_REQUIRE(settings.size() > 1u);
  const double best = error_at(chosen->setting);
  for (double setting : settings) BOOST_TEST(best <= error_at(setting), "stop fraction " << setting);
}

BOOST_AUTO_TEST_CASE(an_offset_the_fit_pushes_motion_does_not_show_is_ruled_out_and_the_decision_carries_both_errors) {
  // Clean pushes, and a model that claims a 10 mm mass-centre offset (five times its floor on rect2): the pushing
  // model's centre of friction moved by it predicts the fit pushes' motion worse, so the step rules it out.
  std::mt19937_64 rng(37);
  const Steps s(simulate_all(draw_scenarios(rng, 4, {})));
  const FrictionBase base = friction_base(s.context(), s.paper.model);
  const std::size_t com = index_of(s.context(), "com_offset");
  ModelState claimed = base.model;
  claimed.terms.push_back({com, 0.0, 0, Eigen::Vector2d(0.01, 0.0), Eigen::Vector2d(1e-4, 1e-4), 100.0, {}});
  const BaseStructure structure = base_structure(s.context(), claimed);
  const MotionConfirmation confirmed = motion_confirmation(s.context(), claimed, structure, base.floors);
  BOOST_TEST(term(confirmed.model.terms, com) == nullptr);
  BOOST_TEST(confirmed.contradicted == std::vector<std::size_t>{com}, boost::test_tools::per_element());
  const auto decisions = confirmed.trace.decisions_of(com);
  BOOST_TEST_REQUIRE(!decisions.empty());
  BOOST_TEST((decisions.front().verdict == Verdict::ContradictedByMotion));
  BOOST_TEST(decisions.front().error_with >= decisions.front().error_without);
  // It is not tried again in the search that follows.
  BOOST_TEST(decisions.size() == 1u);
}

BOOST_AUTO_TEST_CASE(held_out_without_findings_the_corrected_model_is_the_base_model) {
  std::mt19937_64 rng(38);
  const Steps s(simulate_all(draw_scenarios(rng, 4, {})));
  const FrictionBase base = friction_base(s.context(), s.paper.model);
  const BaseStructure structure = base_structure(s.context(), base.model);
  const HeldOutErrors e = held_out(s.context(), base.model, structure, s.paper.residual_before);
  BOOST_TEST(e.ablations.empty());
  BOOST_TEST(e.error_after.phases > 0);
  BOOST_TEST(e.error_base.pos_mm_mean == e.error_after.pos_mm_mean);
  BOOST_TEST(e.error_after.pos_mm_mean < e.error_before.pos_mm_mean);
  BOOST_TEST(e.correction.pushing_model);
  BOOST_TEST(e.fit_phase_biases.size() > 0u);
}

BOOST_AUTO_TEST_CASE(the_base_model_is_in_every_corrected_model_and_nothing_is_named_on_clean_pushes) {
  std::mt19937_64 rng(33);
  const DiagnosisResult r = diagnose(simulate_all(draw_scenarios(rng, 4, {})), EffectLibrary::standard(), fast_options());
  log_result(r);
  check_base_model(r);
  BOOST_TEST(effects_found(r).empty(), findings_text(r));
  // Nothing found: the corrected model is the base model.
  BOOST_TEST(r.error_after.pos_mm_mean == r.error_base.pos_mm_mean);
  BOOST_TEST(r.error_after.pos_mm_mean < r.error_before.pos_mm_mean);
}

BOOST_AUTO_TEST_CASE(a_significant_amount_below_its_floor_is_reported_as_negligible_and_not_found) {
  // A 1 mm mass-centre offset on rect2 (floor: 5 % of the 41 mm radius of gyration, 2.1 mm): the torque channel
  // resolves it, but it changes the motion less than the support's own variation.
  std::mt19937_64 rng(34);
  const DiagnosisResult r =
      diagnose(simulate_all(draw_scenarios(rng, 6, {{"com_offset", 0.001}})), EffectLibrary::standard(), fast_options());
  log_result(r);
  const EffectReport& e = report(r, "com_offset");
  BOOST_TEST_MESSAGE("com_offset: significant " << e.passed_test << ", amount " << e.amount << " floor " << e.floor.amount);
  BOOST_TEST(e.passed_test, "a 1 mm offset is resolved by the torque channel");
  BOOST_TEST(e.negligible);
  BOOST_TEST(!e.selected);
  BOOST_TEST(e.amount < e.floor.amount);
  BOOST_TEST(e.floor.amount == 0.05 * std::sqrt(0.001808 / 1.045), boost::test_tools::tolerance(1e-9));
  BOOST_TEST(findings_text(r).find("significant but negligible: com_offset") != std::string::npos, findings_text(r));
  check_base_model(r);
}

BOOST_AUTO_TEST_CASE(a_step_that_fails_is_reported_and_the_diagnosis_goes_on) {
  std::mt19937_64 rng(35);
  const auto pushes = simulate_all(draw_scenarios(rng, 4, {}));
  EffectLibrary library = EffectLibrary::standard();
  library.register_effect(std::make_unique<BrokenEffect>());
  const DiagnosisResult r = diagnose(pushes, library, fast_options());
  BOOST_TEST_REQUIRE(r.step_failures.size() == 1u);
  BOOST_TEST(r.step_failures[0].step == "force_laws");
  BOOST_TEST(r.step_failures[0].what.find("broken: no regressor here") != std::string::npos, r.step_failures[0].what);
  BOOST_TEST(!report(r, "broken").selected);
  BOOST_TEST(std::isfinite(report(r, "broken").score));
  check_base_model(r);  // the later steps ran
  BOOST_TEST(r.error_after.phases > 0);
  // The failed step gave nothing: the pipeline went on with its input, so nothing was found and its search's
  // decisions are not in the report (every candidate it would have tested is as the earlier steps left it).
  BOOST_TEST(effects_found(r).empty(), findings_text(r));
  BOOST_TEST(!report(r, "viscous_friction").passed_test);
  BOOST_TEST(report(r, "viscous_friction").score == 0.0);

  // Without a friction law in the library the friction base cannot be fitted: reported, and the rest goes on.
  EffectLibrary no_law = EffectLibrary::standard();
  no_law.remove("coulomb_friction");
  const DiagnosisResult s = diagnose(pushes, no_law, fast_options());
  BOOST_TEST_REQUIRE(!s.step_failures.empty());
  BOOST_TEST(s.step_failures[0].step == "friction_base");
  BOOST_TEST(s.error_after.phases > 0);
}

BOOST_AUTO_TEST_CASE(blind_trials_name_each_kind_at_twice_its_floor) {
  // One trial per kind whose test resolves it at twice the floor on 6 pushes, drawn by the validation's own
  // randomized physics (object, friction, stiffness, pressure, speeds). Seeds 7000+ are not the tuning range.
  for (const auto& [kind, index] : std::vector<std::pair<std::string, int>>{
           {"time_offset", 1}, {"force_offset", 2}, {"com_offset", 5}, {"inertia_mismatch", 6}}) {
    const Trial t = run_trial(kind, index, 2.0);
    BOOST_TEST(t.trial.true_named, kind << " should be named: " << findings_text(t.result));
    check_base_model(t.result);
    BOOST_TEST(t.result.error_after.pos_mm_mean < t.result.error_before.pos_mm_mean, kind);
  }
}

BOOST_AUTO_TEST_CASE(a_mass_factor_whose_first_fit_leaves_the_plausible_range_is_found_by_its_re_fit) {
  // A blind trial of the tuning seeds 70000 (validation defaults): ellip2 four times heavier than its nominal mass.
  // The first, linearised fit says 5.5, outside the plausible 0.2-5 (before the re-fit from inside the range it
  // was refused as "not this effect"); the re-fit, with the observer re-run at the applied mass, settles near 4.
  ValidationOptions o;
  o.seed = 70000;
  o.draw_preloads = o.draw_sensor_offsets = false;  // drawn without preloads or sensor offsets
  ValidationTrial v;
  const auto scenarios = draw_validation_trial(o, 0, "inertia_mismatch", v);
  BOOST_TEST_REQUIRE(v.amount == 4.0, boost::test_tools::tolerance(1e-9));  // the mass's cap: the case this is about
  const DiagnosisResult r = diagnose(simulate_trial(scenarios), EffectLibrary::standard(), o.diagnosis);
  score_trial(r, v);
  BOOST_TEST(v.true_named, "the mass factor should be found: " << findings_text(r));
  BOOST_TEST(v.fitted_amount == 4.0, boost::test_tools::tolerance(0.15));
  const bool started_inside = std::any_of(r.log.begin(), r.log.end(), [](const std::string& line) {
    return line.find("inertia_mismatch: first fit outside the physical range") != std::string::npos;
  });
  BOOST_TEST(started_inside, "the first fit should have left the range, or this test no longer tests the re-fit");
}

BOOST_AUTO_TEST_CASE(a_lag_the_pushes_share_is_found_when_one_pushs_own_search_settles_elsewhere) {
  // A blind trial of the tuning seeds 110000 (validation defaults, 7 pushes of ellip2, a 24.9 ms lag). The long slow
  // push's own search settles about 50 ms above the lag the other pushes agree on to a millisecond; with the
  // pushes' plain spread the shared lag (score 2353) was vetoed and nothing was named. The spread is robust now.
  ValidationOptions o;
  o.seed = 110000;
  o.draw_preloads = o.draw_sensor_offsets = false;  // drawn without preloads or sensor offsets
  ValidationTrial v;
  const auto scenarios = draw_validation_trial(o, 4, "time_offset", v);
  const auto pushes = simulate_trial(scenarios);
  const auto lag = EffectLibrary::standard().find("time_offset");
  double farthest_s = 0;
  for (const auto& push : pushes) {
    const DirectFit own = lag->fit_directly({prepare_diagnosis_push(push, 0.0, push.duration_s())});
    farthest_s = std::max(farthest_s, std::abs(own.theta(0) - v.amount));
  }
  BOOST_TEST(farthest_s > 0.03, "no push's own search settles elsewhere: this test no longer tests the robust spread");
  const DiagnosisResult r = diagnose(pushes, EffectLibrary::standard(), o.diagnosis);
  score_trial(r, v);
  BOOST_TEST(v.true_named, "the lag should be found: " << findings_text(r));
  BOOST_TEST(v.fitted_amount == v.amount, boost::test_tools::tolerance(0.1));
}

BOOST_AUTO_TEST_CASE(a_mass_centre_offset_the_fit_pushes_motion_contradicts_is_not_found) {
  // A blind clean trial of the tuning seeds 171000 (validation defaults, rect1, 4 pushes): the torque residual fits a
  // 10.9 mm offset, significant and several floors above the floor even by one standard error, but moving the
  // pushing model's centre of friction by it predicts the fit pushes' motion worse (held out: 0.27 -> 0.48 mm).
  const auto [v, r] = blind_trial(171000, 50, "none");
  const EffectReport* com = &report(r, "com_offset");
  BOOST_TEST(com->passed_test, "the offset should pass its test, or this no longer tests the motion: " << com->note);
  BOOST_TEST(com->amount - com->amount_std > com->floor.amount, "it should clear its floor by the margin: " << com->note);
  BOOST_TEST(com->contradicted_by_motion, com->note);
  BOOST_TEST(!com->selected);
  BOOST_TEST(v.true_named, "nothing should be named: " << findings_text(r));
  BOOST_TEST(findings_text(r).find("contradicted by the fit pushes' motion: com_offset") != std::string::npos,
             findings_text(r));
  // The friction laws are then searched again without it, and it is not tried again.
  const auto contradicted = std::find_if(r.log.begin(), r.log.end(), [](const std::string& line) {
    return line.find("com_offset: contradicted by the fit pushes' motion") != std::string::npos;
  });
  BOOST_TEST_REQUIRE((contradicted != r.log.end()));
  const auto searched = std::find_if(contradicted, r.log.end(), [](const std::string& line) {
    return line.find("greedy (against the friction law)") != std::string::npos;
  });
  BOOST_TEST((searched != r.log.end()), "no search after the contradiction");
  BOOST_TEST(std::none_of(contradicted, r.log.end(), [](const std::string& line) {
    return line.find("com_offset joins") != std::string::npos;
  }));
}

BOOST_AUTO_TEST_CASE(a_true_mass_centre_offset_is_confirmed_by_the_motion) {
  // A blind trial of the tuning seeds 150000 (validation defaults): of the true offsets there, the one whose fit
  // pushes' prediction it improves least (normalised error 0.86 of the model's without it). Still found.
  const auto [v, r] = blind_trial(150000, 94, "com_offset");
  BOOST_TEST(v.true_named, "the offset should be found: " << findings_text(r));
  const bool confirmed = std::any_of(r.log.begin(), r.log.end(), [](const std::string& line) {
    return line.find("com_offset: confirmed by the fit pushes' motion") != std::string::npos;
  });
  BOOST_TEST(confirmed);
}

/// The motion confirmation's decision about com_offset in `r`'s log.
std::string motion_decision(const DiagnosisResult& r) {
  const auto it = std::find_if(r.log.begin(), r.log.end(), [](const std::string& line) {
    return line.find("com_offset: c") != std::string::npos &&
           line.find("by the fit pushes' motion") != std::string::npos;
  });
  return it == r.log.end() ? std::string() : *it;
}

BOOST_AUTO_TEST_CASE(a_true_offset_is_confirmed_by_the_fit_pushes_motion) {
  // A blind trial of the tuning seeds 359400 (validation defaults, ellip2, a 7.1 mm offset, 4 fit pushes).
  const auto [v, r] = blind_trial(359400, 30, "com_offset", true);
  BOOST_TEST(v.true_named, "the offset should be found: " << findings_text(r));
  const std::string decision = motion_decision(r);
  BOOST_TEST(decision.find("confirmed") != std::string::npos, decision);
  BOOST_TEST(decision.find("better on 3 of 4 fit pushes") != std::string::npos, decision);
}

BOOST_AUTO_TEST_CASE(a_true_offset_that_predicts_some_fit_pushes_worse_is_found) {
  // A trial of the tuning seeds 378000 (`validate-diagnosis --kinds com_offset --seed 378000`: validation defaults,
  // ellip1, a mass centre 7.4 mm off along body x, 4 fit pushes): the fitted offset lowers the fit phases' mean
  // error by more than a third, while it predicts two of the four fit pushes worse (the pushing model's
  // stick/slide switch and its identification on each push's early phases; the true offset put in does the same to
  // one of them). The mean decides: found.
  const auto [v, r] = blind_trial(378000, 11, "com_offset", true);
  BOOST_TEST(v.floor_multiple >= 2);
  const std::string decision = motion_decision(r);
  BOOST_TEST(decision.find("better on 2 of 4 fit pushes") != std::string::npos, decision);
  BOOST_TEST(decision.find("confirmed") != std::string::npos, decision);
  BOOST_TEST(v.true_named, "the offset should be found: " << findings_text(r));
  const EffectReport& com = report(r, "com_offset");
  BOOST_TEST(std::abs(com.theta(0) - v.amount) < 0.25 * std::abs(v.amount),
             "delta_x " << com.theta(0) << " m against the simulated " << v.amount << " m");
}

BOOST_AUTO_TEST_CASE(even_the_true_offset_need_not_predict_every_fit_push_better) {
  // Why the motion confirmation asks only for the fit pushes' mean error: a trial of the tuning seeds 377000
  // (`validate-diagnosis --kinds com_offset --seed 377000`: validation defaults, rect2, the mass centre 5.5 mm along
  // body x, 4 fit pushes). With the true offset itself in the base model (no fitted one), the pushing model predicts
  // three of the four fit pushes worse than without it, and their mean too: its stick/slide switch and its
  // identification on each push's early phases make single pushes' predictions jump with the centre of friction.
  ValidationOptions o;
  o.seed = 377000;
  o.kinds = {"com_offset"};
  ValidationTrial v;
  const std::vector<PushScenario> scenarios = draw_validation_trial(o, 22, "com_offset", v);
  BOOST_TEST_REQUIRE(v.floor_multiple >= 2);
  const Steps s(simulate_trial(scenarios), o.diagnosis);
  const FrictionBase base = friction_base(s.context(), s.paper.model);
  const std::size_t com = index_of(s.context(), "com_offset");
  ModelState truth = base.model;
  truth.terms.push_back({com, 0.0, 0, Eigen::Vector2d(v.amount, 0.0), Eigen::Vector2d(1e-4, 1e-4), 100.0, {}});
  const BaseStructure structure = base_structure(s.context(), truth);
  std::vector<Selection> with = truth.terms;
  with.insert(with.end(), structure.parts.begin(), structure.parts.end());
  std::vector<Selection> without = base.model.terms;
  without.insert(without.end(), structure.parts.begin(), structure.parts.end());
  const auto errors_with = s.context().fit_phase_errors(s.context().correction_of(with, true));
  const auto errors_without = s.context().fit_phase_errors(s.context().correction_of(without, true));
  BOOST_TEST_REQUIRE(errors_with.per_push.size() == errors_without.per_push.size());
  int worse = 0;
  for (std::size_t p = 0; p < errors_with.per_push.size(); ++p) {
    BOOST_TEST_MESSAGE("fit push " << p << ": normalised error " << errors_with.per_push[p] << " with the true offset, "
                                   << errors_without.per_push[p] << " without");
    worse += errors_with.per_push[p] > errors_without.per_push[p];
  }
  BOOST_TEST_MESSAGE("mean " << errors_with.mean << " with, " << errors_without.mean << " without");
  BOOST_TEST(worse >= 1, "the true offset predicts every fit push better here");
}

BOOST_AUTO_TEST_CASE(an_offset_that_takes_up_a_hidden_bias_and_barely_moves_the_prediction_is_not_found) {
  // A trial of the tuning seeds 373200 (validation defaults, rect2, a force bias of 4.6 floors outside the catalogue,
  // 3 fit pushes): a 4.2 mm mass-centre offset takes up part of the bias's torque, passes its test and clears its
  // floor, and predicts two of the three fit pushes better, but their mean error by about 3 % only. A true offset
  // moves the pushing model's centre of friction and with it how every push turns: one that changes the prediction
  // by less than kMotionConfirmationGain is not found.
  const DiagnosisResult r = hidden_trial(373200, 18, "force_offset");
  const EffectReport& com = report(r, "com_offset");
  BOOST_TEST(com.passed_test, "the offset should pass its test, or this no longer tests the motion: " << com.note);
  BOOST_TEST(com.amount - com.amount_std > com.floor.amount, "it should clear its floor by the margin: " << com.note);
  const std::string decision = motion_decision(r);
  BOOST_TEST(decision.find("better on 2 of 3 fit pushes") != std::string::npos, decision);
  BOOST_TEST(com.contradicted_by_motion, com.note);
  BOOST_TEST(!com.selected);
  for (const auto& e : r.effects) BOOST_TEST((e.structural || !e.selected), e.kind << ": " << findings_text(r));
}

BOOST_AUTO_TEST_CASE(a_bias_is_read_from_the_held_out_pushes_rests_when_the_fit_pushes_start_pressed) {
  // A blind trial of the tuning seeds 359400 (validation defaults, rect3, a bias of -0.66 N on each axis, 4 fit and 4
  // held-out pushes): of the fit pushes only one rests clear of the object, which cannot tell a shared bias from its
  // own zero; the held-out pushes' rests, part of no prediction phase, add the second.
  const auto [v, r] = blind_trial(359400, 18, "force_offset", true);
  const EffectReport& bias = report(r, "force_offset");
  BOOST_TEST(bias.selected, bias.note);
  BOOST_TEST(v.true_named, findings_text(r));
  const double truth_N = std::abs(v.amount) * std::sqrt(2.0);  // the drawn amount is each axis's
  BOOST_TEST(bias.amount == truth_N, boost::test_tools::tolerance(0.25));
}

BOOST_AUTO_TEST_CASE(friction_laws_that_stand_in_for_a_tilted_support_are_not_found) {
  // A trial of the tuning seeds 359200 (validation defaults but sensor zeros of 0.10 N per axis, a tilted support
  // outside the catalogue, 4 fit pushes):
  // Stribeck friction and drag take up part of the tilt's constant force (scores 26 and 19, above their floors), but
  // the residual stays unexplained, and beside that residual's leading signature (a constant force in the world
  // frame, which is what a tilt is) neither passes its test any longer.
  const DiagnosisResult r = hidden_trial(359200, 15, "support_tilt", 0.1);
  for (const char* kind : {"stribeck_friction", "viscous_friction"}) {
    const EffectReport& law = report(r, kind);
    BOOST_TEST(law.passed_test, kind << " should pass its own test, or this no longer tests the stand-in: " << law.note);
    BOOST_TEST(law.stands_in_for_unexplained, law.note);
    BOOST_TEST(!law.selected);
    BOOST_TEST(law.note.find("world_force") != std::string::npos, law.note);
  }
  BOOST_TEST(!r.adequacy.explained, findings_text(r));
  for (const auto& e : r.effects) BOOST_TEST((e.structural || !e.selected), e.kind << ": " << findings_text(r));
  BOOST_TEST(findings_text(r).find("standing in for the unexplained residual") != std::string::npos, findings_text(r));
}

BOOST_AUTO_TEST_CASE(the_held_out_pushes_force_shows_a_hidden_delay_that_two_fit_pushes_leave_unseen) {
  // A trial of the tuning seeds 362200 (validation defaults, ellip1, four pushes: two fit, two held out), a force delay
  // of 4.8 floors outside the catalogue. On the two fit pushes alone the force part called the residual explained;
  // with the held-out pushes' force beside theirs (nothing a prediction uses is fitted on them) it is unexplained.
  const DiagnosisResult r = hidden_trial(362200, 1, "time_offset");
  BOOST_TEST(r.fit_sources.size() == 2u);
  BOOST_TEST(r.adequacy.force_pushes == 4);
  BOOST_TEST(r.adequacy.force_unexplained, findings_text(r));
  BOOST_TEST(!r.adequacy.explained, findings_text(r));
  for (const auto& e : r.effects) BOOST_TEST((e.structural || !e.selected), e.kind << ": " << findings_text(r));
}

BOOST_AUTO_TEST_CASE(a_drag_outside_the_catalogue_is_not_read_as_a_delay) {
  // A trial of the tuning seeds 362200 (validation defaults, rect2, four pushes), a drag of 3.1 floors hidden from the
  // catalogue: the delay's search against Coulomb friction alone found a lag in it (a force read late looks like a
  // drag where the push speeds up and slows down); with a drag fitted beside mu as a nuisance it finds none, and the
  // drag shows as an unexplained residual.
  const DiagnosisResult r = hidden_trial(362200, 3, "viscous_friction");
  BOOST_TEST(!report(r, "time_offset").selected, findings_text(r));
  BOOST_TEST(!r.adequacy.explained, findings_text(r));
  for (const auto& e : r.effects) BOOST_TEST((e.structural || !e.selected), e.kind << ": " << findings_text(r));
}

BOOST_AUTO_TEST_CASE(a_delay_that_stands_in_for_a_hidden_drag_is_not_found) {
  // A trial of the tuning seeds 376400 (validation defaults, ellip2, a drag of 3.7 floors hidden from the catalogue):
  // the delay's search finds a lag of 22 ms (score 26) and the drag beside mu does not veto it, but the corrected
  // model leaves the fit pushes' force residual unexplained, led by the speed signature; scored beside that
  // signature the lag makes the residual worse, so it stands in for the residual and is not found.
  const DiagnosisResult r = hidden_trial(376400, 2, "viscous_friction");
  const EffectReport& delay = report(r, "time_offset");
  BOOST_TEST(delay.stands_in_for_unexplained, findings_text(r));
  BOOST_TEST(!delay.selected, findings_text(r));
  BOOST_TEST(delay.note.find("speed") != std::string::npos, delay.note);
  BOOST_TEST(!r.adequacy.explained, findings_text(r));
  for (const auto& e : r.effects) BOOST_TEST((e.structural || !e.selected), e.kind << ": " << findings_text(r));
}

BOOST_AUTO_TEST_CASE(a_friction_law_that_takes_up_a_hidden_bias_is_not_found) {
  // A trial of the tuning seeds 376400 (validation defaults, hex, a sensor bias of 4 floors hidden from the catalogue):
  // Stribeck friction joins (score 33) and the fit pushes' force residual is explained with it, but the clear rests of
  // three pushes share a force of 0.49 N that no found effect takes out; with that force taken out of the data as a
  // sensor bias, Stribeck friction no longer passes its test: it took up part of the bias during the push.
  const DiagnosisResult r = hidden_trial(376400, 3, "force_offset");
  const EffectReport& law = report(r, "stribeck_friction");
  BOOST_TEST(law.passed_test,
             "Stribeck friction should pass its own test, or this no longer tests the check: " << law.note);
  BOOST_TEST(law.stands_in_for_unexplained, law.note);
  BOOST_TEST(!law.selected);
  BOOST_TEST(law.note.find("clear rests") != std::string::npos, law.note);
  BOOST_TEST(r.adequacy.rest_unexplained, findings_text(r));
  for (const auto& e : r.effects) BOOST_TEST((e.structural || !e.selected), e.kind << ": " << findings_text(r));
}

BOOST_AUTO_TEST_CASE(a_drag_that_would_turn_the_support_friction_torque_negative_is_not_found) {
  // A blind Stribeck trial of seeds 180000 (rect1, 4 pushes). A drag of 15.6 1/s fits the sliding data jointly with
  // mu 0.14 and a torque excess of -0.46: the support's friction torque would drive the rotation, and the corrected
  // model, once the push ended, spun the object where drag and torque balance (held-out yaw 13.4 deg, the base
  // model's 0.39).
  const DiagnosisResult r = blind_trial(180000, 132, "stribeck_friction").result;
  const EffectReport* drag = &report(r, "viscous_friction");
  BOOST_TEST(!drag->selected, findings_text(r));
  BOOST_TEST(drag->note.find("would drive the rotation") != std::string::npos, drag->note);
  BOOST_TEST(r.error_after.theta_deg_mean < 1.0);
}

BOOST_AUTO_TEST_CASE(the_base_model_leaves_out_a_friction_torque_that_would_drive_the_rotation) {
  // A blind mass-centre trial of seeds 180000. The base model's friction torque, fitted beside mu on the sliding
  // samples, came out at mu + torque_excess = -0.44: with it the corrected model's held-out yaw error was 0.40 deg
  // (0.17 without it), the same check as the greedy search's, applied where the base model is fitted.
  const DiagnosisResult r = blind_trial(180000, 30, "com_offset").result;
  const EffectReport* torque = &report(r, "friction_torque");
  BOOST_TEST(!torque->selected, findings_text(r));
  BOOST_TEST(torque->note.find("would drive the rotation") != std::string::npos, torque->note);
  BOOST_TEST(r.error_after.theta_deg_mean < 0.3);
}

BOOST_AUTO_TEST_CASE(fewer_pushes_than_the_validation_used_are_flagged) {
  // The blind validation draws 4 to 8 pushes; a diagnosis of fewer says so in the result, its JSON and its report.
  for (int pushes : {2, 4}) {
    ValidationOptions o;
    o.seed = 7000;
    o.min_pushes = o.max_pushes = pushes;
    o.diagnosis = fast_options();
    ValidationTrial v;
    const DiagnosisResult r =
        diagnose(simulate_trial(draw_validation_trial(o, 0, "none", v)), EffectLibrary::standard(), o.diagnosis);
    const std::string report = diagnosis_markdown(r, o.diagnosis, {}, "");
    if (pushes < 4) {
      BOOST_TEST(r.caution.find("only 2 pushes") != std::string::npos, r.caution);
      BOOST_TEST(diagnosis_json(r, o.diagnosis).at("caution").get<std::string>() == r.caution);
      BOOST_TEST(report.find("> Caution: only 2 pushes") != std::string::npos);
    } else {
      BOOST_TEST(r.caution.empty(), r.caution);
      BOOST_TEST(report.find("Caution") == std::string::npos);
    }
  }
}

BOOST_AUTO_TEST_CASE(blind_clean_trials_name_nothing) {
  for (int index : {0, 8, 16}) {
    const Trial t = run_trial("none", index, 2.0);
    BOOST_TEST(t.trial.true_named, "nothing should be named: " << findings_text(t.result));
  }
}

BOOST_AUTO_TEST_SUITE_END()
